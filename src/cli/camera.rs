//! The camera flags shared by the tools (`#[command(flatten)]`): a camera file, or
//! either model of [`crate::camera`] spelled as flags. The flags build a
//! [`CameraSpec`] directly and [`Camera::from_spec`] checks it, so they are
//! checked exactly as a camera file is; only the error names the flag
//! (`--lookat`) where the file's error names the JSON field (`lookat.center`).

use glam::DVec3;

use crate::camera::{
    Aspect, Camera, CameraError, CameraSpec, IrisProjection, IrisSpec, LookAt, ObliqueKind, Ortho,
    Ortho2, Perspective, ViewProjection, ViewSpec, Window,
};
use crate::cli::usage_bail;

/// Where flag errors come from, in place of a file name.
const ORIGIN: &str = "camera flags";

/// The command-line flag that sets a JSON field (for error messages).
fn flag_of(field: &str) -> Option<&'static str> {
    let top = field.split('.').take(2).collect::<Vec<_>>();
    Some(match top.as_slice() {
        ["lookat", "eye" | "center"] | ["lookat"] => "--lookat",
        ["lookat", "up"] => "--up",
        ["lookat", "twist"] => "--twist",
        ["perspective", ..] => "--perspective",
        ["ortho", ..] => "--ortho",
        ["ortho2", ..] => "--ortho2",
        ["view", "vrp"] => "--vrp",
        ["view", "vpn"] => "--vpn",
        ["view", "view_up"] => "--view-up",
        ["view", "view_distance"] => "--view-distance",
        ["view", "window"] => "--window",
        ["view", "cop"] => "--cop",
        ["view", "dop"] => "--dop",
        ["view", "oblique" | "isometric"] => "--oblique",
        ["view", "front"] => "--front",
        ["view", "back"] => "--back",
        _ => return None,
    })
}

/// Parses `N` comma-separated finite numbers (`"0,100,-5"`).
/// `--perspective FOVY,ASPECT,NEAR,FAR`, ASPECT a number or `auto`.
fn parse_perspective(text: &str) -> std::result::Result<Perspective, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if let [fovy, "auto", near, far] = parts[..] {
        let [fovy, near, far] = parse_list::<3>(&[fovy, near, far].join(","))?;
        return Ok(Perspective {
            fovy,
            aspect: Aspect::Auto,
            near,
            far,
        });
    }
    let [fovy, aspect, near, far] = parse_list::<4>(text)?;
    Ok(Perspective {
        fovy,
        aspect: Aspect::Ratio(aspect),
        near,
        far,
    })
}

fn parse_list<const N: usize>(text: &str) -> std::result::Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers, found {}",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(&parts) {
        let x: f64 = part
            .parse()
            .map_err(|_| format!("{part:?} is not a number"))?;
        if !x.is_finite() {
            return Err(format!("{part} is not a finite number"));
        }
        *slot = x;
    }
    Ok(out)
}

/// Parses one finite number.
fn parse_finite(text: &str) -> std::result::Result<f64, String> {
    parse_list::<1>(text).map(|[x]| x)
}

/// The camera flags shared by the tools (`#[command(flatten)]`): a camera file, or
/// either model spelled as flags. See the module docs for the meaning of each value.
#[derive(clap::Args, Clone, Debug, Default, PartialEq)]
pub struct CameraArgs {
    /// Camera JSON file (`-` = standard input); excludes every other camera flag.
    /// Default: none (the tool's default view).
    #[arg(long, value_name = "FILE", help_heading = "Camera")]
    pub camera: Option<String>,

    /// IRIS/GLU lookat: eye and center points. Default: none (identity view, eye at
    /// the origin looking down -z).
    #[arg(long, value_name = "EX,EY,EZ,CX,CY,CZ", value_parser = parse_list::<6>, allow_hyphen_values = true, help_heading = "Camera")]
    pub lookat: Option<[f64; 6]>,

    /// Up direction for --lookat. Default: 0,1,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera")]
    pub up: Option<[f64; 3]>,

    /// IRIS lookat twist in degrees (right-hand rotation of the camera about its line
    /// of sight). Default: 0.
    #[arg(long, value_name = "DEG", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera")]
    pub twist: Option<f64>,

    /// gluPerspective: vertical field of view in degrees, aspect (width/height,
    /// or `auto` for the image's own), near and far distances (near may be 0).
    /// Default: none.
    #[arg(long, value_name = "FOVY,ASPECT,NEAR,FAR", value_parser = parse_perspective, allow_hyphen_values = true, help_heading = "Camera")]
    pub perspective: Option<Perspective>,

    /// glOrtho: left, right, bottom, top, near, far in eye coordinates. Default: none.
    #[arg(long, value_name = "L,R,B,T,N,F", value_parser = parse_list::<6>, allow_hyphen_values = true, help_heading = "Camera")]
    pub ortho: Option<[f64; 6]>,

    /// IRIS ortho2 (gluOrtho2D): left, right, bottom, top; near -1, far 1. Default: none.
    #[arg(long, value_name = "L,R,B,T", value_parser = parse_list::<4>, allow_hyphen_values = true, help_heading = "Camera")]
    pub ortho2: Option<[f64; 4]>,

    /// Textbook view reference point (world). Default: 0,0,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub vrp: Option<[f64; 3]>,

    /// View plane normal: the direction the camera looks. Default: 0,0,-1
    /// (-1,-1,-1 with --oblique isometric).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub vpn: Option<[f64; 3]>,

    /// View-up direction (world), shown vertical on the image. Default: 0,1,0.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub view_up: Option<[f64; 3]>,

    /// Distance from the VRP to the view plane along the VPN. Default: 0.
    #[arg(long, value_name = "D", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub view_distance: Option<f64>,

    /// Window on the view plane (view plane coordinates, centred on the VPN line
    /// through the VRP); it fills the image. Default: none (required).
    #[arg(long, value_name = "UMIN,UMAX,VMIN,VMAX", value_parser = parse_list::<4>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub window: Option<[f64; 4]>,

    /// Perspective: centre of projection (world coordinates, on the viewer's side of
    /// the view plane). Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub cop: Option<[f64; 3]>,

    /// Parallel: direction of projection (world; oblique when not along the VPN).
    /// Default: none.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_list::<3>, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub dop: Option<[f64; 3]>,

    /// Parallel: cavalier or cabinet oblique projection with the receding axis at
    /// ANGLE degrees (default 45), or isometric (no angle). Default: none.
    #[arg(long, value_name = "cavalier|cabinet|isometric[,ANGLE]", value_parser = parse_oblique, help_heading = "Camera (textbook view system)")]
    pub oblique: Option<Oblique>,

    /// Front clipping plane: distance from the VRP along the VPN. Default: none
    /// (required).
    #[arg(long, value_name = "F", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub front: Option<f64>,

    /// Back clipping plane: distance from the VRP along the VPN. Default: none
    /// (required).
    #[arg(long, value_name = "B", value_parser = parse_finite, allow_hyphen_values = true, help_heading = "Camera (textbook view system)")]
    pub back: Option<f64>,
}

/// `--oblique`: one of the textbook's special parallel projections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Oblique {
    /// Receding axis at the angle (degrees), full length.
    Cavalier(Option<f64>),
    /// Receding axis at the angle (degrees), half length.
    Cabinet(Option<f64>),
    /// Projection along a VPN with equal-magnitude components.
    Isometric,
}

fn parse_oblique(text: &str) -> std::result::Result<Oblique, String> {
    let (kind, angle) = match text.split_once(',') {
        Some((k, a)) => (k.trim(), Some(parse_finite(a)?)),
        None => (text.trim(), None),
    };
    match (kind, angle) {
        ("cavalier", a) => Ok(Oblique::Cavalier(a)),
        ("cabinet", a) => Ok(Oblique::Cabinet(a)),
        ("isometric", None) => Ok(Oblique::Isometric),
        ("isometric", Some(_)) => Err("isometric takes no angle".into()),
        (other, _) => Err(format!(
            "{other:?}: expected cavalier, cabinet or isometric"
        )),
    }
}

impl CameraArgs {
    /// The camera the flags describe; None when no camera flag was given (the
    /// caller picks its default). Contradictory or degenerate flags are usage
    /// errors (exit status 2) naming the flag; a bad --camera file is a failure.
    pub fn resolve(&self) -> anyhow::Result<Option<Camera>> {
        if let Some(path) = &self.camera {
            if self.any_model_flag() {
                usage_bail!("--camera cannot be combined with other camera flags");
            }
            return Ok(Some(Camera::load(path)?));
        }
        if self.lookat.is_none() && (self.up.is_some() || self.twist.is_some()) {
            usage_bail!("--up and --twist need --lookat EX,EY,EZ,CX,CY,CZ");
        }
        let spec = match self.spec() {
            Ok(Some(spec)) => spec,
            Ok(None) => return Ok(None),
            Err(e) => return Err(usage_error(e)),
        };
        Camera::from_spec(&spec).map(Some).map_err(usage_error)
    }

    /// Whether any flag other than --camera was given.
    fn any_model_flag(&self) -> bool {
        *self
            != CameraArgs {
                camera: self.camera.clone(),
                ..CameraArgs::default()
            }
    }

    /// The specification the flags give (None when no camera flag was given). The
    /// IRIS flags and the view flags cannot both be given: a `CameraSpec` holds
    /// one model ([`CameraSpec::from_parts`]). `resolve` has already refused
    /// --up and --twist without --lookat.
    fn spec(&self) -> Result<Option<CameraSpec>, CameraError> {
        let mut projection = Vec::new();
        if let Some(p) = self.perspective {
            projection.push(IrisProjection::Perspective(p));
        }
        if let Some([left, right, bottom, top, near, far]) = self.ortho {
            projection.push(IrisProjection::Ortho(Ortho {
                left,
                right,
                bottom,
                top,
                near,
                far,
            }));
        }
        if let Some([left, right, bottom, top]) = self.ortho2 {
            projection.push(IrisProjection::Ortho2(Ortho2 {
                left,
                right,
                bottom,
                top,
            }));
        }
        let iris = IrisSpec {
            lookat: self.lookat.map(|l| LookAt {
                eye: DVec3::new(l[0], l[1], l[2]),
                center: DVec3::new(l[3], l[4], l[5]),
                up: self.up.map(DVec3::from_array),
                twist: self.twist,
            }),
            projection,
        };

        let mut projection = Vec::new();
        if let Some(cop) = self.cop {
            projection.push(ViewProjection::Cop(DVec3::from_array(cop)));
        }
        if let Some(dop) = self.dop {
            projection.push(ViewProjection::Dop(DVec3::from_array(dop)));
        }
        match self.oblique {
            Some(Oblique::Cavalier(angle)) => projection.push(ViewProjection::Oblique {
                kind: ObliqueKind::Cavalier,
                angle,
            }),
            Some(Oblique::Cabinet(angle)) => projection.push(ViewProjection::Oblique {
                kind: ObliqueKind::Cabinet,
                angle,
            }),
            Some(Oblique::Isometric) => projection.push(ViewProjection::Isometric),
            None => {}
        }
        let view = ViewSpec {
            vrp: self.vrp.map(DVec3::from_array),
            vpn: self.vpn.map(DVec3::from_array),
            view_up: self.view_up.map(DVec3::from_array),
            view_distance: self.view_distance,
            window: self.window.map(Window::from_array),
            projection,
            front: self.front,
            back: self.back,
        };

        CameraSpec::from_parts(iris, view)
    }
}

/// A camera error as a usage error naming the flag (`camera flags: --lookat:
/// ...`), or the JSON field when no flag sets it alone (`camera flags: view: no
/// projection ...`).
fn usage_error(e: CameraError) -> anyhow::Error {
    let text = match e {
        CameraError::Invalid { field, message, .. } => {
            let name = flag_of(&field).unwrap_or(&field);
            format!("{ORIGIN}: {name}: {message}")
        }
        other => other.to_string(),
    };
    anyhow::Error::new(crate::cli::UsageError(text))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::test_support::*;
    use serde_json::json;

    #[test]
    fn flags_resolve_like_json() {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            camera: CameraArgs,
        }
        let parse = |args: &[&str]| {
            Cli::try_parse_from(std::iter::once("t").chain(args.iter().copied())).map(|c| c.camera)
        };
        <Cli as clap::CommandFactory>::command().debug_assert();
        assert_eq!(parse(&[]).unwrap().resolve().unwrap(), None);
        let e = parse(&["--up", "0,0,1", "--ortho2", "0,1,0,1"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(format!("{e}").contains("need --lookat"), "{e}");
        let flags = parse(&[
            "--lookat",
            "0,100,-5,0,0,-900",
            "--twist",
            "0",
            "--perspective",
            "55,1,0,1000",
        ])
        .unwrap();
        assert_eq!(flags.resolve().unwrap(), Some(cam(demo2())));
        let e = parse(&["--perspective", "55,1,-1,1000"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(e.downcast_ref::<crate::cli::UsageError>().is_some());
        let msg = format!("{e:#}");
        assert!(
            msg.contains("--perspective") && msg.contains("negative"),
            "{msg}"
        );
        assert!(parse(&["--perspective", "NaN,1,0,1"]).is_err());
        assert!(parse(&["--perspective", "inf,1,0,1"]).is_err());
        assert!(parse(&["--ortho2", "0,1,0"]).is_err());
        let e = parse(&["--camera", "x.json", "--ortho2", "0,1,0,1"])
            .unwrap()
            .resolve()
            .unwrap_err();
        assert!(e.downcast_ref::<crate::cli::UsageError>().is_some());
    }

    #[test]
    fn textbook_flags() {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            camera: CameraArgs,
        }
        let parse = |args: &[&str]| {
            Cli::try_parse_from(std::iter::once("t").chain(args.iter().copied())).map(|c| c.camera)
        };
        let flags = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--oblique",
            "cabinet,30",
        ])
        .unwrap();
        let json = cam(view(json!({"oblique": {"kind": "cabinet", "angle": 30}})));
        assert_eq!(flags.resolve().unwrap(), Some(json));
        let flags = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--oblique",
            "isometric",
            "--vrp",
            "1,1,1",
        ])
        .unwrap();
        assert!(flags.resolve().unwrap().is_some());
        assert!(parse(&["--oblique", "isometric,30"]).is_err());
        assert!(parse(&["--oblique", "cabinett"]).is_err());
        let e = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--vpn",
            "0,0,0",
            "--dop",
            "0,0,1",
        ])
        .unwrap()
        .resolve()
        .unwrap_err();
        let msg = format!("{e:#}");
        assert!(
            msg.contains("--vpn") && msg.contains("INVALID VIEW PLANE NORMAL"),
            "{msg}"
        );
        let e = parse(&[
            "--window",
            "-1,1,-1,1",
            "--front",
            "-10",
            "--back",
            "10",
            "--dop",
            "0,0,1",
            "--ortho2",
            "0,1,0,1",
        ])
        .unwrap()
        .resolve()
        .unwrap_err();
        assert!(format!("{e:#}").contains("--ortho2"), "{e:#}");
    }

    /// Parses camera flags as a tool would.
    fn flags(args: &str) -> CameraArgs {
        use clap::Parser;
        #[derive(Parser)]
        struct Cli {
            #[command(flatten)]
            camera: CameraArgs,
        }
        let args = std::iter::once("t").chain(args.split_whitespace());
        Cli::try_parse_from(args).unwrap().camera
    }

    /// The same cameras as flags and as JSON: the same camera, to the bit.
    #[test]
    fn flags_and_json_give_identical_cameras() {
        let window = "--window -1,1,-1,1 --front -10 --back 10";
        let cases = [
            (
                "--lookat 0,100,-5,0,0,-900 --twist 0 --perspective 55,1,0,1000".to_string(),
                demo2(),
            ),
            (
                "--lookat 1,2,3,4,-1,-5 --up 0.2,1,0.1 --twist 12.5 --ortho -3,2,-1,4,-2,30".into(),
                json!({"lookat": {"eye": [1, 2, 3], "center": [4, -1, -5], "up": [0.2, 1, 0.1],
                                  "twist": 12.5},
                       "ortho": {"left": -3, "right": 2, "bottom": -1, "top": 4, "near": -2, "far": 30}}),
            ),
            (
                "--ortho2 0,1023,0,767".into(),
                json!({"ortho2": [0, 1023, 0, 767]}),
            ),
            (
                "--perspective 50,1.5,0.5,40".into(),
                json!({"perspective": {"fovy": 50, "aspect": 1.5, "near": 0.5, "far": 40}}),
            ),
            (
                "--vrp 1,2,3 --vpn 3,-3,-8 --view-up 0.2,1,0.1 --view-distance 1 \
                 --window -1.5,1.5,-1,1 --cop 1,2,3 --front 0.5 --back 40"
                    .into(),
                json!({"view": {"vrp": [1, 2, 3], "vpn": [3, -3, -8], "view_up": [0.2, 1, 0.1],
                                "view_distance": 1, "window": [-1.5, 1.5, -1, 1], "cop": [1, 2, 3],
                                "front": 0.5, "back": 40}}),
            ),
            (
                format!("{window} --dop 0.3,-0.2,1 --view-distance 2"),
                view(json!({"dop": [0.3, -0.2, 1], "view_distance": 2})),
            ),
            (
                format!("{window} --oblique cabinet,30"),
                view(json!({"oblique": {"kind": "cabinet", "angle": 30}})),
            ),
            (
                format!("{window} --oblique cavalier"),
                view(json!({"oblique": {"kind": "cavalier"}})),
            ),
            (
                "--oblique isometric --vrp 2,2,2 --window -1,1,-1,1 --front 0 --back 9".into(),
                json!({"view": {"vrp": [2, 2, 2], "isometric": true,
                                "window": [-1, 1, -1, 1], "front": 0, "back": 9}}),
            ),
        ];
        for (args, value) in cases {
            let by_flags = flags(&args).resolve().unwrap().unwrap();
            assert!(same_bits(&by_flags, &cam(value)), "{args}");
        }
    }

    /// Bad cameras as flags and as JSON: the same error, the flag named in place
    /// of the field (or the field when no single flag sets it), and a usage error.
    #[test]
    fn flags_and_json_give_the_same_errors() {
        let window = "--window -1,1,-1,1 --front -10 --back 10";
        let cases = [
            (
                "--perspective 55,1,-1,1000".to_string(),
                json!({"perspective": {"fovy": 55, "aspect": 1, "near": -1, "far": 1000}}),
                "--perspective",
            ),
            (
                "--lookat 0,0,0,0,0,0 --ortho2 0,1,0,1".into(),
                json!({"lookat": {"eye": [0, 0, 0], "center": [0, 0, 0]}, "ortho2": [0, 1, 0, 1]}),
                "--lookat",
            ),
            (
                "--lookat 0,5,0,0,0,0 --perspective 0,1,0,1".into(),
                json!({"lookat": {"eye": [0, 5, 0], "center": [0, 0, 0]}, "perspective": {"fovy": 0, "aspect": 1, "near": 0, "far": 1}}),
                "--lookat",
            ),
            (
                "--lookat 0,0,0,0,0,-1 --up 0,0,2 --ortho2 0,1,0,1".into(),
                json!({"lookat": {"eye": [0, 0, 0], "center": [0, 0, -1], "up": [0, 0, 2]}, "ortho2": [0, 1, 0, 1]}),
                "--up",
            ),
            (
                "--lookat 0,0,0,0,0,-1".into(),
                json!({"lookat": {"eye": [0, 0, 0], "center": [0, 0, -1]}}),
                "camera",
            ),
            (
                "--ortho2 0,1,0,1 --perspective 60,1,0,1".into(),
                json!({"ortho2": [0, 1, 0, 1], "perspective": {"fovy": 60, "aspect": 1, "near": 0, "far": 1}}),
                "--ortho2",
            ),
            (
                "--ortho -1,1,0,1,0,0".into(),
                json!({"ortho": {"left": -1, "right": 1, "bottom": 0, "top": 1, "near": 0, "far": 0}}),
                "--ortho",
            ),
            (
                format!("{window} --dop 0,0,1 --ortho2 0,1,0,1"),
                {
                    let mut v = view(json!({"dop": [0, 0, 1]}));
                    v["ortho2"] = json!([0, 1, 0, 1]);
                    v
                },
                "--ortho2",
            ),
            (
                format!("{window} --lookat 0,0,0,0,0,-1 --oblique cavalier"),
                {
                    let mut v = view(json!({"oblique": {"kind": "cavalier"}}));
                    v["lookat"] = json!({"eye": [0, 0, 0], "center": [0, 0, -1]});
                    v
                },
                "--lookat",
            ),
            (window.to_string(), view(json!({})), "view"),
            (
                "--dop 0,0,1 --front 0 --back 1".into(),
                json!({"view": {"dop": [0, 0, 1], "front": 0, "back": 1}}),
                "--window",
            ),
            (
                "--dop 0,0,1 --window 0,1,0,1 --back 1".into(),
                json!({"view": {"dop": [0, 0, 1], "window": [0, 1, 0, 1], "back": 1}}),
                "--front",
            ),
            (
                "--dop 0,0,1 --window 0,1,0,1 --front 3".into(),
                json!({"view": {"dop": [0, 0, 1], "window": [0, 1, 0, 1], "front": 3}}),
                "--back",
            ),
            (
                format!("{window} --cop 0,0,1 --oblique cabinet"),
                view(json!({"cop": [0, 0, 1], "oblique": {"kind": "cabinet"}})),
                "--oblique",
            ),
            (
                format!("{window} --dop 0,0,1 --oblique isometric"),
                view(json!({"dop": [0, 0, 1], "isometric": true})),
                "--oblique",
            ),
            (
                format!("{window} --oblique isometric --vpn -1,-2,-1"),
                view(json!({"isometric": true, "vpn": [-1, -2, -1]})),
                "--vpn",
            ),
            (
                format!("{window} --vpn 0,0,0 --view-up 0,0,0 --dop 0,0,1"),
                view(json!({"vpn": [0, 0, 0], "view_up": [0, 0, 0], "dop": [0, 0, 1]})),
                "--vpn",
            ),
            (
                format!("{window} --view-up 0,0,3 --dop 0,0,1"),
                view(json!({"view_up": [0, 0, 3], "dop": [0, 0, 1]})),
                "--view-up",
            ),
            (
                format!("{window} --dop 1,0,1e-300"),
                view(json!({"dop": [1, 0, 1e-300]})),
                "--dop",
            ),
            (
                format!("{window} --cop 0,0,-3"),
                view(json!({"cop": [0, 0, -3]})),
                "--cop",
            ),
            (
                "--cop 0,0,1 --window -1,1,-1,1 --front -2 --back 10".into(),
                json!({"view": {"cop": [0, 0, 1], "window": [-1, 1, -1, 1], "front": -2, "back": 10}}),
                "--front",
            ),
            (
                "--window 1,1,0,1 --front 0 --back 1 --dop 0,0,1".into(),
                json!({"view": {"window": [1, 1, 0, 1], "front": 0, "back": 1, "dop": [0, 0, 1]}}),
                "--window",
            ),
            (
                format!("{window} --vrp 1.5e308,1.5e308,1.5e308 --oblique isometric"),
                view(json!({"vrp": [1.5e308, 1.5e308, 1.5e308], "isometric": true})),
                "camera",
            ),
        ];
        for (args, value, named) in cases {
            let e = flags(&args).resolve().unwrap_err();
            assert!(
                e.downcast_ref::<crate::cli::UsageError>().is_some(),
                "{args}"
            );
            let Err(CameraError::Invalid { field, message, .. }) = Camera::from_json(&value, "t")
            else {
                panic!("{value} is not rejected as invalid");
            };
            assert_eq!(flag_of(&field).unwrap_or(&field), named, "{args}");
            assert_eq!(
                format!("{e:#}"),
                format!("camera flags: {named}: {message}"),
                "{args}"
            );
        }
    }
}
