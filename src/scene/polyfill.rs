//! The partition job of `polyfill3` (the thesis's `polcolorf3`, ch. IV, with
//! docs/stream-format.md "object" placement): a stream's patterned polygons cut into texture
//! point polygons, one per texel cell, written as NDJSON records by
//! [`CellWriter`]. Objects stay objects (a face is partitioned once and
//! placed by its instances, Fig. 5.1); records without an object-mode pattern
//! pass through unchanged, unless [`PartitionOptions::pattern`] gives those
//! without any texture one.

pub use super::cell_writer::CellWriter;
use super::error::{CellsError, PartitionError};
use crate::error::OptionError;
use crate::geom::merge::Merge;
use crate::geom::partition::{estimate_cells, simple_on_plane, thesis_partition};
use crate::geom::plane::DEFAULT_PLANARITY_TOL;
use crate::geom::{map_to_plane, outline, Grid, Partitioner, Placement, Shape};
use crate::pat::Pattern;
use crate::raster::Cull;
use crate::stream::{self, Instance, Item, ObjectDef, Objects, PatternMode, Record};
use crate::texture::map::object_uv;
use crate::texture::state::{TextureState, KEYS as STATE_KEYS};
use crate::view::ViewVolume;
use glam::DVec3;
use serde_json::Value;
use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Which algorithm partitions the polygons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Compat {
    /// The thesis's loop (Fig. 4.7): accumulated grid, inclusive bounds,
    /// degenerate polygons along the far edges.
    Thesis,
}

/// What the partition does with each record. The placement fields are the
/// defaults for records whose `"pattern"` leaves them out.
#[derive(Clone, Debug)]
pub struct PartitionOptions {
    /// Pattern file for records whose "pattern" names no "file", and, in
    /// object mode, for every polygon record (not a quadric) with neither a
    /// "pattern" nor a "stripe" of its own. Default value: none (a
    /// "pattern" without a "file" is an error; polygons without a pattern
    /// pass through).
    pub pattern: Option<PathBuf>,
    /// Side of one texel in world units. Default value: 1.
    pub incr: f64,
    /// Degrees counter-clockwise of the pattern's x from the first edge.
    /// Default value: 0.
    pub rotate: f64,
    /// Shift of the pattern right, in texels. Default value: 0.
    pub horz: f64,
    /// Shift of the pattern up, in texels. Default value: 0.
    pub vert: f64,
    /// Join same-coloured whole cells into one polygon: runs along a row,
    /// or rectangles of them ([`Merge`]). Default value: none (each cell its
    /// own polygon).
    pub merge: Option<Merge>,
    /// Reproduce another algorithm. Default value: none (the exact partition).
    pub compat: Option<Compat>,
    /// Largest distance of a vertex from the polygon's plane, relative to its
    /// size. Default value: [`DEFAULT_PLANARITY_TOL`].
    pub planarity_tol: f64,
    /// Most polygons the job may write (estimated from each polygon's area /
    /// incr² before its cells are written). Default value: 50,000,000.
    pub max_polygons: u64,
    /// Largest distance of a circle's or arc's chords from the true curve, in
    /// world units; also the quadric tessellation's. Default value: 0.01.
    pub tolerance: f64,
    /// Drop cells wholly outside this view volume, and whole polygons
    /// turning it the face [`Self::cull`] names. Default value: none.
    pub volume: Option<ViewVolume>,
    /// With a [`Self::volume`], the faces dropped as well: what
    /// `scene-render --cull` with the same value and camera would not draw.
    /// A polygon within [`crate::view::EDGE_ON_SINE`] of edge-on is kept
    /// whatever its face (the renderer's rounding may draw it).
    /// [`Cull::None`] drops only what lies outside the volume. Default value:
    /// [`Cull::Back`].
    pub cull: Cull,
    /// Do not partition: write each object-mode polygon whole with its
    /// placement as per-vertex "uv" texel coordinates. Default value: false.
    pub uv: bool,
    /// How the files that forwarded records name (patterns, stripe maps and
    /// tables) are written: the output is read from another directory than
    /// the input, so each is rewritten absolute or relative to the output's
    /// directory ([`stream::RefTarget::for_output`]). Default value:
    /// [`stream::RefTarget::Absolute`].
    pub refs: stream::RefTarget,
}

impl PartitionOptions {
    /// Every field at its default value (see each field).
    pub const DEFAULT: PartitionOptions = PartitionOptions {
        pattern: None,
        incr: 1.0,
        rotate: 0.0,
        horz: 0.0,
        vert: 0.0,
        merge: None,
        compat: None,
        planarity_tol: DEFAULT_PLANARITY_TOL,
        max_polygons: DEFAULT_MAX_POLYGONS,
        tolerance: DEFAULT_TOLERANCE,
        volume: None,
        cull: Cull::Back,
        uv: false,
        refs: stream::RefTarget::Absolute,
    };
}

impl Default for PartitionOptions {
    fn default() -> Self {
        PartitionOptions::DEFAULT
    }
}

/// The default [`PartitionOptions::max_polygons`].
pub const DEFAULT_MAX_POLYGONS: u64 = 50_000_000;

/// The default [`PartitionOptions::tolerance`], world units.
pub const DEFAULT_TOLERANCE: f64 = 0.01;

/// What a partition job did (`polyfill3 --json` prints it).
#[derive(Default, Debug, Clone, PartialEq, Eq)]
pub struct Summary {
    /// Records read, inside objects included.
    pub records: u64,
    /// Records passed through unchanged (no object-mode pattern).
    pub passed: u64,
    /// Records partitioned (or written whole with "uv").
    pub partitioned: u64,
    /// Records dropped by the view volume.
    pub culled: u64,
    /// Polygons written.
    pub polygons: u64,
    /// Object definitions.
    pub objects: u64,
    /// Instances.
    pub instances: u64,
    /// The files read besides the stream, each once, in the order first
    /// read: pattern files and the meshes' OBJ and MTL files, what a build
    /// system must know the output depends on (`polyfill3 --depfile`).
    pub files: Vec<PathBuf>,
    /// The files records name that the output names too (forwarded, read
    /// or not: a screen pattern is passed on unread), each once: an output
    /// must not be put in their place.
    pub named: Vec<PathBuf>,
}

/// `error` of record `index` of `input` (`within` an object's records): a
/// [`PartitionError::Record`], except a failed write, which is the output's
/// and not the record's (`polyfill3 -o /dev/full` said `scene.json: record
/// 0: No space left on device`, a hostile-input review).
fn record_error(
    error: CellsError,
    input: &str,
    index: usize,
    within: Option<(String, usize)>,
) -> PartitionError {
    match error {
        CellsError::Write(e) => PartitionError::Write(e),
        error => PartitionError::Record {
            input: input.to_string(),
            index,
            within,
            error: Box::new(error),
        },
    }
}

/// Partitions the stream `reader` (named `source` in errors, its files
/// resolved against `base`) into `out`. `warn` receives each warning once, as
/// it happens (records whose pattern mode is not partitioned, the first
/// polygon no larger than one texel ([`super::CoarseTexture`]), texture state
/// that partitioning drops, unknown keys in a `"pattern"` or `"stripe"`:
/// [`super::keys`]). Returns the
/// output, flushed, and the counts.
pub fn partition_stream<W: Write>(
    reader: Box<dyn BufRead + Send>,
    source: &str,
    base: &Path,
    out: W,
    options: &PartitionOptions,
    warn: &mut dyn FnMut(String),
) -> Result<(W, Summary), PartitionError> {
    let mut job = Job {
        args: options,
        base: base.to_path_buf(),
        patterns: HashMap::new(),
        ids: stream::FileIds::default(),
        partitioner: Partitioner::new(),
        writer: CellWriter::new(out),
        volume: options.volume,
        summary: Summary::default(),
        warned_mode: false,
        warned_coarse: false,
        warned_state: false,
        unknown: super::keys::UnknownKeys::default(),
        warn,
    };
    // Objects and instances are kept as they are (Fig. 5.1: a face is
    // partitioned once and placed four times), not expanded into copies.
    let mut objects = Objects::default();
    // With --pattern, a polygon record needs no colour of its own: it
    // takes the pattern (`record`).
    let options = stream::ReadOptions {
        bare_records: job.args.pattern.is_some(),
    };
    stream::for_each_item_with(reader, source, base, &options, |item| match item {
        Item::Record(rec) => {
            let index = rec.index;
            job.record(rec)
                .map_err(|error| record_error(error, source, index, None))
        }
        Item::Object(def) => {
            objects
                .define(def.skeleton())
                .map_err(|e| e.named(source))?;
            job.object(def, source)
        }
        Item::Instance(inst) => {
            objects.check_instance(&inst).map_err(|e| e.named(source))?;
            Ok(job.instance(&inst)?)
        }
        // The renderer's: passed through as written.
        Item::Light(light) => Ok(job.writer.pass(&light.fields)?),
    })?;
    let summary = job.summary.clone();
    Ok((job.writer.into_inner()?, summary))
}

struct Job<'a, W: Write> {
    args: &'a PartitionOptions,
    base: PathBuf,
    /// Each pattern read, keyed by its file, not its spelling
    /// ([`stream::FileIds`]).
    patterns: HashMap<PathBuf, Rc<Pattern>>,
    ids: stream::FileIds,
    partitioner: Partitioner,
    writer: CellWriter<W>,
    volume: Option<ViewVolume>,
    summary: Summary,
    warned_mode: bool,
    /// Whether a polygon no larger than a texel has been warned about (once
    /// per run: a stream may have millions).
    warned_coarse: bool,
    warned_state: bool,
    unknown: super::keys::UnknownKeys,
    warn: &'a mut dyn FnMut(String),
}

impl<W: Write> Job<'_, W> {
    /// Where a record's pattern file is: its "file" resolved against the
    /// stream's directory, else [`PartitionOptions::pattern`].
    fn pattern_path(&self, file: Option<&str>) -> Result<PathBuf, OptionError> {
        match (file, &self.args.pattern) {
            (Some(f), _) => Ok(stream::resolve(&self.base, f)),
            (None, Some(p)) => Ok(p.clone()),
            (None, None) => Err(OptionError::new(
                "pattern: no \"file\" in the record and no ",
                "pattern",
                " given",
            )),
        }
    }

    fn pattern(&mut self, file: Option<&str>) -> Result<Rc<Pattern>, CellsError> {
        let path = self.pattern_path(file)?;
        if let Some(p) = self.patterns.get(self.ids.file(&path)) {
            return Ok(p.clone());
        }
        let name = path.display().to_string();
        let opened = crate::io::open_path(&path)
            .map_err(|e| CellsError::Pattern(crate::text::ParseError::io(&name, e)))?;
        // An image texture (scene-render draws those) has no palette for
        // the cells' colours and merging: a .pat is needed here.
        if crate::io::is_image(&opened.start) {
            return Err(CellsError::Option(OptionError::new(
                format!(
                    "{name}: an image; polygons are cut into the texels of a .pat \
                     only (scene-render draws images): make one with pat-from-image, \
                     or give one with "
                ),
                "pattern",
                "",
            )));
        }
        // Read as a stream: a pattern may be larger than a file read whole.
        let p = Pattern::read_from(&mut opened.into_reader(), &name);
        let p = Rc::new(p.map_err(CellsError::Pattern)?);
        let file = self.ids.file(&path).to_path_buf();
        self.patterns.insert(file, p.clone());
        self.summary.files.push(path);
        Ok(p)
    }

    /// Writes an object definition back as an object whose `"records"` are
    /// its records partitioned (once, however many instances it gets), and
    /// its instances unchanged; the definition's other fields keep their
    /// order. Culling does not apply inside objects: where an instance puts
    /// them is not known here.
    fn object(&mut self, def: ObjectDef, source: &str) -> Result<(), PartitionError> {
        self.summary.objects += 1;
        for f in &def.files {
            if !self.summary.files.contains(f) {
                self.summary.files.push(f.clone());
            }
        }
        self.writer.capture()?;
        let volume = self.volume.take();
        let result = self.object_items(&def, source);
        self.volume = volume;
        let body = self.writer.end_capture()?;
        result?;
        let mut line = Vec::with_capacity(body.len() + 64);
        line.push(b'{');
        for (i, (k, v)) in def.fields.iter().enumerate() {
            if i > 0 {
                line.push(b',');
            }
            serde_json::to_writer(&mut line, k).map_err(std::io::Error::from)?;
            line.push(b':');
            if k == "records" {
                line.push(b'[');
                let mut first = true;
                for rec in body.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
                    if !first {
                        line.push(b',');
                    }
                    first = false;
                    line.extend_from_slice(rec);
                }
                line.push(b']');
            } else {
                serde_json::to_writer(&mut line, v).map_err(std::io::Error::from)?;
            }
        }
        line.extend_from_slice(b"}\n");
        Ok(self.writer.pass_raw(&line)?)
    }

    fn object_items(&mut self, def: &ObjectDef, source: &str) -> Result<(), PartitionError> {
        for (i, item) in def.items.iter().enumerate() {
            match item {
                Item::Record(rec) => self.record(rec.clone()).map_err(|error| {
                    record_error(error, source, def.index, Some((def.name.clone(), i)))
                })?,
                Item::Instance(inst) => self.instance(inst)?,
                Item::Object(_) | Item::Light(_) => {
                    unreachable!("Objects::define rejects definitions and lights inside objects")
                }
            }
        }
        Ok(())
    }

    /// A quadric record becomes its triangles, each a uv-mode record (texture
    /// coordinates in texels of its pattern) that passes through like any
    /// uv record: the texture is placed by coordinates, not cut into texel
    /// polygons. Slices and stacks the record leaves out come from the
    /// tolerance (world units; there is no camera). The triangles count
    /// towards the polygon limit; culling does not apply. A quadric whose
    /// transform varies per frame passes through unchanged.
    fn quadric(&mut self, rec: &Record) -> Result<(), CellsError> {
        // A transform that varies per frame is scene-render's to evaluate:
        // expanding frame 0 here would freeze the animation, so the record
        // passes through unchanged (scene-render draws quadrics directly).
        if rec
            .fields
            .get("transform")
            .is_some_and(crate::geom::transform::Transform::is_animated)
        {
            self.summary.passed += 1;
            return Ok(self.writer.pass(&rec.fields)?);
        }
        let size = match &rec.pattern {
            Some(p) if p.mode != Some(PatternMode::Screen) => {
                Some(self.pattern(p.file.as_deref())?.size())
            }
            _ => None,
        };
        // The budget first, from the slices and stacks alone: nothing is
        // tessellated for a record that cannot be written.
        let over = |count: u64| {
            OptionError::new(
                format!("{count} triangles of the quadric would take the output past "),
                "max_polygons",
                format!(
                    " {} ({} written so far)",
                    self.args.max_polygons, self.summary.polygons
                ),
            )
        };
        let bound =
            stream::quadric_triangle_bound(rec, self.args.tolerance).expect("a quadric record");
        if self.summary.polygons.saturating_add(bound) > self.args.max_polygons {
            return Err(over(bound).into());
        }
        // Within the bound, so within the budget: each triangle is written
        // as it is made.
        let writer = &mut self.writer;
        let written = stream::for_each_quadric_triangle(rec, self.args.tolerance, size, |t| {
            writer.pass(&t).map_err(CellsError::from)
        })
        .expect("a quadric record")?;
        self.summary.polygons += written;
        self.summary.passed += 1;
        Ok(())
    }

    /// [`PartitionOptions::uv`]: writes the record whole, its docs/stream-format.md object placement turned
    /// into per-vertex texel coordinates by the same [`object_uv`] that
    /// `scene-render` uses for direct texturing, so both draw the same texture
    /// (texture coordinates are affine over a planar polygon, so the vertex
    /// values determine the whole map). The pattern "file" becomes an
    /// absolute path: the output may be read from another directory than the
    /// input's, against which a relative "file" resolved.
    fn forward_uv(
        &mut self,
        rec: &Record,
        pref: &stream::PatternRef,
        vertices: &[DVec3],
        place: Placement,
        rotate: f64,
    ) -> Result<(), CellsError> {
        // Loaded (once) only to report a missing or bad pattern here rather
        // than in the renderer.
        self.pattern(pref.file.as_deref())?;
        let uv = object_uv(vertices, place, rotate, self.args.planarity_tol)?;
        let uv = serde_json::json!(uv.iter().map(|t| [t.x, t.y]).collect::<Vec<_>>());
        let fields = self.whole(rec, vertices, Some(uv))?;
        self.summary.partitioned += 1;
        self.summary.polygons += 1;
        Ok(self.writer.pass(&fields)?)
    }

    /// A record that is not partitioned: unchanged, except with `uv` set,
    /// where every record comes out as a polygon (rect, circle and arc
    /// flattened within the tolerance) with an absolute pattern path, so that a
    /// renderer that only draws polygons can take the stream anywhere.
    fn pass_record(&mut self, rec: &Record) -> Result<(), CellsError> {
        if !self.args.uv {
            return Ok(self.writer.pass(&rec.fields)?);
        }
        let vertices = outline(&rec.shape, self.args.tolerance);
        let fields = self.whole(rec, &vertices, None)?;
        Ok(self.writer.pass(&fields)?)
    }

    /// `rec`'s fields for `uv` output: "vertices" set to `vertices` (curves
    /// dropped), the pattern "file" made absolute, and with `uv` given, the
    /// "uv" field set and the pattern put in "uv" mode (its object placement
    /// fields dropped: they no longer apply), or, for a record without a
    /// "pattern" (one that takes [`PartitionOptions::pattern`]), added.
    /// Other fields, in the pattern too, are kept (docs/stream-format.md).
    fn whole(
        &self,
        rec: &Record,
        vertices: &[DVec3],
        uv: Option<Value>,
    ) -> Result<stream::Fields, CellsError> {
        let mut fields = rec.fields.clone();
        let replaced = |k: &str| match k {
            "rect" | "circle" | "arc" | "vertices" => true,
            "uv" => uv.is_some(),
            _ => false,
        };
        fields.retain(|k, _| !replaced(k));
        if let Some(p) = fields.get_mut("pattern") {
            // A "file" of the record's own was forwarded with the record
            // (see `record`); --pattern stands in for none.
            let mut o = p.as_object().cloned().unwrap_or_default();
            if !o.contains_key("file") && self.args.pattern.is_some() {
                o.insert("file".into(), Value::String(self.forwarded_pattern()?));
            }
            if uv.is_some() {
                for key in ["incr", "rotate", "horz", "vert"] {
                    o.remove(key);
                }
                o.insert("mode".into(), Value::String("uv".into()));
            }
            *p = Value::Object(o);
        } else if uv.is_some() {
            // The record takes --pattern (see `record`).
            fields.insert(
                "pattern",
                serde_json::json!({"file": self.forwarded_pattern()?, "mode": "uv"}),
            );
        }
        fields.insert(
            "vertices",
            serde_json::json!(vertices.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>()),
        );
        if let Some(uv) = uv {
            fields.insert("uv", uv);
        }
        Ok(fields)
    }

    /// [`PartitionOptions::pattern`] as forwarded records name it.
    fn forwarded_pattern(&self) -> Result<String, CellsError> {
        let path = self.pattern_path(None)?;
        self.args
            .refs
            .path(&path)
            .map_err(|error| CellsError::PatternPath { path, error })
    }

    /// `rec` with the files it names rewritten for the output
    /// ([`PartitionOptions::refs`]); its typed view (the pattern the job
    /// loads) keeps them as read. Rewritten in place: a copy of the fields
    /// held every vertex twice more as JSON values while the record was cut
    /// (a third of polyfill3's peak on a polygon of 100,000 vertices).
    fn forwarded(&mut self, mut rec: Record) -> Result<Record, CellsError> {
        if stream::names_files(&rec.fields) {
            let named = &mut self.summary.named;
            stream::forward_file_refs(&mut rec.fields, &self.base, &self.args.refs, named)
                .map_err(|error| CellsError::PatternPath {
                    path: self.base.clone(),
                    error,
                })?;
        }
        Ok(rec)
    }

    /// An instance passes through unchanged: its object is partitioned once.
    fn instance(&mut self, inst: &Instance) -> std::io::Result<()> {
        self.summary.instances += 1;
        self.writer.pass(&inst.fields)
    }

    fn record(&mut self, rec: Record) -> Result<(), CellsError> {
        self.summary.records += 1;
        self.unknown.check(rec.index, &rec.fields, &mut self.warn);
        // Checked here, though only the renderer uses it, so that a bad
        // value is reported by the first tool that reads it.
        let state = match rec.fields.get("pattern") {
            Some(p) => TextureState::from_pattern(p).map_err(CellsError::TextureState)?,
            None => TextureState::default(),
        };
        let rec = self.forwarded(rec)?;
        if let Shape::Quadric(_) = rec.shape {
            return self.quadric(&rec);
        }
        // A polygon without a texture of its own takes --pattern, in object
        // mode; its "uv", if any, placed no pattern and does not count.
        let (pref, own) = match &rec.pattern {
            Some(p) => (p.clone(), true),
            None if self.args.pattern.is_some() && !rec.fields.contains_key("stripe") => (
                stream::PatternRef {
                    mode: Some(PatternMode::Object),
                    ..Default::default()
                },
                false,
            ),
            None => {
                self.summary.passed += 1;
                return self.pass_record(&rec);
            }
        };
        let mode = pref.mode.unwrap_or(if rec.uv.is_some() {
            PatternMode::Uv
        } else {
            PatternMode::Object
        });
        if mode != PatternMode::Object || (own && rec.uv.is_some()) {
            // With `uv` nothing is partitioned: no surprise to warn about.
            if !self.warned_mode && !self.args.uv {
                (self.warn)(format!(
                    "record {}: patterns in \"screen\" or \"uv\" mode are not partitioned; \
                     such records pass through unchanged",
                    rec.index
                ));
                self.warned_mode = true;
            }
            self.summary.passed += 1;
            return self.pass_record(&rec);
        }
        let pattern = self.pattern(pref.file.as_deref())?;
        let a = self.args;
        let place = Placement {
            incr: pref.incr.unwrap_or(a.incr),
            horz: pref.horz.unwrap_or(a.horz),
            vert: pref.vert.unwrap_or(a.vert),
        };
        let rotate = pref.rotate.unwrap_or(a.rotate);
        let vertices = match &rec.shape {
            Shape::Polygon(v) => v.to_vec(),
            other => outline(other, a.tolerance),
        };
        let mut poly = map_to_plane(&vertices, rotate, a.planarity_tol)?;
        if !self.warned_coarse {
            if let Some(c) = super::CoarseTexture::check(rec.index, poly.area, place.incr) {
                (self.warn)(c.to_string());
                self.warned_coarse = true;
            }
        }
        // A "transform" still on a record varies per frame (a static one was
        // applied when it was read): where the record is, only the renderer
        // knows, so it is not culled, as inside objects; its cells carry it.
        let volume = match rec.fields.contains_key("transform") {
            true => None,
            false => self.volume,
        };
        if let Some(vol) = &volume {
            let (normal, point) = (poly.frame.normal, poly.frame.origin);
            let facing = match a.cull {
                Cull::None => false,
                Cull::Back => vol.back_facing(normal, point),
                Cull::Front => vol.front_facing(normal, point),
            };
            if facing || vol.outside(&vertices) {
                self.summary.culled += 1;
                return Ok(());
            }
        }
        if a.uv {
            return self.forward_uv(&rec, &pref, &vertices, place, rotate);
        }
        if !state.is_empty() && !self.warned_state {
            // Texel polygons are flat: the state they would need is that of
            // the partition itself (repeat, replace, the exact box).
            let keys = rec.fields["pattern"]
                .as_object()
                .map(|o| {
                    o.keys()
                        .filter(|k| STATE_KEYS.contains(&k.as_str()))
                        .map(|k| format!("\"{k}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default();
            (self.warn)(format!(
                "record {}: \"pattern\" keys {keys} do not apply to texel polygons: \
                 each takes its texel's own colour, repeated (--uv keeps them for scene-render)",
                rec.index
            ));
            self.warned_state = true;
        }
        // Only the cut needs the projection simple: with --uv the record
        // was written whole, as readers take it.
        simple_on_plane(&mut poly, &vertices);
        let grid = Grid::new(&poly.points, place)?;
        let estimate = (poly.area / (place.incr * place.incr)).min(estimate_cells(
            grid.xmax - grid.xmin,
            grid.ymax - grid.ymin,
            place.incr,
        ));
        if self.summary.polygons as f64 + estimate > a.max_polygons as f64 {
            return Err(OptionError::new(
                format!(
                    "about {estimate:.0} polygons at incr {} would take the output past ",
                    place.incr
                ),
                "max_polygons",
                format!(
                    " {} ({} written so far)",
                    a.max_polygons, self.summary.polygons
                ),
            )
            .into());
        }
        self.writer.begin(
            &rec,
            pattern,
            a.merge,
            a.max_polygons - self.summary.polygons,
        );
        self.writer.volume = volume;
        match a.compat {
            None => self.partitioner.run(&poly, &grid, &mut self.writer),
            Some(Compat::Thesis) => {
                let (h, v) = (place.horz, place.vert);
                if h.fract() != 0.0 || v.fract() != 0.0 {
                    return Err(OptionError::new(
                        "",
                        "compat",
                        format!(
                            " thesis: horz {h} and vert {v} must be integers, as in the thesis"
                        ),
                    )
                    .into());
                }
                let size = self.writer.pattern_size();
                thesis_partition(
                    &poly,
                    place.incr,
                    h as i64,
                    v as i64,
                    size,
                    &mut self.writer,
                )
            }
        }
        self.writer.finish()?;
        self.summary.partitioned += 1;
        self.summary.polygons += self.writer.written;
        Ok(())
    }
}
