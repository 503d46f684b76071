//! `scene-render`: the polygon stream through a camera to an image, with exact
//! anti-aliasing, the reference image (docs/rendering.md), and image comparison.

use super::camera::CameraArgs;
use super::Size;
use crate::camera::Camera;
use crate::cli::{eprintln_or_drop, usage_bail};
use crate::color::Rgb8;
use crate::io::{decode_any, display_name, read_input, AnyImage, Depth, ImageFormat, PngOptions};
use crate::progress::Progress;
use crate::raster::{self, compare, reference, Aa, Background, Cull};
use crate::scene::{self, DrawOptions, Scene};
use crate::texture::place::TextureSettings;
use crate::texture::Texels;
use crate::view::View;
use anyhow::{Context, Result};
use clap::Parser;
use std::io::Write;

const TOOL: &str = "scene-render";

const EXAMPLES: &str = "\
Examples:
  scene-render --ortho2 0,1023,0,767 --background 255,255,255 demo1.json -o demo1.png
      The thesis's demo 1: 2D records with screen-mode patterns.
  polyfill3 scene.json -o cells.json
  scene-render --camera cam.json --cull back --background-pattern bkgrnd.pat cells.json -o demo2.png
      The thesis's demo 2: its pyramid and plain cut into texture point
      polygons by polyfill3, then drawn.
  scene-render --perspective 55,auto,0,1000 --lookat 0,100,-5,0,0,-900 scene.json > out.png
      Aspect auto: the image's own width/height, no stretch (demo 2 uses 1 at 1024x768).
  scene-render --camera cam.json --aa ss16 --cull back scene.json -o ss16.png
  scene-render --camera cam.json --cull back --reference scene.json -o reference.png
  scene-render --camera cam.json --cull back scene.json --compare reference.png --diff diff.png
  scene-render --image ss16.png --compare reference.png --json
      Measure any image of the same size against the reference.
  scene-render --camera cam.json --cull back scene.json -o exact.pfm
  scene-render --camera cam.json --cull back --depth 16 scene.json -o exact16.png
  scene-render --image exact16.png --compare exact.pfm
      The frame's linear values unrounded (PFM), and 16-bit sRGB: errors
      below one 8-bit code can be measured.
  scene-render --camera cam.json --frames 36 -o frame-%04d.png spin.json
      An animation: instance transforms with {\"start\": a, \"step\": s} numbers.
  scene-render --camera cam.json --frames 36 --frame 7 -o frame-%04d.png spin.json
      Frame 7 alone, as one job of a make -j, GNU parallel or Slurm batch.
  scene-render --camera cam.json --frames 36 --animate --fps 12 -o turn.png spin.json
      The same animation as one animated PNG.
  scene-render --ortho -80,80,-60,60,0,100 --size 800x600 two-spheres.json -o two.png
      Seed 002's textured spheres: quadric records (sphere, cylinder, cone, disk).

Without a camera the view is ortho2(0, W, 0, H) for a WxH image: 2D records
(rect, circle, arc) and [x,y] polygons map one world unit to one pixel, origin
at the lower-left.";

/// Render a polygon stream (patkit-stream(5)) to PNG, PPM or PAM (8- or 16-bit sRGB)
/// or PFM (linear float): homogeneous clipping, depth buffering, and exact-area
/// anti-aliasing in linear light.
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

    /// Image format; by default from the output's extension (.png, .ppm,
    /// .pnm, .pam, .pfm), PNG on standard output. PFM stores the frame's
    /// linear-light values as 32-bit floats, unrounded, and no alpha.
    #[arg(long, value_enum)]
    pub format: Option<ImageFormat>,

    /// Bits per channel of PNG, PPM and PAM output: 8, or 16 (each code the
    /// nearest to the exact sRGB value; MAXVAL 65535 in PPM and PAM). Not
    /// for PFM, which is float, nor --animate.
    #[arg(long, value_enum, value_name = "8|16", hide_possible_values = true,
          conflicts_with_all = ["image", "animate"])]
    pub depth: Option<Depth>,

    /// Image size (WxH). The default is the IRIS screen.
    #[arg(long, default_value = "1024x768")]
    pub size: Size,

    /// Background colour (`r,g,b` or `#rrggbb`), or `none`: what polygons
    /// leave uncovered is transparent, and the image carries their coverage
    /// as alpha (PNG, PAM). The frame is drawn twice: 1.6x the whole
    /// process's time on 10,000 random triangles in one run
    /// (bench/RESULTS-same-images.md).
    #[arg(long, value_name = "COLOR", default_value = "0,0,0")]
    pub background: BackgroundColor,

    /// A .pat or an image (PNG, JPEG, ...: told by content) tiled over the
    /// background in screen mode (the thesis's colorclear): pixel (x, y)
    /// from the lower-left takes texel (x mod W, y mod H), an image's bottom
    /// row being texel row 0; transparent texels (alpha below one half) show
    /// --background.
    #[arg(long, value_name = "FILE")]
    pub background_pattern: Option<String>,

    #[command(flatten)]
    pub camera: CameraArgs,

    #[command(flatten)]
    pub texture: super::scene_texture::TextureArgs,

    #[command(flatten)]
    pub stripe: super::scene_stripe::StripeArgs,

    /// Which faces to drop; the front is the side from which the vertices run
    /// counter-clockwise.
    #[arg(long, value_enum, default_value_t = Cull::None)]
    pub cull: Cull,

    /// Anti-aliasing: none (pixel centres), ss<N> (N = k*k samples on a k x k
    /// grid, N up to 256), or exact (the exact visible area of every polygon in
    /// each pixel, box filter; a textured fragment meeting more than 65,536
    /// texels, 16,384 with transparent texels, or a stripe fragment crossing
    /// more than 65,536 map-sample boundaries is estimated instead, and reported:
    /// docs/rendering.md, Where exactness holds).
    // This doc comment is the flag's --help text, where `ss<N>` is meant
    // literally; rustdoc would read `<N>` as an unclosed HTML tag.
    #[allow(rustdoc::invalid_html_tags)]
    #[arg(long, value_name = "none|ssN|exact", default_value = "exact")]
    pub aa: Aa,

    /// Removed: kept only to say so to the scripts that pass it.
    #[arg(long, value_name = "E", hide = true, allow_hyphen_values = true)]
    pub max_error: Option<String>,

    /// Render the reference image instead (each pixel the average of the
    /// scene over its square in linear light, by an independent, slower
    /// method: exact along lines, exact between events along y); its own error
    /// estimate is reported on standard error, with the number of pixels
    /// whose 8-bit value it leaves uncertain (pixels meeting more than 1,024
    /// texel lines or a plane's horizon, for one): it is no ground truth there
    /// (docs/rendering.md, Where exactness holds).
    #[arg(long, conflicts_with = "aa")]
    pub reference: bool,

    /// Uniform strips per pixel added to the reference's events (a multiple of
    /// 3 from 3 to 3000; more only tightens the error estimate).
    #[arg(long, value_name = "N", default_value_t = reference::DEFAULT_LINES,
          value_parser = parse_reference_samples, requires = "reference")]
    pub reference_samples: u32,

    /// Compare the image with this reference image and print RMSE, PSNR, the
    /// largest error and the share of pixels off by more than 4 (8-bit sRGB,
    /// over RGB). A 16-bit PNG, PPM or PAM, or a PFM, on either side is
    /// measured in fractional 8-bit codes and in linear light too.
    #[arg(long, value_name = "REF")]
    pub compare: Option<String>,

    /// With --compare: measure this existing image instead of rendering a scene.
    /// The flags that shape a render or its output are refused with it.
    #[arg(long, value_name = "IMAGE", requires = "compare", conflicts_with_all = [
        "input", "output", "format", "depth", "size", "background", "background_pattern",
        "CameraArgs", "TextureArgs", "StripeArgs", "cull", "aa", "max_error", "reference",
        "reference_samples", "frames", "animate", "fps", "quadric_tolerance", "frame",
        "max_polygons",
    ])]
    pub image: Option<String>,

    /// With --compare: write the difference, amplified 16x per channel, here
    /// (an 8-bit PNG, PPM or PAM, whatever the inputs' depth).
    #[arg(long, value_name = "FILE", requires = "compare")]
    pub diff: Option<String>,

    /// Print the --compare and --reference reports, and what --aa exact
    /// estimated, as one JSON object, {"version": 1, "tool": "scene-render",
    /// ...}; with --frames or --frame, one entry per frame in its "frames"
    /// array (docs/json.md). It goes to standard output, or standard error
    /// when the image does.
    #[arg(long)]
    pub json: bool,

    /// Print the time of each phase (read and project, render, write) to
    /// standard error.
    #[arg(long)]
    pub timings: bool,

    /// Render an animation of N frames (docs/objects.md): numbers of instance
    /// transforms written `{"start": a, "step": s}` are `a + s*k` in frame k
    /// (0-based), and so are those of quadric records' "transform". -o must
    /// then be a pattern such as frame-%04d.png, or a plain name with
    /// --animate.
    #[arg(long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u64).range(1..=MAX_FRAMES),
          conflicts_with_all = ["reference", "compare", "image"])]
    pub frames: u64,

    /// With --frames: write one animated PNG (APNG) to -o, a plain name such
    /// as turn.png, instead of one file per frame. It loops forever; every
    /// frame is whole, and frame 0 is also the still image shown by viewers
    /// without APNG support.
    #[arg(long, requires = "frames", conflicts_with = "frame")]
    pub animate: bool,

    /// With --animate: frames per second (each frame shows for 1/FPS s).
    #[arg(long, value_name = "FPS", default_value_t = DEFAULT_FPS,
          value_parser = parse_fps, requires = "animate")]
    pub fps: u16,

    /// Largest distance, in pixels, of a quadric's chords from its true
    /// surface, for quadric records that leave out slices or stacks
    /// (docs/objects.md): measured at the nearest point of the quadric's
    /// bounding sphere as drawn by this camera.
    #[arg(long, value_name = "PX", default_value_t = crate::geom::quadric::DEFAULT_TOLERANCE_PX)]
    pub quadric_tolerance: f64,

    /// Render only frame K of the --frames (0-based): one job of a batch run
    /// by make -j, GNU parallel or a Slurm job array.
    #[arg(long, value_name = "K", conflicts_with_all = ["reference", "compare", "image"])]
    pub frame: Option<u64>,

    /// Write the make rule of the output: every file the run read (the
    /// stream, its patterns and stripe files, the camera file,
    /// --background-pattern, --compare), as `cc -MD` does. Needs -o; with
    /// --frames, every frame is a target.
    #[arg(long, value_name = "FILE")]
    pub depfile: Option<String>,

    /// The most polygons a frame may expand into (instances times their objects'
    /// polygons, an empty object's counting one, quadrics their triangles): a
    /// scene over it is refused when read,
    /// before any work (a quadric without slices and stacks when the view has
    /// chosen them, before it is cut).
    #[arg(long, value_name = "N", default_value_t = crate::scene::LoadOptions::DEFAULT.max_polygons)]
    pub max_polygons: u64,

    #[command(flatten)]
    pub threads: super::ThreadArgs,

    #[command(flatten)]
    pub progress: super::progress::ProgressArgs,
}

/// The scene's drawing options from the flags.
fn draw_options(args: &Args, texture: TextureSettings) -> DrawOptions {
    DrawOptions {
        cull: args.cull,
        texture,
        stripe_lod: args.stripe.mode(),
        stripe_footprint: scene::stripe_footprint(args.aa),
        quadric_tolerance: args.quadric_tolerance,
    }
}

/// Runs `scene-render`.
pub fn run(args: Args) -> Result<()> {
    // A usage error first (status 2), then the standard output's.
    super::check_inputs(&inputs_of(&args))?;
    let to_stdout = match &args.output {
        Some(o) => o == crate::io::STDIO,
        None => args.compare.is_none(),
    };
    if to_stdout {
        super::check_stdout(super::USE_OUTPUT_FILE)?;
    } else if args.compare.is_some() || args.json {
        // The report's place, checked before the work: found closed after
        // the render, it failed the run with the image already in place
        // of the old one (a hostile-input review).
        super::check_stdout(REPORT_ON_STDOUT)?;
    }
    args.threads.install(|| run_in_pool(args))?
}

/// [`super::check_stdout`]'s hint where the report goes to standard output.
const REPORT_ON_STDOUT: &str = "the report goes there: redirect it to a file";

/// The most frames one run renders: a day of film at 24 frames a second,
/// far more than a batch needs, and a bound that catches a mistyped count.
pub const MAX_FRAMES: u64 = 24 * 60 * 60 * 24;

/// Frames per second of an --animate APNG: the thesis's demo 2 turned its
/// pyramid at about this rate on the IRIS.
pub const DEFAULT_FPS: u16 = 10;

/// The files the command line names to read, by flag.
fn inputs_of(args: &Args) -> [(&'static str, Option<&str>); 5] {
    [
        // With --image no stream is read (its default `-` included).
        (
            "the stream",
            Some(args.input.as_str()).filter(|_| args.image.is_none()),
        ),
        ("--image", args.image.as_deref()),
        ("--compare", args.compare.as_deref()),
        ("--camera", args.camera.camera.as_deref()),
        ("--background-pattern", args.background_pattern.as_deref()),
    ]
}

fn run_in_pool(args: Args) -> Result<()> {
    let inputs = inputs_of(&args);
    let animation = args.frames > 1 || args.frame.is_some();
    if let Some(k) = args.frame {
        if k >= args.frames {
            usage_bail!(
                "--frame {k}: expected a frame below --frames {}",
                args.frames
            );
        }
    }
    if !(args.quadric_tolerance > 0.0 && args.quadric_tolerance.is_finite()) {
        usage_bail!(
            "--quadric-tolerance {}: expected a positive number of pixels",
            args.quadric_tolerance
        );
    }
    let named_output = args.output.as_deref().filter(|o| *o != crate::io::STDIO);
    if args.depfile.is_some() && named_output.is_none() {
        usage_bail!("--depfile needs -o FILE: the make rule names the output as its target");
    }
    // Two outputs of one file: the one written last would replace the other
    // (`--depfile x -o x` left the make rule where the image was).
    let outputs = [
        ("-o", named_output),
        ("--diff", args.diff.as_deref()),
        ("--depfile", args.depfile.as_deref()),
    ];
    // A report goes to standard output unless the image does
    // (`print_report`): `--diff -` beside it made one stream of the two.
    let report_on_stdout =
        (args.compare.is_some() || args.json) && args.output.as_deref() != Some(crate::io::STDIO);
    super::refuse_shared_outputs(&[
        ("-o", args.output.as_deref()),
        ("the report", report_on_stdout.then_some(crate::io::STDIO)),
        outputs[1],
        outputs[2],
    ])?;
    if let (true, Some(pattern), Some(depfile)) = (animation, named_output, &args.depfile) {
        // Each frame's name against the make rule's (`-o g-%d.png --depfile
        // g-1.png` wrote frame 1 over it).
        // Resolved only where the last components match or the frame's name
        // is a link: up to MAX_FRAMES names are checked before the render
        // (2,000,000 frames: 5.1 s to the first frame against 1.7 s, a
        // review, about 1.7 µs a frame, where a frame takes milliseconds).
        let last = |n: &str| std::path::Path::new(n).file_name().map(|f| f.to_owned());
        let depfile_last =
            super::destination(depfile).and_then(|d| d.file_name().map(|f| f.to_owned()));
        let frames = args.frame.map_or(0..args.frames, |k| k..k + 1);
        for (k, name) in frames.filter_map(|k| Some((k, frame_name(pattern, k)?))) {
            let is_link = || std::fs::symlink_metadata(&name).is_ok_and(|m| m.is_symlink());
            if name == *depfile || last(&name) == depfile_last || is_link() {
                let frame = format!("frame {k} of -o");
                super::refuse_shared_outputs(&[
                    (&frame, Some(&name)),
                    ("--depfile", Some(depfile)),
                ])?;
            }
        }
    }
    // The same outputs against the inputs, `-o -` as the file standard
    // output is; an animation's frames are checked one by one as they are
    // written (`render_frames`), its -o being a pattern of names.
    let destinations = [
        ("-o", args.output.as_deref().filter(|_| !animation)),
        outputs[1],
        outputs[2],
    ];
    super::refuse_replacing_inputs(&destinations, &inputs)?;
    if args.animate {
        match &args.output {
            None => usage_bail!("--animate: give -o, the animated PNG to write"),
            Some(o) if frame_name(o, 0).is_some() => {
                usage_bail!(
                    "-o {o}: --animate writes one file: expected a plain name such as turn.png"
                )
            }
            _ => {}
        }
        if matches!(args.format, Some(f) if f != ImageFormat::Png) {
            usage_bail!("--animate writes an animated PNG: --format must be png");
        }
        let o = args.output.as_deref().unwrap_or_default();
        let ext = std::path::Path::new(o)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if o != crate::io::STDIO && !matches!(ext.as_deref(), Some("png" | "apng")) {
            usage_bail!("-o {o}: --animate writes an animated PNG: expected a .png or .apng name");
        }
    } else if animation {
        match &args.output {
            None => usage_bail!("--frames: give -o, a pattern such as frame-%04d.png"),
            // Standard output: the frames one after another (a stream).
            Some(o) if o == crate::io::STDIO => {}
            Some(o) if frame_slots(o).len() > 1 => {
                usage_bail!("-o {o}: more than one frame number in the name: give one %d or %0Nd (%% is a literal %)")
            }
            Some(o) if frame_width(o).is_some_and(|w| w > MAX_FRAME_WIDTH) => {
                usage_bail!("-o {o}: a frame number that wide makes no file name: at most %0{MAX_FRAME_WIDTH}d")
            }
            Some(o) if frame_name(o, 0).is_none() && (args.frame.is_none() && args.frames > 1) => {
                usage_bail!("-o {o}: with --frames {} expected a pattern with %d or %0Nd, such as frame-%04d.png", args.frames)
            }
            _ => {}
        }
    }
    if let Some(e) = &args.max_error {
        usage_bail!("--max-error {e}: this option was removed: --aa exact (the default) took as long as the plans it chose, on every benchmark scene, and is exact (bench/RESULTS-max-error.md); for speed choose --aa none or ssN by bench/RESULTS-tradeoff.md");
    }
    if args.json && args.compare.is_none() && !args.reference && !animation {
        usage_bail!(
            "--json is for the --compare and --reference reports, and for the frames of --frames"
        );
    }
    let texture = match args.texture.settings() {
        Ok(t) => t,
        Err(e) => usage_bail!("{e}"),
    };
    // Every destination is checked before any work (a missing directory
    // found after an hour of rendering helps nobody).
    match &args.output {
        Some(o) => {
            let first = args.frame.unwrap_or(0);
            crate::io::check_output(&frame_name(o, first).unwrap_or_else(|| o.clone()), true)?;
        }
        // No -o: the image goes to standard output, unless --compare
        // only measures it; a terminal there is refused now, not after
        // the render.
        None if args.compare.is_none() => crate::io::check_output(crate::io::STDIO, true)?,
        None => {}
    }
    for extra in [&args.diff, &args.depfile].into_iter().flatten() {
        crate::io::check_output(extra, false)?;
    }
    if let Some(d) = &args.diff {
        // The difference is an 8-bit picture.
        super::output_format_8bit(None, d)?;
    }
    // Everything that can fail is checked before anything is written, and
    // the sizes before any pixel is decoded or drawn: a reference of
    // another size was found after a 4096x4096 render of 47 s, and a
    // 16000x16000 PNG of 1 MB was decoded (1.75 GB) to be found larger
    // than a 32x32 image (a hostile-input review).
    let reference_bytes = args.compare.as_deref().map(read_picture).transpose()?;
    let image_bytes = args.image.as_deref().map(read_picture).transpose()?;
    if let (Some(r), Some(r_bytes)) = (&args.compare, &reference_bytes) {
        let image = match (&args.image, &image_bytes) {
            (Some(i), Some(i_bytes)) => crate::io::picture_size(i_bytes, display_name(i))?,
            _ => (args.size.width, args.size.height),
        };
        let reference = crate::io::picture_size(r_bytes, display_name(r))?;
        if image != reference {
            let mismatch = compare::SizeMismatch { image, reference };
            return Err(anyhow::Error::new(mismatch).context(format!("comparing with {r}")));
        }
    }
    let reference_img = match (&args.compare, &reference_bytes) {
        (Some(r), Some(bytes)) => Some(decode_any(bytes, display_name(r))?),
        _ => None,
    };
    if let (Some(img_name), Some(bytes)) = (&args.image, &image_bytes) {
        let img = decode_any(bytes, display_name(img_name))?;
        write_depfile(&args, None)?;
        finish(
            &args,
            None,
            img,
            reference_img,
            Reports {
                residual: None,
                estimated: None,
            },
        )?;
        return Ok(());
    }
    let output = match (&args.output, &args.compare) {
        (Some(o), _) => Some(o.clone()),
        (None, Some(_)) => None,
        (None, None) => Some(crate::io::STDIO.to_string()),
    };
    let transparent = args.background == BackgroundColor::None;
    let stream = animation && !args.animate && output.as_deref() == Some(crate::io::STDIO);
    let format = if args.animate {
        Some(ImageFormat::Png)
    } else if stream {
        // Frames one after another on standard output, for `ffmpeg -f
        // image2pipe -i -`: uncompressed unless --format says otherwise.
        Some(args.format.unwrap_or(if transparent {
            ImageFormat::Pam
        } else {
            ImageFormat::Ppm
        }))
    } else {
        output
            .as_deref()
            .map(|o| super::output_format(args.format, o))
            .transpose()?
    };
    if transparent && format == Some(ImageFormat::Ppm) {
        usage_bail!("--background none: PPM has no alpha channel: write PNG or PAM");
    }
    // The format written, or without an output (--compare alone) the one
    // --format names, else PNG: the image is measured as it would be written.
    let written = format.or(args.format).unwrap_or(ImageFormat::Png);
    if transparent && written == ImageFormat::Pfm {
        usage_bail!("--background none: PFM has no alpha channel: write PNG or PAM");
    }
    if let (ImageFormat::Pfm, Some(d)) = (written, args.depth) {
        usage_bail!(
            "--depth {}: PFM stores 32-bit floats in linear light: --depth is for PNG, PPM and PAM",
            if d == Depth::Sixteen { 16 } else { 8 }
        );
    }
    let encoding = written.encoding(args.depth.unwrap_or_default());
    let Size { width, height } = args.size;
    let given = args.camera.resolve()?;
    let camera_given = given.is_some();
    let camera = given.unwrap_or_else(|| Camera::ortho2(0.0, width as f64, 0.0, height as f64));
    let view = View::new(&camera, width, height);
    let bg_pattern = match &args.background_pattern {
        // A command-line input: `<(...)` works as well as a file.
        Some(p) => Some(Texels::read_input(p)?),
        None => None,
    };
    let bg = match args.background {
        BackgroundColor::Color(c) => Background::new(c, bg_pattern),
        BackgroundColor::None => Background::transparent(bg_pattern),
    };
    let t_read = std::time::Instant::now();
    let limits = crate::scene::LoadOptions {
        max_polygons: args.max_polygons,
    };
    let scene =
        Scene::load_with(&args.input, &limits).map_err(|e| scene_error(&args, e, Stage::Read))?;
    for w in scene.warnings() {
        super::warn("scene-render", w);
    }
    let how = draw_options(&args, texture);
    if animation || args.animate {
        let format = format.expect("animations have an output");
        super::refuse_replacing_read_files(&destinations, scene.files())?;
        write_depfile(&args, Some(scene.files()))?;
        let named = inputs
            .iter()
            .filter_map(|(_, p)| p.filter(|p| *p != crate::io::STDIO));
        let read: Vec<std::path::PathBuf> = scene
            .files()
            .iter()
            .cloned()
            .chain(named.map(std::path::PathBuf::from))
            .collect();
        return render_frames(
            &args,
            &how,
            scene,
            (&view, camera_given),
            &bg,
            (format, encoding),
            &read,
        );
    }
    // One frame needs only its screen polygons: the scene's parts go as
    // they are projected, before the render's own buffers come.
    let files = scene.files().to_vec();
    let (polys, tally) = scene
        .into_frame(&view, &how, 0)
        .map_err(|e| scene_error(&args, e, Stage::Project))?;
    warn_if_blank(&args, (&view, camera_given), 0, &tally);
    let t_render = std::time::Instant::now();
    let bar = args.progress.bar(TOOL);
    let (img, residual, estimated) = if args.reference {
        let pass = |bg: &Background| {
            reference::render_with(&polys, bg, &view, args.reference_samples, &bar)
        };
        let r = if bg.is_transparent() {
            pass(&bg.opaque(Rgb8::BLACK))
        } else {
            pass(&bg)
        };
        let res = r.residual(args.reference_samples);
        let img = if bg.is_transparent() {
            let over_white = pass(&bg.opaque(Rgb8::WHITE));
            raster::Frame::encode_with_alpha(&r.frame, &over_white.frame, encoding)
        } else {
            r.frame.encode(encoding)
        };
        (img, Some(res), None)
    } else {
        let r = scene::render_encoded(&polys, &bg, &view, args.aa, &bar, encoding);
        let estimated = Estimated::of(&r, &polys);
        (r.image, None, estimated)
    };
    drop(bar);
    let t_write = std::time::Instant::now();
    let reports = Reports {
        residual,
        estimated,
    };
    super::refuse_replacing_read_files(&destinations, &files)?;
    write_depfile(&args, Some(&files))?;
    finish(&args, output.zip(format), img, reference_img, reports)?;
    if args.timings {
        eprintln_or_drop!(
            "{TOOL}: timings: read {:.4} s, render {:.4} s, write {:.4} s ({} polygons)",
            (t_render - t_read).as_secs_f64(),
            (t_write - t_render).as_secs_f64(),
            t_write.elapsed().as_secs_f64(),
            polys.len()
        );
    }
    Ok(())
}

/// `--depfile`: the outputs written (every frame of an animation) and every
/// file read to make them. Written before the outputs: a rule that cannot
/// be written then leaves them as they were (written after, they would be
/// targets newer than their files with no rule naming those files), and a
/// rule written for outputs that then fail is harmless, their old files
/// being older than it says.
fn write_depfile(args: &Args, scene_files: Option<&[std::path::PathBuf]>) -> Result<()> {
    let Some(depfile) = &args.depfile else {
        return Ok(());
    };
    let output = args
        .output
        .as_deref()
        .expect("--depfile needs -o (checked)");
    let targets: Vec<String> = if args.animate || (args.frames <= 1 && args.frame.is_none()) {
        vec![output.to_string()]
    } else {
        let frames: Vec<u64> = match args.frame {
            Some(k) => vec![k],
            None => (0..args.frames).collect(),
        };
        frames
            .into_iter()
            .map(|k| frame_name(output, k).unwrap_or_else(|| output.to_string()))
            .collect()
    };
    let mut deps: Vec<String> = Vec::new();
    match scene_files {
        Some(files) => {
            deps.push(args.input.clone());
            deps.extend(files.iter().map(|p| super::dep_name(p)));
            deps.extend(args.camera.camera.iter().cloned());
            deps.extend(args.background_pattern.iter().cloned());
        }
        None => deps.extend(args.image.iter().cloned()),
    }
    deps.extend(args.compare.iter().cloned());
    super::write_depfile(depfile, &targets, &deps)
}

/// `--background`: a colour, or `none` (transparent).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackgroundColor {
    /// An opaque colour.
    Color(Rgb8),
    /// Transparent: coverage becomes alpha.
    None,
}

impl std::str::FromStr for BackgroundColor {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "none" {
            return Ok(BackgroundColor::None);
        }
        s.parse::<Rgb8>()
            .map(BackgroundColor::Color)
            .map_err(|e| format!("{e}, or `none` for a transparent background"))
    }
}

/// What a render has to say beside the image.
struct Reports {
    /// `--reference`'s own error estimate.
    residual: Option<reference::Residual>,
    /// Fragments `--aa exact` estimated rather than integrated.
    estimated: Option<Estimated>,
}

/// What `--aa exact` did not integrate exactly (`Frame::estimated`): never
/// silent, a warning and, with `--json`, the key `estimated`.
#[derive(Clone, Copy, Debug, serde::Serialize)]
struct Estimated {
    /// Pixel fragments that took the EWA estimate or the stripes' LOD
    /// filter.
    fragments: u64,
    /// How far each can be from its exact value, 8-bit codes: the largest
    /// contrast of the frame's textures and stripes
    /// (`PolyTexture::contrast_codes`, `StripeTexture::contrast_codes`).
    bound_codes: u32,
}

impl Estimated {
    fn of(r: &scene::Rendered, polys: &[raster::ScreenPoly]) -> Option<Estimated> {
        r.estimate_bound(polys).map(|bound_codes| Estimated {
            fragments: r.estimated,
            bound_codes,
        })
    }

    /// The warning, `at` naming the frame of an animation.
    fn warn(&self, at: &str) {
        eprintln_or_drop!(
            "{TOOL}: warning: {at}{} pixel fragment(s) too fine to integrate exactly (more than {} texel cells, {} for a pattern with transparent texels, or stripes reaching a plane's horizon): their colour is an estimate (EWA, or the stripes' level-of-detail filter), not the exact box integral, within {} code(s) of it (the textures' contrast)",
            self.fragments,
            crate::texture::cells::MAX_EXACT_CELLS,
            crate::texture::cells::MAX_SWEPT_CELLS,
            self.bound_codes
        );
    }
}

/// Writes the image and the difference to their temporary files, then the
/// reports, then moves the files into place, once everything is computed: a
/// report that cannot be written leaves the old files. (An animation's
/// frames take their names as each is done, and its `--json` report comes
/// after the last: a full standard output then fails the run with the
/// frames written.)
fn finish(
    args: &Args,
    output: Option<(String, ImageFormat)>,
    img: AnyImage,
    reference_img: Option<AnyImage>,
    reports: Reports,
) -> Result<()> {
    let Reports {
        residual,
        estimated,
    } = reports;
    if let Some(e) = &estimated {
        e.warn("");
    }
    let metrics = match &reference_img {
        Some(r) => Some(compare::compare_any(&img, r).with_context(|| {
            format!("comparing with {}", args.compare.as_deref().unwrap_or(""))
        })?),
        None => None,
    };
    let diff = match &reference_img {
        Some(r) if args.diff.is_some() => Some(AnyImage::Srgb8(compare::diff_any(
            &img,
            r,
            compare::DIFF_GAIN,
        )?)),
        _ => None,
    };
    let image_on_stdout = output.as_ref().is_some_and(|(o, _)| o == crate::io::STDIO);
    // The image and the difference appear together or not at all: both are
    // written to their temporary files first, then both moved into place.
    let mut written = Vec::new();
    let mut write = |image: AnyImage, name: &str, format: ImageFormat| -> Result<()> {
        let mut out = crate::io::Output::create(name, true)?;
        image
            .encode_spent(format, PngOptions::GENERAL, &mut out)
            .map_err(|e| out.cause(e))
            .with_context(|| {
                let shown = if name == crate::io::STDIO {
                    "standard output"
                } else {
                    name
                };
                format!("writing {shown}")
            })?;
        written.push(out);
        Ok(())
    };
    if let Some((o, f)) = &output {
        write(img, o, *f)?;
    }
    if let (Some(d), Some(name)) = (diff, &args.diff) {
        write(d, name, super::output_format_8bit(None, name)?)?;
    }
    // Reports go to standard output unless the image does, and before the
    // files take their names: a report that cannot be written (`>/dev/full`)
    // fails the run with the old files in place.
    let mut text = String::new();
    if args.json {
        let mut obj = super::json_head(TOOL);
        if let Some(m) = &metrics {
            obj.insert("compare".into(), serde_json::to_value(m)?);
        }
        if let Some(r) = &residual {
            obj.insert("reference".into(), serde_json::to_value(r)?);
        }
        if let Some(e) = &estimated {
            obj.insert("estimated".into(), serde_json::to_value(e)?);
        }
        text = serde_json::to_string_pretty(&obj)? + "\n";
    } else {
        if let Some(m) = &metrics {
            text.push_str(&m.report());
        }
        if let Some(r) = &residual {
            // Without --json the reference note is diagnostic: standard error.
            eprintln_or_drop!(
                "{TOOL}: reference: error estimate at most {:.3e} linear, {} code(s) in 8 bits, {} pixel(s) not certain ({} strips/pixel over the events)",
                r.max_linear, r.max_codes, r.uncertain_pixels, r.lines
            );
        }
    }
    if !text.is_empty() {
        print_report(&text, image_on_stdout)?;
    }
    for out in written {
        out.commit()?;
    }
    Ok(())
}

/// `--fps N`: a whole number of frames per second, 1 to 65535 (an APNG
/// frame's delay is 1/N s exactly). `29.97` was refused as "invalid digit
/// found in string".
fn parse_fps(text: &str) -> std::result::Result<u16, String> {
    match text.parse::<u16>() {
        Ok(0) => Err("0 frames per second: expected 1 to 65535".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!(
            "`{text}`: expected a whole number of frames per second, 1 to 65535"
        )),
    }
}

/// `--reference-samples N`: a multiple of 3 from 3 to 3000. The reference
/// takes its strips in threes (`reference::render`), so 4 and 5 drew what
/// 3 does while the report said 5 (a hostile-input review).
fn parse_reference_samples(text: &str) -> std::result::Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if (3..=3000).contains(&n) && n % 3 == 0 => Ok(n),
        Ok(n) if (3..=3000).contains(&n) => Err(format!(
            "{n} is not a multiple of 3 (the strips come in threes: {} or {})",
            n / 3 * 3,
            n / 3 * 3 + 3
        )),
        Ok(n) => Err(format!("{n} is not in 3..=3000")),
        Err(_) => Err(format!("`{text}` is not a whole number")),
    }
}

/// The bytes of an image to measure (`--compare`, `--image`), decoded
/// (`crate::io::decode_any`) at the depth it has: 8- or 16-bit sRGB, or a
/// PFM's linear light.
fn read_picture(name: &str) -> Result<Vec<u8>> {
    Ok(read_input(name, crate::io::InputKind::ImageOrPfm)?)
}

/// The widest frame number a pattern may ask for: 255, the longest file
/// name (`NAME_MAX`). Wider made no name, and over 65,535 `format!` panicked.
const MAX_FRAME_WIDTH: usize = 255;

/// A frame-number conversion in an output name, as printf reads it: `%d`,
/// `%Nd` (padded with spaces) or `%0Nd` (with zeros), `%%` being a literal
/// `%`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct FrameSlot {
    /// The bytes of the name it takes, `%` to `d`: `start..end`.
    start: usize,
    end: usize,
    /// `N` (0 for `%d`), saturated for a huge N.
    width: usize,
    zero: bool,
}

/// The frame-number conversions of an output name, in order (a name that is
/// not a pattern has none; `-o f%d%d.png` two, which is refused).
fn frame_slots(pattern: &str) -> Vec<FrameSlot> {
    let bytes = pattern.as_bytes();
    let (mut slots, mut i) = (Vec::new(), 0);
    while i < bytes.len() {
        if bytes[i] != b'%' {
            i += 1;
            continue;
        }
        if bytes.get(i + 1) == Some(&b'%') {
            i += 2;
            continue;
        }
        let digits = bytes[i + 1..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        let end = i + 1 + digits;
        if bytes.get(end) == Some(&b'd') {
            let n = &pattern[i + 1..end];
            slots.push(FrameSlot {
                start: i,
                end: end + 1,
                width: n
                    .parse()
                    .unwrap_or(if digits == 0 { 0 } else { usize::MAX }),
                zero: n.starts_with('0'),
            });
        }
        i = end.max(i + 1);
    }
    slots
}

/// The width `N` of the one `%d` or `%0Nd` in an output name; `None` when
/// the name has no such pattern, or more than one.
fn frame_width(pattern: &str) -> Option<usize> {
    match frame_slots(pattern)[..] {
        [FrameSlot { width, .. }] => Some(width),
        _ => None,
    }
}

/// The output name's one `%d` or `%0Nd` replaced by the frame number and
/// each `%%` by `%`; `None` when the name has no such pattern, more than one,
/// or one wider than `MAX_FRAME_WIDTH`.
pub fn frame_name(pattern: &str, k: u64) -> Option<String> {
    let [slot] = frame_slots(pattern)[..] else {
        return None;
    };
    let width = Some(slot.width).filter(|&w| w <= MAX_FRAME_WIDTH)?;
    let num = if slot.zero {
        format!("{k:0width$}")
    } else {
        format!("{k:width$}")
    };
    let literal = |s: &str| s.replace("%%", "%");
    Some(format!(
        "{}{num}{}",
        literal(&pattern[..slot.start]),
        literal(&pattern[slot.end..])
    ))
}

/// Below this many pixels of summed polygon area, a frame of a non-empty
/// stream "draws almost nothing": less than one pixel's worth of ink is
/// far likelier a wrong camera or scale than an intended picture.
const ALMOST_NOTHING_PX: f64 = 1.0;

/// Where a [`crate::scene::SceneError`] came from: reading names the
/// stream in its errors, projecting does not.
#[derive(PartialEq)]
enum Stage {
    Read,
    Project,
}

/// A scene's error as the tool says it: named by its input, and a scene
/// past `--max-polygons` (when read, or when a quadric's slices and stacks
/// are chosen for the view) says which flag raises the limit.
fn scene_error(args: &Args, e: crate::scene::SceneError, stage: Stage) -> anyhow::Error {
    let name = display_name(&args.input);
    match e {
        crate::scene::SceneError::TooMuchWork { .. } => {
            anyhow::anyhow!("{name}: {e} (--max-polygons raises it)")
        }
        e if stage == Stage::Project => anyhow::Error::from(e).context(name.to_string()),
        e => e.into(),
    }
}

/// Warns when frame `k` draws nothing, or almost nothing, of a non-empty
/// stream, naming what became of its polygons (an all-background image with
/// exit 0 is the commonest silent mistake: a 3D scene without a camera).
fn warn_if_blank(args: &Args, (view, camera_given): (&View, bool), k: u64, tally: &raster::Tally) {
    let total = tally.total();
    if total == 0 || tally.drawn_area >= ALMOST_NOTHING_PX {
        return;
    }
    let plural = |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let polygons = plural(total, "polygon", "polygons");
    let mut what = if tally.drawn == 0 {
        format!("frame {k} draws nothing: of {polygons}, ")
    } else {
        format!(
            "frame {k} draws almost nothing: {} drawn {} {:.2} pixels in all; of {polygons}, ",
            tally.drawn,
            if tally.drawn == 1 { "covers" } else { "cover" },
            tally.drawn_area,
        )
    };
    let culled = format!("culled (--cull {})", cull_name(args.cull));
    let reasons = [
        (tally.outside, ["lies", "lie"], "outside the view volume"),
        (tally.culled, ["was", "were"], culled.as_str()),
        (
            tally.no_area,
            ["has", "have"],
            "no area on screen (edge-on)",
        ),
        (
            tally.not_finite,
            ["has", "have"],
            "a coordinate that overflows",
        ),
    ];
    let mut why: Vec<String> = reasons
        .iter()
        .filter(|(n, _, _)| *n > 0)
        .map(|&(n, [one, many], what)| format!("{} {what}", plural(n, one, many)))
        .collect();
    if why.is_empty() {
        why.push("none is lost: they are that small on screen".to_string());
    }
    what.push_str(&why.join(", "));
    if tally.outside > 0 && !camera_given {
        what.push_str(&format!(
            "; no camera was given, and the default (--ortho2 0,{},0,{}) shows only z in [-1, 1]: \
             give --camera FILE, or --perspective and --lookat",
            view.width, view.height
        ));
    }
    crate::cli::warn(TOOL, what);
}

/// The `--cull` spelling of `cull`.
fn cull_name(cull: Cull) -> String {
    use clap::ValueEnum;
    cull.to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}

/// Renders the frames of an animation from one reading of the scene: the
/// objects are read (and their patterns loaded) once, and each frame only
/// projects and resolves. With --frame K only frame K is drawn. The last
/// frame (the only one with --frame K) frees the scene as it is projected
/// ([`Scene::into_frame`]).
fn render_frames(
    args: &Args,
    how: &DrawOptions,
    scene: Scene,
    (view, camera_given): (&View, bool),
    bg: &raster::Background,
    (format, encoding): (ImageFormat, crate::io::Encoding),
    inputs: &[std::path::PathBuf],
) -> Result<()> {
    let pattern = args.output.as_deref().expect("checked by run_in_pool");
    let frames: Vec<u64> = match args.frame {
        Some(k) => vec![k],
        None => (0..args.frames).collect(),
    };
    let mut apng = None;
    // `-o -`: every frame to one standard output, in order.
    let mut stream = (pattern == crate::io::STDIO && !args.animate)
        .then(|| crate::io::Output::create(pattern, true))
        .transpose()?;
    // --json: every frame's report, printed as one document when all frames
    // are written (a document per frame would not parse as one JSON value).
    let mut frame_reports = Vec::new();
    // Named once: a transform's error already says "at frame k".
    let at_frame = |e: crate::scene::SceneError, k: u64| {
        let e = scene_error(args, e, Stage::Project);
        if format!("{e:#}").contains(&format!("at frame {k}")) {
            e
        } else {
            e.context(format!("frame {k}"))
        }
    };
    // Every frame's transforms before any frame is written: one failing at
    // frame K replaced frames 0 to K-1 first.
    if frames.len() > 1 && scene.is_animated() {
        for &k in &frames {
            scene.check_transforms_at(k).map_err(|e| at_frame(e, k))?;
        }
    }
    let bar = args.progress.bar(TOOL);
    bar.phase("frames", frames.len() as u64);
    // Kept while a frame is still to come; the last one frees it.
    let mut scene = Some(scene);
    let last = frames.len().saturating_sub(1);
    for (i, k) in frames.into_iter().enumerate() {
        let name = frame_name(pattern, k).unwrap_or_else(|| pattern.to_string());
        // Each frame's own name, before it is drawn (`-o frame-%04d.png`
        // over an input frame-0003.png).
        super::refuse_replacing_read_files(&[("-o", Some(&name))], inputs)?;
        let t0 = std::time::Instant::now();
        let kept = "the scene is kept until the last frame";
        let projected = if i == last {
            scene.take().expect(kept).into_frame(view, how, k)
        } else {
            scene.as_ref().expect(kept).project_tallied(view, how, k)
        };
        let (polys, tally) = projected.map_err(|e| at_frame(e, k))?;
        warn_if_blank(args, (view, camera_given), k, &tally);
        let t1 = std::time::Instant::now();
        let rendered = scene::render_encoded(
            &polys,
            bg,
            view,
            args.aa,
            &crate::progress::Silent,
            encoding,
        );
        let estimated = Estimated::of(&rendered, &polys);
        if let Some(e) = &estimated {
            e.warn(&format!("frame {k}: "));
        }
        if args.json {
            let mut o = serde_json::Map::new();
            o.insert("frame".into(), k.into());
            if let Some(e) = &estimated {
                o.insert("estimated".into(), serde_json::to_value(e)?);
            }
            frame_reports.push(serde_json::Value::Object(o));
        }
        let img = rendered.image;
        let t2 = std::time::Instant::now();
        if args.animate {
            let AnyImage::Srgb8(img) = img else {
                unreachable!("--animate writes 8-bit (--depth conflicts with it)")
            };
            if apng.is_none() {
                let frames = u32::try_from(args.frames).context("too many frames for an APNG")?;
                apng = Some(crate::io::ApngWriter::create(
                    pattern,
                    img.width,
                    img.height,
                    img.channels,
                    frames,
                    args.fps,
                )?);
            }
            apng.as_mut().expect("created above").push(&img)?;
        } else if let Some(out) = stream.as_mut() {
            img.encode_spent(format, PngOptions::GENERAL, out)
                .map_err(|e| out.cause(e))
                .context("writing standard output")?;
        } else {
            img.save_spent(&name, format, PngOptions::GENERAL)?;
        }
        if args.timings {
            eprintln_or_drop!(
                "{TOOL}: timings: frame {k}: project {:.4} s, render {:.4} s, write {:.4} s ({} polygons)",
                (t1 - t0).as_secs_f64(),
                (t2 - t1).as_secs_f64(),
                t2.elapsed().as_secs_f64(),
                polys.len()
            );
        }
        bar.advance(1);
    }
    if let Some(a) = apng {
        a.finish()?;
    }
    let on_stdout = stream.is_some();
    if let Some(out) = stream {
        out.commit()?;
    }
    drop(bar);
    if args.json {
        let doc = super::json_document(TOOL, "frames", frame_reports);
        let text = serde_json::to_string_pretty(&doc)? + "\n";
        print_report(&text, on_stdout)?;
    }
    Ok(())
}

/// Prints a report on standard output, or on standard error when the image
/// itself goes to standard output.
fn print_report(text: &str, image_on_stdout: bool) -> Result<()> {
    if image_on_stdout {
        return super::write_report_to_stderr(text);
    }
    // The image has its file (to be) already: -o is no way round.
    super::check_stdout(REPORT_ON_STDOUT)?;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .context("writing standard output")
}

#[cfg(test)]
mod frame_name_tests {
    use super::frame_name;

    /// printf's reading: one conversion, `%%` a literal `%`, any other `%`
    /// kept as it is; two conversions or none make no pattern.
    #[test]
    fn a_frame_name_replaces_its_one_conversion_and_unescapes_percents() {
        for (pattern, name) in [
            ("f%d.png", Some("f7.png")),
            ("f%04d.png", Some("f0007.png")),
            ("f%3d.png", Some("f  7.png")),
            ("100%%-%d.png", Some("100%-7.png")),
            ("%d%%", Some("7%")),
            ("a%sb%02d", Some("a%sb07")),
            ("f%%d.png", None),
            ("f%d%d.png", None),
            ("plain.png", None),
            ("trailing%", None),
            ("f%0256d.png", None),
        ] {
            assert_eq!(frame_name(pattern, 7).as_deref(), name, "{pattern}");
        }
    }
}
