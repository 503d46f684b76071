//! `polyfill3`: partition 3D polygons into texture point polygons (the thesis's
//! `polcolorf3`, ch. IV, with the "object" placement of docs/stream-format.md).

use crate::cli::usage_bail;
use crate::geom::merge::Merge;
use crate::geom::plane::DEFAULT_PLANARITY_TOL;
use crate::io::{display_name, Output, STDIO};
use crate::raster::Cull;
use crate::scene::polyfill::{
    partition_stream, Compat, PartitionOptions, DEFAULT_MAX_POLYGONS, DEFAULT_TOLERANCE,
};
use crate::stream;
use crate::view::ViewVolume;
use anyhow::{Context, Result};
use clap::Parser;
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::time::Instant;

const EXAMPLES: &str = "\
Examples:
  polyfill3 scene.json -o cells.json
      Partition every polygon of scene.json that has a \"pattern\".
  polyfill3 --pattern brick.pat --incr 2 --horz -5 faces.json
      Cut every polygon of faces.json that has no pattern of its own with
      brick.pat, 2 units a texel, shifted 5 texels left (as the thesis's demo2
      places pyr.pat); the placement also fills in what a \"pattern\" leaves out.
  polyfill3 --merge=blocks scene.json | scene-render --camera cam.json -o out.png -
      Join equal whole cells into rectangles (--merge alone: runs along a
      row): fewer polygons and vertices over the same region. The camera is
      scene-render's: the cells are in world coordinates.
  polyfill3 --camera cam.json --cull=none scene.json | scene-render --camera cam.json -o seen.png -
      Leave out the cells this camera cannot see, both faces kept, as
      scene-render draws them by default: the same picture from fewer records.
  polyfill3 --compat thesis --incr 25 plain.json | wc -l
      The thesis's own loop, degenerate polygons included (Table 5.1).
  polyfill3 --uv scene.json | scene-render --camera cam.json -o out.png -
      Keep each polygon whole, with its \"object\" placement as \"uv\"
      coordinates (for renderers that take texture coordinates).";

#[derive(Parser, Debug)]
#[command(
    name = "polyfill3",
    version,
    about = "Partition 3D polygons into flat-coloured texture point polygons",
    long_about = "Reads a polygon stream (patkit-stream(5): a JSON array or NDJSON), and writes, for \
every polygon with a \"pattern\" in \"object\" mode, one flat-coloured polygon per \
non-transparent texel cell it covers, in the polygon's plane and winding: the \
thesis's polcolorf3. Each output record keeps the input's other fields, with \
\"vertices\" (always [x,y,z]), \"color\" (the texel's colour) and \"texel\": \
[column, row]. Patterns in \"screen\" or \"uv\" mode pass through unchanged.\n\n\
Fields no tool reads (ids, tags) come out in every record written exactly as \
written (123456789012345678901234567890, 1e2 and \"\\u00e9\" stay so), less \
the whitespace between their tokens; the fields the tools read are written \
as serde_json writes them (docs/polyfill3.md, \"Unknown fields\").\n\n\
--pattern FILE gives every polygon record (vertices, rect, circle or arc) that \
has neither a \"pattern\" nor a \"stripe\" of its own the pattern FILE in \
\"object\" mode, placed by --incr, --rotate, --horz and --vert, inside objects \
too (such a record needs no \"color\" then); records with a pattern of their \
own keep it (the flags fill in only the \"file\" and placement fields it \
leaves out), stripes and quadrics are left as they are. Without --pattern, \
records without a pattern pass through unchanged.\n\n\
Objects and instances (docs/objects.md) stay intact: an object definition is \
written back with its records partitioned, once however many instances place \
it (the thesis's Fig. 5.1), and instances pass through unchanged. --cull does \
not apply inside objects.\n\n\
Placement (patkit-stream(5)): plane x along the edge vertex0->vertex1 rotated by \
\"rotate\" degrees counter-clockwise, y 90 degrees counter-clockwise from it \
seen from the front; texel column floor((x - xmin)/incr - horz) mod SIZE, row \
floor((y - ymin)/incr - vert) mod SIZE. Concave polygons are supported; a \
cell whose piece of a concave polygon falls apart gives one polygon per part. \
Only pieces with positive area are written, and neighbouring cells share \
their vertices bit for bit, except where a piece that rounding folded was \
mended: there the two may meet at a T-junction whose gap is within rounding \
(docs/polyfill3.md, The partition).\n\n\
--uv does not partition: each \"object\" polygon (rect, circle and arc \
flattened first) is written whole, with \"uv\" (its placement's texel \
coordinates at each vertex) and \"pattern\": {\"file\", \"mode\": \"uv\"}, \
so that a renderer with per-vertex texture coordinates (OpenGL) draws the \
same texture.\n\n\
Files named by the records written (pattern \"file\"s; a stripe's \"map\", \
\"colors\" and translation file), in objects too, are rewritten for a reader \
in another directory: on standard output as absolute paths without . or .. \
(the reader's directory is unknown), with -o FILE relative to FILE's \
directory, so that the output and the files it names move together. \
Everything else is copied as read.\n\n\
--json prints a summary (records, polygons, objects, instances, seconds) to standard error, \
one JSON object described in docs/json.md.",
    after_help = EXAMPLES
)]
pub struct Args {
    /// Input polygon stream, `-` for standard input.
    #[arg(default_value = "-")]
    pub input: String,
    /// Output file (NDJSON), `-` for standard output.
    #[arg(short, long, default_value = "-")]
    pub output: String,
    /// Pattern, in "object" mode, for every polygon record without a
    /// "pattern" or "stripe" of its own, and the file of those whose
    /// "pattern" names none (relative to the current directory).
    #[arg(long, value_name = "FILE")]
    pub pattern: Option<PathBuf>,
    /// Side of one texel in world units, for records without "incr".
    #[arg(long, default_value_t = 1.0)]
    pub incr: f64,
    /// Degrees counter-clockwise of the pattern's x from the first edge, for
    /// records without "rotate".
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub rotate: f64,
    /// Shift of the pattern right in texels, for records without "horz".
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub horz: f64,
    /// Shift of the pattern up in texels, for records without "vert".
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub vert: f64,
    /// Join same-coloured whole cells into one polygon (the record gets
    /// "cells": how many): runs along a row (HOW rows, the default), or
    /// rectangles of them, runs of consecutive rows over the same columns
    /// (HOW blocks: fewer vertices, the same region). Every grid corner on
    /// the polygon's sides is kept, so neighbours meet it vertex to vertex.
    #[arg(
        long,
        value_enum,
        value_name = "HOW",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "rows"
    )]
    pub merge: Option<Merge>,
    /// Reproduce another algorithm: `thesis` is the thesis's loop, degenerate
    /// polygons included (horz and vert must be integers).
    #[arg(long, value_enum)]
    pub compat: Option<Compat>,
    /// Largest distance of a vertex from the polygon's plane, relative to the
    /// polygon's size (bounding-box diagonal).
    #[arg(long, default_value_t = DEFAULT_PLANARITY_TOL)]
    pub planarity_tol: f64,
    /// Refuse a job that would make more polygons than this: texel cells
    /// (estimated from each polygon's area / incr² before its cells are
    /// written) and quadric triangles. Records passed through unchanged are
    /// the input's own and not counted.
    #[arg(long, default_value_t = DEFAULT_MAX_POLYGONS)]
    pub max_polygons: u64,
    /// Largest distance of a circle's or arc's chords from the true curve, in
    /// world units (for "circle" and "arc" records); also sets the slices and
    /// stacks a quadric record leaves out.
    #[arg(long, default_value_t = DEFAULT_TOLERANCE)]
    pub tolerance: f64,
    /// The camera for --cull: a camera file (patkit-camera(5)) or the same
    /// camera flags as scene-render's.
    #[command(flatten)]
    pub camera: super::camera::CameraArgs,
    /// Drop cells wholly outside the camera's view volume, and whole
    /// polygons turning it the FACES side (back, front, or none: keep both),
    /// before they are written: what `scene-render --cull FACES` with the
    /// same camera would not draw. --cull alone is --cull=back; the words
    /// back, front and none after it are its value (a file so named is
    /// ./none). Needs a camera.
    #[arg(
        long,
        value_enum,
        value_name = "FACES",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "back"
    )]
    pub cull: Option<Cull>,
    /// Do not partition: write each "object"-mode polygon whole (curves
    /// flattened) with its placement as per-vertex "uv" texel coordinates and
    /// "pattern": {"file": ABSOLUTE PATH, "mode": "uv"}, for renderers that
    /// take texture coordinates. --cull drops whole polygons.
    #[arg(long, conflicts_with_all = ["merge", "compat"])]
    pub uv: bool,
    /// Print a JSON summary to standard error: {"version": 1, "tool":
    /// "polyfill3", ...} (docs/json.md).
    #[arg(long)]
    pub json: bool,
    /// Write the make rule of the output: every file the run read (the
    /// input, the patterns, --camera, --pattern), as `cc -MD` does. Needs -o.
    #[arg(long, value_name = "FILE")]
    pub depfile: Option<String>,

    // The records are formatted on these workers, in batches, and written
    // in order (`scene::cell_writer`).
    #[command(flatten)]
    pub threads: super::ThreadArgs,

    #[command(flatten)]
    pub progress: super::progress::ProgressArgs,
}

/// Runs `polyfill3` on its pool of workers.
pub fn run(args: Args) -> Result<()> {
    args.threads.install(|| run_in_pool(args))?
}

/// Checks the flags, then runs the library's partition job.
fn run_in_pool(args: Args) -> Result<()> {
    if !(args.incr.is_finite() && args.incr > 0.0) {
        usage_bail!("--incr {}: expected a positive number", args.incr);
    }
    for (name, v) in [
        ("--rotate", args.rotate),
        ("--horz", args.horz),
        ("--vert", args.vert),
    ] {
        if !v.is_finite() {
            usage_bail!("{name} {v}: expected a finite number");
        }
    }
    if !(args.planarity_tol >= 0.0 && args.planarity_tol.is_finite()) {
        usage_bail!(
            "--planarity-tol {}: expected a number >= 0",
            args.planarity_tol
        );
    }
    if !(args.tolerance > 0.0 && args.tolerance.is_finite()) {
        usage_bail!("--tolerance {}: expected a positive number", args.tolerance);
    }
    if args.compat.is_some() && args.merge.is_some() {
        usage_bail!("--merge and --compat thesis cannot be combined: the thesis does not merge");
    }
    if args.pattern.as_deref() == Some(std::path::Path::new(STDIO)) {
        // Records written may name --pattern's file for the renderer (those
        // forwarded with their pattern, `--uv`), and --depfile lists it:
        // standard input has no name to give them. Before, `-` was looked
        // up as a file named `-`, and its error ("-: No such file or
        // directory") came at the first record that needed it.
        usage_bail!(
            "--pattern -: the pattern must be a file (records written may name it for the \
             renderer), not standard input"
        );
    }
    let pattern = args.pattern.as_ref().map(|p| p.to_string_lossy());
    let inputs = [
        ("the stream", Some(args.input.as_str())),
        ("--camera", args.camera.camera.as_deref()),
        ("--pattern", pattern.as_deref()),
    ];
    super::check_inputs(&inputs)?;
    let outputs = [
        ("-o", Some(args.output.as_str())),
        ("--depfile", args.depfile.as_deref()),
    ];
    super::refuse_replacing_inputs(&outputs, &inputs)?;
    let camera = args.camera.resolve()?;
    match (&camera, args.cull) {
        (Some(_), None) => {
            usage_bail!("a camera is only used by --cull: add --cull, or leave out the camera flags")
        }
        (None, Some(_)) => usage_bail!(
            "--cull needs a camera: --camera FILE, or camera flags such as --perspective and --lookat"
        ),
        _ => {}
    }
    if args.depfile.is_some() && args.output == STDIO {
        usage_bail!("--depfile needs -o FILE: the make rule names the output as its target");
    }
    super::refuse_shared_outputs(&[
        ("-o", Some(args.output.as_str())),
        ("--depfile", args.depfile.as_deref()),
    ])?;
    if let Some(depfile) = &args.depfile {
        // Before the work, as scene-render checks it.
        crate::io::check_output(depfile, false)?;
    }
    let volume = match camera {
        Some(cam) => {
            if cam.aspect_from_image {
                anyhow::bail!(
                    "{}: perspective.aspect \"auto\" is the image's width/height, and \
                     polyfill3 draws no image: give the ratio as a number",
                    args.camera
                        .camera
                        .as_deref()
                        .map_or("--perspective", display_name)
                );
            }
            Some(ViewVolume::new(&cam))
        }
        None => None,
    };
    let start = Instant::now();
    let source = display_name(&args.input).to_string();
    let base = stream::base_dir(&args.input);
    let bar = args.progress.bar("polyfill3");
    let reader: Box<dyn BufRead + Send> = if args.input == STDIO {
        let stdin = Box::new(BufReader::with_capacity(1 << 16, std::io::stdin()));
        bar.reading(&source, 0, stdin)
    } else {
        // The other tools' opening: an empty name or a directory is said so.
        let f = crate::io::open_file(&args.input)?;
        let len = f.metadata().map(|m| m.len()).unwrap_or(0);
        bar.reading(&source, len, Box::new(BufReader::with_capacity(1 << 16, f)))
    };
    if args.output == STDIO {
        super::check_stdout(super::USE_OUTPUT_FILE)?;
    }
    let out = Output::create(&args.output, false)?;
    let options = PartitionOptions {
        pattern: args.pattern.clone(),
        incr: args.incr,
        rotate: args.rotate,
        horz: args.horz,
        vert: args.vert,
        merge: args.merge,
        compat: args.compat,
        planarity_tol: args.planarity_tol,
        max_polygons: args.max_polygons,
        tolerance: args.tolerance,
        volume,
        cull: args.cull.unwrap_or(Cull::Back),
        uv: args.uv,
        refs: stream::RefTarget::for_output(&args.output)
            .with_context(|| format!("{}: cannot name files relative to it", args.output))?,
    };
    let mut warn = |message: String| super::warn("polyfill3", message);
    let (out, s) = partition_stream(reader, &source, &base, out, &options, &mut warn).map_err(
        |e| match e {
            // The output's error, whatever record was being written.
            crate::scene::PartitionError::Write(io) => {
                anyhow::Error::from(io).context(match args.output.as_str() {
                    STDIO => "writing standard output".to_string(),
                    file => format!("writing {file}"),
                })
            }
            e => e.into(),
        },
    )?;
    drop(bar);
    super::refuse_replacing_read_files(&outputs, &[&s.files[..], &s.named[..]].concat())?;
    // The make rule first: a rule that cannot be written leaves the old
    // output in place, where the output written first would be a target
    // newer than its files with no rule naming them.
    if let Some(depfile) = &args.depfile {
        let mut deps = vec![args.input.clone()];
        deps.extend(args.camera.camera.iter().cloned());
        deps.extend(args.pattern.iter().map(|p| super::dep_name(p)));
        deps.extend(s.files.iter().map(|p| super::dep_name(p)));
        super::write_depfile(depfile, std::slice::from_ref(&args.output), &deps)?;
    }
    if args.json {
        // Before the output is committed: a report that cannot be written
        // leaves the old output, as scene-render's does.
        super::write_report_to_stderr(&format!(
            "{}\n",
            serde_json::json!({
                "version": super::JSON_VERSION,
                "tool": "polyfill3",
                "input": source,
                "records": s.records,
                "passed_through": s.passed,
                "partitioned": s.partitioned,
                "culled": s.culled,
                "polygons": s.polygons,
                "objects": s.objects,
                "instances": s.instances,
                "seconds": start.elapsed().as_secs_f64(),
            })
        ))?;
    }
    out.commit()?;
    Ok(())
}
