//! `scene-render`: the polygon stream through a camera to an image, with exact
//! anti-aliasing, the SPEC §4 reference image, and image comparison.

use super::Size;
use crate::camera::{Camera, CameraArgs};
use crate::color::Rgb8;
use crate::io::{decode_image, display_name, read_input, Image, ImageFormat, PngOptions};
use crate::pat::Pattern;
use crate::raster::{
    self, compare, reference, Aa, Background, Cull, ScreenPattern, ScreenPoly, View,
};
use crate::stream::{for_each_record, PatternMode, Shape};
use crate::usage_bail;
use anyhow::{Context, Result};
use clap::Parser;
use glam::DVec3;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::sync::Arc;

const TOOL: &str = "scene-render";

const EXAMPLES: &str = "\
Examples:
  scene-render --size 1024x768 --background 255,255,255 demo1.json -o demo1.png
  polyfill3 pyramid.json | scene-render --camera demo2.camera.json -o demo2.png
  scene-render --perspective 55,1.333,0,1000 --lookat 0,100,-5,0,0,-900 scene.json > out.png
  scene-render --aa ss16 --cull back scene.json -o ss16.png
  scene-render --reference scene.json -o reference.png
  scene-render --aa exact scene.json --compare reference.png --diff diff.png
  scene-render --image llvmpipe.png --compare reference.png --json

Without a camera the view is ortho2(0, W, 0, H) for a WxH image: 2D records
(rect, circle, arc) and [x,y] polygons map one world unit to one pixel, origin
at the lower-left.";

/// Render a polygon stream (SPEC §2) to PNG, PPM or PAM: homogeneous clipping,
/// depth buffering, and exact-area anti-aliasing in linear light.
#[derive(Parser, Debug)]
#[command(name = "scene-render", version, after_help = EXAMPLES)]
pub struct Args {
    /// The polygon stream (JSON array or NDJSON); `-` reads standard input.
    #[arg(default_value = "-")]
    pub input: String,

    /// Output image; `-` is standard output. Default: standard output, or no image
    /// with --compare (only the report).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<String>,

    /// Image format; by default from the output's extension, PNG on standard output.
    #[arg(long, value_enum)]
    pub format: Option<ImageFormat>,

    /// Image size (WxH). The default is the IRIS screen.
    #[arg(long, default_value = "1024x768")]
    pub size: Size,

    /// Background colour (`r,g,b` or `#rrggbb`).
    #[arg(long, value_name = "COLOR", default_value = "0,0,0")]
    pub background: Rgb8,

    /// A .pat tiled over the background in screen mode (the thesis's colorclear):
    /// pixel (x, y) from the lower-left takes texel (x mod SIZE, y mod SIZE);
    /// transparent texels show --background.
    #[arg(long, value_name = "FILE.pat")]
    pub background_pattern: Option<String>,

    #[command(flatten)]
    pub camera: CameraArgs,

    #[command(flatten)]
    pub texture: super::scene_texture::TextureArgs,

    /// Which faces to drop; the front is the side from which the vertices run
    /// counter-clockwise.
    #[arg(long, value_enum, default_value_t = Cull::None)]
    pub cull: Cull,

    /// Anti-aliasing: none (pixel centres), ss<N> (N = k*k samples on a k x k
    /// grid, N up to 256), or exact (the exact visible area of every polygon in
    /// each pixel, box filter).
    #[arg(long, value_name = "none|ssN|exact", default_value = "exact")]
    pub aa: Aa,

    /// Render the SPEC §4 reference image instead (an independent, slower
    /// method: exact along lines, exact between events along y); its own error
    /// estimate is reported on standard error.
    #[arg(long, conflicts_with = "aa")]
    pub reference: bool,

    /// Uniform strips per pixel added to the reference's events (a multiple of
    /// 3; more only tightens the error estimate).
    #[arg(long, value_name = "N", default_value_t = reference::DEFAULT_LINES,
          value_parser = clap::value_parser!(u32).range(3..=3000), requires = "reference")]
    pub reference_samples: u32,

    /// Compare the image with this reference image and print RMSE, PSNR, the
    /// largest error and the share of pixels off by more than 4 (8-bit sRGB,
    /// over RGB).
    #[arg(long, value_name = "REF")]
    pub compare: Option<String>,

    /// With --compare: measure this existing image instead of rendering a scene.
    #[arg(long, value_name = "IMAGE", requires = "compare")]
    pub image: Option<String>,

    /// With --compare: write the difference, amplified 16x per channel, here.
    #[arg(long, value_name = "FILE", requires = "compare")]
    pub diff: Option<String>,

    /// Print the --compare and --reference reports as JSON.
    #[arg(long)]
    pub json: bool,

    /// Print the time of each phase (read and project, render, write) to
    /// standard error.
    #[arg(long)]
    pub timings: bool,

    /// Worker threads (default: all cores). The output is identical for any N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
}

/// Runs `scene-render`.
pub fn run(args: Args) -> Result<()> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n as usize);
    }
    let pool = pool.build().context("starting worker threads")?;
    pool.install(|| run_in_pool(args))
}

fn run_in_pool(args: Args) -> Result<()> {
    if args.json && args.compare.is_none() && !args.reference {
        usage_bail!("--json is for the --compare and --reference reports");
    }
    // Everything that can fail is checked before anything is written.
    let reference_img = match &args.compare {
        Some(r) => Some(load_image(r)?),
        None => None,
    };
    if let Some(img_name) = &args.image {
        let img = load_image(img_name)?;
        return finish(&args, None, img, reference_img, None);
    }
    let output = match (&args.output, &args.compare) {
        (Some(o), _) => Some(o.clone()),
        (None, Some(_)) => None,
        (None, None) => Some(crate::io::STDIO.to_string()),
    };
    let format = output
        .as_deref()
        .map(|o| ImageFormat::choose(args.format, o))
        .transpose()?;
    let Size { width, height } = args.size;
    let camera = match args.camera.resolve()? {
        Some(c) => c,
        None => Camera::ortho2(0.0, width as f64, 0.0, height as f64),
    };
    let view = View {
        world_to_clip: camera.world_to_clip(),
        near: camera.near,
        far: camera.far,
        perspective: camera.perspective,
        width,
        height,
    };
    let bg = Background {
        color: args.background,
        pattern: match &args.background_pattern {
            Some(p) => Some(Pattern::read_file(std::path::Path::new(p))?),
            None => None,
        },
    };
    let t_read = std::time::Instant::now();
    let polys = read_scene(&args.input, &view, args.cull, &args.texture)?;
    let t_render = std::time::Instant::now();
    let (img, residual) = if args.reference {
        let r = reference::render(&polys, &bg, width, height, args.reference_samples);
        let res = r.residual(args.reference_samples);
        (r.frame.to_image(), Some(res))
    } else {
        (
            raster::render(&polys, &bg, width, height, args.aa).to_image(),
            None,
        )
    };
    let t_write = std::time::Instant::now();
    finish(&args, output.zip(format), img, reference_img, residual)?;
    if args.timings {
        eprintln!(
            "{TOOL}: timings: read {:.4} s, render {:.4} s, write {:.4} s ({} polygons)",
            (t_render - t_read).as_secs_f64(),
            (t_write - t_render).as_secs_f64(),
            t_write.elapsed().as_secs_f64(),
            polys.len()
        );
    }
    Ok(())
}

/// Writes the image and the reports, in that order, once everything is computed.
fn finish(
    args: &Args,
    output: Option<(String, ImageFormat)>,
    img: Image,
    reference_img: Option<Image>,
    residual: Option<reference::Residual>,
) -> Result<()> {
    let metrics = match &reference_img {
        Some(r) => Some(compare::compare(&img, r).with_context(|| {
            format!("comparing with {}", args.compare.as_deref().unwrap_or(""))
        })?),
        None => None,
    };
    let diff = match &reference_img {
        Some(r) if args.diff.is_some() => Some(compare::diff_image(&img, r, compare::DIFF_GAIN)?),
        _ => None,
    };
    let image_on_stdout = output.as_ref().is_some_and(|(o, _)| o == crate::io::STDIO);
    if let Some((o, f)) = &output {
        img.save_with(o, *f, PngOptions::GENERAL)?;
    }
    if let (Some(d), Some(name)) = (diff, &args.diff) {
        let f = ImageFormat::choose(None, name)?;
        d.save_with(name, f, PngOptions::GENERAL)?;
    }
    // Reports go to standard output unless the image does.
    let mut text = String::new();
    if args.json {
        let mut obj = serde_json::Map::new();
        if let Some(m) = &metrics {
            obj.insert("compare".into(), serde_json::to_value(m)?);
        }
        if let Some(r) = &residual {
            obj.insert("reference".into(), serde_json::to_value(r)?);
        }
        text = serde_json::to_string_pretty(&obj)? + "\n";
    } else {
        if let Some(m) = &metrics {
            text.push_str(&m.report());
        }
        if let Some(r) = &residual {
            // Without --json the reference note is diagnostic: standard error.
            eprintln!(
                "{TOOL}: reference: error estimate at most {:.3e} linear, {} code(s) in 8 bits, {} pixel(s) not certain ({} strips/pixel over the events)",
                r.max_linear, r.max_codes, r.uncertain_pixels, r.lines
            );
        }
    }
    if !text.is_empty() {
        if image_on_stdout {
            eprint!("{text}");
        } else {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .context("writing standard output")?;
        }
    }
    Ok(())
}

fn load_image(name: &str) -> Result<Image> {
    let bytes = read_input(name)?;
    let rgba = decode_image(&bytes, display_name(name))?;
    let (width, height) = rgba.dimensions();
    Ok(Image {
        width,
        height,
        channels: 4,
        data: rgba.into_raw(),
    })
}

/// Reads the stream and projects every record. Patterns are drawn directly:
/// screen mode (the IRIS hardware patterns of the thesis's demo 1) per pixel,
/// object and uv placement through their screen → texel map
/// (`scene_texture`), integrated exactly over texel cells by `--aa exact`.
fn read_scene(
    input: &str,
    view: &View,
    cull: Cull,
    texture: &super::scene_texture::TextureArgs,
) -> Result<Vec<ScreenPoly>> {
    let name = display_name(input).to_string();
    let base = crate::stream::base_dir(input);
    let mut patterns: HashMap<std::path::PathBuf, Arc<ScreenPattern>> = HashMap::new();
    let reader: Box<dyn BufRead> = if input == crate::io::STDIO {
        Box::new(std::io::stdin().lock())
    } else {
        let path = std::path::Path::new(input);
        if path.is_dir() {
            anyhow::bail!("{input}: is a directory, not a file");
        }
        Box::new(BufReader::with_capacity(
            1 << 16,
            std::fs::File::open(path).with_context(|| input.to_string())?,
        ))
    };
    let mut polys = Vec::new();
    for_each_record(reader, &name, |rec| {
        let mut screen = None;
        // "object" and "uv" patterns: placed after projection (below).
        let mut placed = None;
        if let Some(pref) = &rec.pattern {
            let mode = pref.mode.unwrap_or(if rec.uv.is_some() {
                PatternMode::Uv
            } else {
                PatternMode::Object
            });
            let Some(file) = &pref.file else {
                anyhow::bail!("{name}: record {}: pattern.file is missing", rec.index);
            };
            // Only patterns the scene references are read, each once.
            let path = crate::stream::resolve(&base, file);
            let p = match patterns.get(&path) {
                Some(p) => p.clone(),
                None => {
                    let pat = Pattern::read_file(&path)
                        .with_context(|| format!("{name}: record {}", rec.index))?;
                    let p = Arc::new(ScreenPattern::new(&pat));
                    patterns.insert(path, p.clone());
                    p
                }
            };
            match mode {
                PatternMode::Screen => screen = Some(p),
                PatternMode::Object | PatternMode::Uv => placed = Some((pref, mode, p)),
            }
        }
        let color = rec.color.unwrap_or(Rgb8::BLACK);
        let tol = curve_tolerance(&rec.shape, view);
        let outline = crate::geom::outline(&rec.shape, tol);
        let order = u32::try_from(rec.index).context("more than 2^32 records")?;
        if let Some(mut p) = raster::project(view, &outline, color, order, cull) {
            p.screen = screen;
            if let Some((pref, mode, texels)) = placed {
                let tex = super::scene_texture::place(
                    texture,
                    color,
                    view,
                    &outline,
                    pref,
                    mode,
                    rec.uv.as_deref(),
                    texels,
                )
                .with_context(|| format!("{name}: record {}", rec.index))?;
                match tex {
                    Some(t) => p.texture = Some(Arc::new(t)),
                    // Visible by the projection but not by the fit: rounding
                    // at a sliver; nothing to draw.
                    None => return Ok(()),
                }
            }
            polys.push(p);
        }
        Ok(())
    })?;
    Ok(polys)
}

/// World-space chord tolerance for a curved record, from the view's scale at
/// the curve's centre, so chords stay within [`raster::CURVE_TOLERANCE_PX`].
fn curve_tolerance(shape: &Shape, view: &View) -> f64 {
    let (center, radius) = match *shape {
        Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => (center, radius),
        _ => return 1.0,
    };
    let c = DVec3::new(center[0], center[1], 0.0);
    let at = |p: DVec3| {
        let q = view.to_clip(p);
        glam::DVec2::new(
            q.x / q.w * view.width as f64,
            q.y / q.w * view.height as f64,
        ) * 0.5
    };
    let (p0, px, py) = (at(c), at(c + DVec3::X * radius), at(c + DVec3::Y * radius));
    let px_per_unit = (px - p0).length().max((py - p0).length()) / radius;
    if px_per_unit.is_finite() && px_per_unit > 0.0 {
        raster::CURVE_TOLERANCE_PX / px_per_unit
    } else {
        // Behind the eye or degenerate: fall back to a fine relative tolerance.
        radius * 1e-4
    }
}
