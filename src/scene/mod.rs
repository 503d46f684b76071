//! The scene stage: between "the stream was read" and "screen polygons go to
//! the rasterizer".
//!
//! [`Scene::read`] keeps a stream as drawable parts: every record with its one
//! texture source resolved (patterns and stripe files loaded once each), and
//! objects defined once and shared by their instances (the thesis's
//! `makeobj`/`callobj`, Fig. 5.1). [`Scene::project`] turns the parts into one
//! frame's [`ScreenPoly`]s through a [`View`]: instance transforms (animated
//! ones at that frame) multiply the view's matrix, curves are flattened for
//! the view's scale, quadrics tessellated for it, and each face's texture is
//! placed on the screen. [`render`] resolves them into an image.
//!
//! [`polyfill`] is the other consumer of the stream: the partition of
//! patterned polygons into texture point polygons (`polyfill3`).
//!
//! A stream of one triangle, rendered through IRIS GL's `ortho2` with exact
//! anti-aliasing, as `scene-render` does:
//!
//! ```
//! use patkit::camera::Camera;
//! use patkit::raster::{Aa, Background};
//! use patkit::scene::{self, DrawOptions, Scene};
//! use patkit::view::View;
//! use patkit::Rgb8;
//!
//! let stream = r#"{"vertices": [[1, 1], [7, 1], [4, 6]], "color": [255, 128, 0]}"#;
//! let scene = Scene::read(Box::new(stream.as_bytes()), "triangle.json", ".".as_ref())?;
//! let view = View::new(&Camera::ortho2(0.0, 8.0, 0.0, 8.0), 8, 8);
//! let polygons = scene.project(&view, &DrawOptions::default(), 0)?;
//! let background = Background::color(Rgb8::BLACK);
//! let image = scene::render(&polygons, &background, &view, Aa::Exact);
//! // Pixel (4, 3) from the lower-left (row 4 from the top) lies inside the triangle.
//! let at = (4 * 8 + 4) * image.channels as usize;
//! assert_eq!(image.data[at..at + 3], [255, 128, 0]);
//! # Ok::<(), patkit::scene::SceneError>(())
//! ```

mod cell_writer;
mod error;
#[cfg(test)]
mod horizon_tests;
pub mod keys;
pub mod polyfill;
#[cfg(test)]
mod shared_pixel_tests;
pub mod stripe;

use error::InRecord;
pub use error::{CellsError, PartitionError, RecordError, SceneError};

use crate::color::Rgb8;
use crate::geom::transform::Transform;
use crate::geom::Shape;
use crate::io::{AnyImage, Encoding, Image};
use crate::light::{Lights, Shade};
use crate::progress::{Progress, Silent};
use crate::raster::{self, Aa, Background, Cull, ScreenPoly, Shader, Tally};
use crate::stream::{
    for_each_item_in, FileIds, Instance, Item, Objects, PatternMode, PatternRef, Record,
};
use crate::stripe::record::StripeLoader;
use crate::stripe::LodMode;
use crate::texture::place::TextureSettings;
use crate::texture::state::TextureState;
use crate::texture::Texels;
use crate::view::View;
use glam::DVec3;
use std::collections::{HashMap, HashSet};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Where a face's colour comes from. A face has exactly one source (a record
/// with both `"pattern"` and `"stripe"` is refused when read); shading, when
/// it comes, is a separate axis that modulates whichever source it is.
#[derive(Clone, Debug)]
pub enum TextureSource {
    /// The record's `"color"` alone.
    Flat,
    /// A screen-mode pattern (docs/stream-format.md, the IRIS `setpattern`): pixel (x, y)
    /// shows texel (x mod SIZE, y mod SIZE).
    Screen(Arc<Texels>),
    /// An "object" or "uv" pattern, placed through its screen → texel map
    /// when the face is projected.
    Placed {
        /// The record's `"pattern"` object (placement: incr, rotate, shifts).
        pattern: PatternRef,
        /// The placement in effect, with the tool's default applied:
        /// [`PatternMode::Object`] or [`PatternMode::Uv`], never `Screen`.
        mode: PatternMode,
        /// The pattern, decoded once and shared by every face that uses it.
        texels: Arc<Texels>,
        /// The record's own filters, boundary and composition, over the
        /// tool's ([`TextureState::over`]).
        state: TextureState,
    },
    /// A stripe texture (seed 001), given its screen mapping when the face
    /// is projected.
    Stripe(stripe::RecordStripe),
}

/// One record ready to draw, in its own coordinates (world coordinates at the
/// top level, the object's inside a definition). Only the geometry is kept,
/// not the record's JSON; what most records lack is kept out of line
/// ([`Extras`]), and a triangle's or a quad's vertices inline, so a flat
/// polygon's part is 120 bytes (the fields inline made every part 336 bytes:
/// a third of a gigabyte for a million triangles).
struct Drawable {
    /// The record's place in the stream: a top-level record's draw order,
    /// 32 bits as [`ScreenPoly::order`] is. A stream of more records is
    /// refused as it is read, at the first one past ([`record_index`]); 4
    /// bytes rather than a word made a triangle's part 120 bytes, not 128.
    index: u32,
    shape: Shape,
    color: Rgb8,
    /// How a lit scene shades it.
    shade: Shade,
    /// `None` for a flat, untextured record whose transform (if any) was
    /// applied when it was read.
    extras: Option<Box<Extras>>,
}

/// The parts of a [`Drawable`] that few records have.
struct Extras {
    texture: TextureSource,
    /// Texture coordinates per vertex, in texels (uv mode).
    uv: Option<Vec<[f64; 2]>>,
    /// Normals per vertex, in the record's coordinates (smooth lighting).
    normals: Option<Vec<DVec3>>,
    /// The record's own "transform" when its numbers vary per frame (a
    /// static one was applied when the record was read, or, for a quadric,
    /// is its `QuadricShape::transform`).
    animated: Option<serde_json::Value>,
}

/// What a [`Drawable`] without [`Extras`] is coloured by.
static FLAT: TextureSource = TextureSource::Flat;

impl Drawable {
    fn texture(&self) -> &TextureSource {
        self.extras.as_ref().map_or(&FLAT, |e| &e.texture)
    }
    fn uv(&self) -> Option<&[[f64; 2]]> {
        self.extras.as_ref().and_then(|e| e.uv.as_deref())
    }
    fn normals(&self) -> Option<&[DVec3]> {
        self.extras.as_ref().and_then(|e| e.normals.as_deref())
    }
    fn animated(&self) -> Option<&serde_json::Value> {
        self.extras.as_ref().and_then(|e| e.animated.as_ref())
    }
}

/// A stream element as the scene keeps it.
enum Part {
    Draw(Drawable),
    /// An instance (the thesis's `callobj`), boxed: its fields would make
    /// every part, most of them polygons, three times as large.
    Place(Box<Placement>),
}

/// An instance: the object's parts are shared, never copied; they are
/// projected through the instance's transform.
struct Placement {
    index: usize,
    name: String,
    object: Arc<Vec<Part>>,
    transform: Transform,
    /// The transform's JSON when its numbers vary per frame.
    animated: Option<serde_json::Value>,
}

/// What reading a scene may cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// The most polygons one frame may expand into: every instance counts
    /// its object's polygons (nested instances multiply), a quadric with
    /// given `slices` and `stacks` its 2 x slices x stacks triangles. A scene
    /// over it is refused when read, before any work, naming the record
    /// where the count passes it. A quadric that leaves them out gets as
    /// many as its chords need at the view, so it is counted when projected,
    /// before it is tessellated, and a frame it takes past the limit is
    /// refused then (a 4 KB stream of 40 nested objects, each
    /// placing the previous twice, expands to 2^40 polygons). At about 130
    /// bytes per triangle at the peak of a frame drawn once
    /// (`bench/memory.sh`: the scene's parts while it is read, the projected
    /// polygons while they are drawn; an animation keeps the parts beside
    /// the polygons, about 120 more), the default allows about 1.3 GB.
    ///
    /// Default value: 10,000,000.
    pub max_polygons: u64,
}

impl LoadOptions {
    /// The defaults, as a constant.
    pub const DEFAULT: LoadOptions = LoadOptions {
        max_polygons: 10_000_000,
    };
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions::DEFAULT
    }
}

impl Part {
    /// The polygons this part expands into in a frame, at most (saturating):
    /// `objects` holds each defined object's count.
    fn polygons(&self, objects: &HashMap<String, u64>) -> u64 {
        match self {
            Part::Draw(d) => match &d.shape {
                Shape::Quadric(q) => match (q.slices, q.stacks) {
                    (Some(a), Some(b)) => 2 * a as u64 * b as u64,
                    // Chosen from the view's tolerance, so counted when
                    // projected ([`QuadricRoom`]); one here.
                    _ => 1,
                },
                _ => 1,
            },
            // At least one: an instance of an empty object draws nothing,
            // but placing it is work, and twelve objects each placing the
            // one before ten times, the first empty, are 10^12 placements
            // (a hostile-input review: hours, under any limit).
            Part::Place(p) => objects.get(&p.name).copied().unwrap_or(0).max(1),
        }
    }
}

/// A polygon stream read into drawable parts, objects defined once. A
/// scene is `Send` and `Sync`: its frames may be projected from several
/// threads at once, as [`Scene::project`] itself does with its parts.
#[derive(Default)]
pub struct Scene {
    /// The top-level parts in stream order, a projection wave
    /// ([`PROJECT_WAVE`] runs of [`PROJECT_RUN`]) to a list, so that a
    /// single frame's projection frees each wave once it is projected
    /// ([`Scene::into_frame`]).
    waves: Vec<Vec<Part>>,
    /// The files read besides the stream, once each: patterns and images
    /// in the order first read, then the meshes' OBJ and MTL files, then
    /// stripe maps and tables.
    files: Vec<PathBuf>,
    /// What the reading found worth a warning ([`Scene::warnings`]).
    warnings: Vec<String>,
    /// The stream's lights; none for an unlit scene.
    lights: crate::light::Lights,
    /// The polygons counted when the stream was read, and the most a frame
    /// may have ([`LoadOptions::max_polygons`]); `None`: no limit.
    limit: Option<Counted>,
}

/// Polygons counted when a scene was read, against its limit.
#[derive(Clone, Copy, Debug)]
struct Counted {
    read: u64,
    limit: u64,
}

/// A polygon no larger than one texel of its "object"-mode pattern (area at
/// most incr²): it shows one texel's colour, or a few, which is rarely what
/// was meant (the default `incr` of 1 on a unit cube paints each face one
/// colour). The tools warn with its `Display`, which names `incr`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoarseTexture {
    /// The record (its index in the stream).
    pub record: usize,
    /// The polygon's area, in its own units squared.
    pub area: f64,
    /// The pattern's texel side (`"incr"`).
    pub incr: f64,
}

impl CoarseTexture {
    /// `Some` when a polygon of `area` is no larger than one texel of side `incr`.
    pub fn check(record: usize, area: f64, incr: f64) -> Option<CoarseTexture> {
        // An area that overflowed is no measure of the polygon (it is
        // refused as too large, `PlaneError::TooLarge`).
        (area > 0.0 && area.is_finite() && area <= incr * incr).then_some(CoarseTexture {
            record,
            area,
            incr,
        })
    }

    /// A record's polygon area if it is planar with a straight outline or a
    /// circle (arcs and quadrics are not checked).
    fn area(shape: &Shape) -> Option<f64> {
        match shape {
            Shape::Polygon(v) => Some(crate::geom::plane::newell_normal(v, v[0]).length() / 2.0),
            Shape::Rect([x0, y0, x1, y1]) => Some(((x1 - x0) * (y1 - y0)).abs()),
            Shape::Circle { radius, .. } => Some(std::f64::consts::PI * radius * radius),
            Shape::Arc { .. } | Shape::Quadric(_) => None,
        }
    }
}

impl std::fmt::Display for CoarseTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let incr = crate::text::readable(self.incr);
        write!(
            f,
            "record {}: the polygon (area {}) is no larger than one texel of its pattern \
             (\"incr\" {incr}: texels {incr} units wide), so it shows one texel's colour; \
             a smaller \"incr\" shows the pattern",
            self.record,
            crate::text::readable(self.area),
        )
    }
}

/// How every record of a frame is drawn.
#[derive(Clone, Copy, Debug)]
pub struct DrawOptions {
    /// Which faces to drop. Default value: [`Cull::None`].
    pub cull: Cull,
    /// How placed patterns are filtered and composed. Default value:
    /// [`TextureSettings::DEFAULT`].
    pub texture: TextureSettings,
    /// The level-of-detail rule of stripe textures. Default value:
    /// [`LodMode::Blend`].
    pub stripe_lod: LodMode,
    /// Pixels per stripe evaluation ([`crate::stripe::StripeTexture::footprint`]):
    /// see [`stripe_footprint`]. Default value: 1.
    pub stripe_footprint: f64,
    /// Largest distance, in pixels, of a quadric's chords from its surface,
    /// for quadric records that leave out slices or stacks. Default value:
    /// [`crate::geom::quadric::DEFAULT_TOLERANCE_PX`].
    pub quadric_tolerance: f64,
}

impl DrawOptions {
    /// Every field at its default value (see each field).
    pub const DEFAULT: DrawOptions = DrawOptions {
        cull: Cull::None,
        texture: TextureSettings::DEFAULT,
        stripe_lod: LodMode::Blend,
        stripe_footprint: 1.0,
        quadric_tolerance: crate::geom::quadric::DEFAULT_TOLERANCE_PX,
    };
}

impl Default for DrawOptions {
    fn default() -> Self {
        DrawOptions::DEFAULT
    }
}

/// The pixels one stripe evaluation stands for under a resolver: `1/k` for
/// k x k supersampling (each sample is a `1/k` pixel), else 1 (the exact
/// resolver evaluates per fragment, point sampling per pixel).
pub fn stripe_footprint(aa: Aa) -> f64 {
    match aa {
        Aa::Ss(k) => 1.0 / k as f64,
        Aa::None | Aa::Exact => 1.0,
    }
}

impl Scene {
    /// Reads the stream at `input` (`-` is standard input). Patterns and
    /// stripe files resolve against the stream's directory.
    pub fn load(input: &str) -> Result<Scene, SceneError> {
        Scene::load_with(input, &LoadOptions::DEFAULT)
    }

    /// [`Scene::load`] within `limits`.
    pub fn load_with(input: &str, limits: &LoadOptions) -> Result<Scene, SceneError> {
        // 64 KiB, a default pipe's whole buffer: standard input's own 8 KiB
        // took eight reads for each of a full pipe's. `stdin()`, not its
        // lock, which cannot move to the thread that reads ahead
        // (`for_each_item`).
        let reader: Box<dyn BufRead + Send> = if input == crate::io::STDIO {
            Box::new(BufReader::with_capacity(1 << 16, std::io::stdin()))
        } else {
            Box::new(BufReader::with_capacity(
                1 << 16,
                crate::io::open_file(input)?,
            ))
        };
        let name = crate::io::display_name(input).to_string();
        Scene::read_with(reader, &name, &crate::stream::base_dir(input), limits)
    }

    /// Reads a stream, keeping objects and instances. `name` is the stream as
    /// errors show it, `base` the directory its files resolve against.
    /// Patterns are drawn directly: screen mode (the IRIS hardware patterns
    /// of the thesis's demo 1) per pixel, object and uv placement through
    /// their screen → texel map, computed when each record is projected (in
    /// the object's own coordinates for an instance, so the pattern stays
    /// fixed to the object as in the thesis's Fig. 5.1). The reader is
    /// `Send`: an NDJSON stream's next lines are read on another thread
    /// ([`crate::stream::for_each_item`]).
    pub fn read(
        reader: Box<dyn BufRead + Send>,
        name: &str,
        base: &Path,
    ) -> Result<Scene, SceneError> {
        Scene::read_with(reader, name, base, &LoadOptions::DEFAULT)
    }

    /// [`Scene::read`] within `limits`.
    pub fn read_with(
        reader: Box<dyn BufRead + Send>,
        name: &str,
        base: &Path,
        limits: &LoadOptions,
    ) -> Result<Scene, SceneError> {
        // Keyed by the file, not its spelling (`stream::FileIds`).
        let (mut patterns, mut ids) = (HashMap::<PathBuf, Arc<Texels>>::new(), FileIds::default());
        let mut stripes = StripeLoader::new(base);
        let mut files = Vec::new();
        let mut coarse = Vec::new();
        let (mut unknown, mut warnings) = (keys::UnknownKeys::default(), Vec::new());
        let mut scene = read_items(reader, name, base, limits, |rec| {
            let at = (Some(name), rec.index);
            unknown.check(rec.index, &rec.fields, |w| warnings.push(w));
            let stripe =
                stripe::read(&mut stripes, &rec.fields, rec.color).in_record(at.0, at.1)?;
            if stripe.is_some() && rec.pattern.is_some() {
                return Err(RecordError::PatternAndStripe).in_record(at.0, at.1);
            }
            let mut texture = TextureSource::Flat;
            if let Some(pref) = &rec.pattern {
                let quadric = matches!(rec.shape, Shape::Quadric(_));
                let mode = pref.mode.unwrap_or(if rec.uv.is_some() || quadric {
                    PatternMode::Uv
                } else {
                    PatternMode::Object
                });
                let Some(file) = &pref.file else {
                    return Err(RecordError::NoPatternFile).in_record(at.0, at.1);
                };
                // Only patterns the scene references are read, each once.
                let path = crate::stream::resolve(base, file);
                let texels = match patterns.get(ids.file(&path)) {
                    Some(p) => p.clone(),
                    None => {
                        let p = Arc::new(Texels::read_file(&path).in_record(at.0, at.1)?);
                        patterns.insert(ids.file(&path).to_path_buf(), p.clone());
                        files.push(path);
                        p
                    }
                };
                if mode == PatternMode::Object {
                    let incr = pref
                        .incr
                        .unwrap_or(crate::texture::place::DEFAULT_PLACEMENT.incr);
                    let area = CoarseTexture::area(&rec.shape);
                    coarse.extend(area.and_then(|a| CoarseTexture::check(rec.index, a, incr)));
                }
                // Checked for screen patterns too, which do not use it: a
                // bad value is an error wherever it is written.
                let state = TextureState::from_pattern(&rec.fields["pattern"])
                    .and_then(|s| s.check(texels.has_alpha()).map(|()| s))
                    .map_err(RecordError::TextureState)
                    .in_record(at.0, at.1)?;
                texture = match mode {
                    PatternMode::Screen => TextureSource::Screen(texels),
                    PatternMode::Object | PatternMode::Uv => TextureSource::Placed {
                        pattern: pref.clone(),
                        mode,
                        texels,
                        state,
                    },
                };
            }
            // Static transforms of polygons, rects, circles and arcs were
            // applied when the record was read (`stream::Record`).
            let animated = rec
                .fields
                .get("transform")
                .filter(|t| Transform::is_animated(t))
                .cloned();
            let color = match &stripe {
                Some(st) => st.face,
                None => rec.color.unwrap_or(Rgb8::BLACK),
            };
            if let Some(st) = stripe {
                texture = TextureSource::Stripe(st);
            }
            let plain = matches!(texture, TextureSource::Flat)
                && rec.uv.is_none()
                && rec.normals.is_none()
                && animated.is_none();
            Ok(Drawable {
                index: record_index(rec.index).in_record(at.0, at.1)?,
                // Kept as read: a triangle's or a quad's vertices inline
                // (`geom::Vertices`), a longer list made on this thread at
                // its exact size (`stream::plain`), so a scene is not
                // scattered over the parsing threads' malloc arenas (a
                // million triangles' peaked at 196 MB that way, 158 once
                // copied here, before their vertices were inline).
                shape: rec.shape,
                color,
                shade: rec.shade,
                extras: (!plain).then(|| {
                    Box::new(Extras {
                        texture,
                        uv: rec.uv,
                        normals: rec.normals,
                        animated,
                    })
                }),
            })
        })?;
        // Then the meshes' files, which reading the stream put there.
        for f in std::mem::take(&mut scene.files) {
            if !files.contains(&f) {
                files.push(f);
            }
        }
        files.extend(stripes.files().iter().cloned());
        scene.files = files;
        if let [first, rest @ ..] = coarse.as_slice() {
            warnings.push(match rest.len() {
                0 => first.to_string(),
                n => format!("{first} (and {n} more records alike)"),
            });
        }
        warnings.append(&mut scene.warnings);
        scene.warnings = warnings;
        Ok(scene)
    }

    /// What reading the stream found worth a warning, each once: unknown
    /// keys inside a record's `"pattern"` or `"stripe"` ([`keys`]), and the
    /// first polygon no larger than one texel ([`CoarseTexture`], with the
    /// count of the others). The tools print them; a library caller may
    /// ignore them.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The files read besides the stream (patterns, stripe maps and tables),
    /// each once, as resolved against the stream's directory: what a build
    /// system must know the scene depends on (`scene-render --depfile`).
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Frame `frame`'s screen polygons through `view`, in stream order (an
    /// instance's polygons draw at the instance's place). Numbers of animated
    /// transforms are taken at `frame` (docs/objects.md).
    pub fn project(
        &self,
        view: &View,
        how: &DrawOptions,
        frame: u64,
    ) -> Result<Vec<ScreenPoly>, SceneError> {
        Ok(self.project_tallied(view, how, frame)?.0)
    }

    /// [`Scene::project`], also counting what became of every polygon
    /// (quadrics count their triangles): drawn, or why not. A frame that
    /// draws nothing of a non-empty stream is a mistake worth a warning
    /// (`scene-render` gives one, naming the counts).
    pub fn project_tallied(
        &self,
        view: &View,
        how: &DrawOptions,
        frame: u64,
    ) -> Result<(Vec<ScreenPoly>, Tally), SceneError> {
        project_waves(&self.waves, view, how, frame, &self.lights, self.limit)
    }

    /// [`Scene::project_tallied`] for a scene drawn once: each wave of parts
    /// is freed as soon as it is projected, so the scene's parts and the
    /// frame's polygons are not held whole at once. A million triangles
    /// peaked at both (136 and 144 bytes each then, bench/memory.sh).
    pub fn into_frame(
        self,
        view: &View,
        how: &DrawOptions,
        frame: u64,
    ) -> Result<(Vec<ScreenPoly>, Tally), SceneError> {
        project_waves(self.waves, view, how, frame, &self.lights, self.limit)
    }

    /// Whether any record or instance has an animated transform: its
    /// frames may then differ, and fail, one from another. Each object's
    /// parts are read once however many instances place it.
    pub fn is_animated(&self) -> bool {
        fn any(parts: &[Part], seen: &mut HashSet<*const Vec<Part>>) -> bool {
            parts.iter().any(|part| match part {
                Part::Draw(d) => d.animated().is_some(),
                Part::Place(p) => {
                    p.animated.is_some()
                        || (seen.insert(Arc::as_ptr(&p.object)) && any(&p.object, seen))
                }
            })
        }
        let mut seen = HashSet::new();
        self.waves.iter().any(|wave| any(wave, &mut seen))
    }

    /// Checks every animated transform of frame `frame` as
    /// [`Scene::project`] would meet it, and nothing else: an animation
    /// calls it for all its frames before it writes any, so that a
    /// transform that fails at frame K (a scale reaching 0, a step reaching
    /// infinity: a pure function of the stream) is an error before frames
    /// 0 to K-1 replace their files (a hostile-input review). The same
    /// errors, in the same order, as projection's; one walk over the
    /// parts, as a frame's projection makes (a scene that is not
    /// [`Scene::is_animated`] needs none).
    pub fn check_transforms_at(&self, frame: u64) -> Result<(), SceneError> {
        self.waves
            .iter()
            .try_for_each(|wave| check_transforms(wave, None, None, frame))
    }

    /// Adds a top-level part at the end of the stream.
    fn push(&mut self, part: Part) {
        match self.waves.last_mut() {
            Some(wave) if wave.len() < PROJECT_RUN * PROJECT_WAVE => wave.push(part),
            _ => self.waves.push(vec![part]),
        }
    }
}

/// Projects `waves` of top-level parts (a scene's, borrowed or owned), each
/// dropped before the next is projected.
///
/// Runs of parts are projected on every thread and joined in stream order:
/// the same polygons in the same order, and the first error in the stream,
/// as one thread would give. A wave of runs at a time, so that the runs'
/// lists, freed once joined, are the next wave's memory: all runs at once
/// held the frame's polygons twice (a million triangles peaked at 512 MB
/// instead of 390).
fn project_waves<W: AsRef<[Part]>>(
    waves: impl IntoIterator<Item = W>,
    view: &View,
    how: &DrawOptions,
    frame: u64,
    lights: &Lights,
    limit: Option<Counted>,
) -> Result<(Vec<ScreenPoly>, Tally), SceneError> {
    use rayon::prelude::*;
    let room = limit.map(|counted| QuadricRoom {
        counted,
        taken: AtomicU64::new(0),
    });
    let mut out = Projected::new(None);
    // The quadrics' triangles beyond one each, in stream order.
    let mut quadric_triangles = 0u64;
    for wave in waves {
        let runs: Vec<Result<Projected, SceneError>> = wave
            .as_ref()
            .par_chunks(PROJECT_RUN)
            .map(|parts| {
                let mut run = Projected::new(room.as_ref());
                project_parts(parts, view, None, None, how, frame, lights, &mut run)?;
                Ok(run)
            })
            .collect();
        drop(wave);
        for run in runs {
            let run = run?;
            if let Some(room) = &room {
                for &(index, more) in &run.quadrics {
                    quadric_triangles = quadric_triangles.saturating_add(more);
                    let polygons = room.total(quadric_triangles);
                    if polygons > room.counted.limit {
                        return Err(SceneError::TooMuchWork {
                            index,
                            polygons,
                            limit: room.counted.limit,
                        });
                    }
                }
            }
            out.polygons.extend(run.polygons);
            out.tally.add(&run.tally);
        }
    }
    Ok((out.polygons, out.tally))
}

/// How many of a scene's top-level parts one projection job takes: enough
/// that a job is thousands of polygons (a part may be an instance of many).
const PROJECT_RUN: usize = 4096;
/// How many runs are projected before they are joined.
const PROJECT_WAVE: usize = 8;

/// A frame's screen polygons as they are projected, and the tally of all.
struct Projected<'a> {
    polygons: Vec<ScreenPoly>,
    tally: Tally,
    /// What the frame's quadrics without given slices and stacks may add.
    room: Option<&'a QuadricRoom>,
    /// The record and the triangles beyond one of each such quadric met,
    /// in stream order: the join counts them in that order ([`QuadricRoom`]).
    quadrics: Vec<(usize, u64)>,
}

/// The triangles that a frame's quadrics tessellated for the view (those
/// that leave out `slices` or `stacks`) add to the polygons counted when
/// the scene was read, where each counted as one: they share what the
/// limit leaves. Reading cannot count them, since the view decides them:
/// a sphere of radius 1e6 in a 64-pixel 2D view takes 39 million
/// triangles for its quarter-pixel chords (a hostile-input review: 7.4 GB
/// before this).
///
/// The projection's threads take room as they come to such quadrics, and
/// once it is used up they cut no more, which bounds the memory; each run
/// also lists its quadrics' counts, and the join adds them up in stream
/// order and names the record where the frame passes the limit, the one
/// a single thread would name, whatever the threads' timing.
struct QuadricRoom {
    counted: Counted,
    /// Triangles beyond one a quadric, taken so far, by every thread.
    taken: AtomicU64,
}

impl QuadricRoom {
    /// Takes room for `more` triangles: whether they fit in what the limit
    /// leaves (if not, the join will refuse the frame).
    fn take(&self, more: u64) -> bool {
        let before = self
            .taken
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |t| {
                Some(t.saturating_add(more))
            })
            .unwrap_or_else(|t| t);
        self.total(before.saturating_add(more)) <= self.counted.limit
    }

    /// The frame's polygons with `more` triangles of such quadrics.
    fn total(&self, more: u64) -> u64 {
        self.counted.read.saturating_add(more)
    }
}

impl<'a> Projected<'a> {
    fn new(room: Option<&'a QuadricRoom>) -> Self {
        Projected {
            polygons: Vec::new(),
            tally: Tally::default(),
            room,
            quadrics: Vec::new(),
        }
    }

    fn push(&mut self, p: ScreenPoly) {
        self.tally.count(Ok(&p));
        self.polygons.push(p);
    }

    fn drop(&mut self, why: raster::Dropped) {
        self.tally.count(Err(why));
    }
}

/// Reads the stream, keeping objects and instances (the thesis's
/// `makeobj`/`callobj`, Fig. 5.1): every record, inside an object or not, goes
/// through `each` once; an instance refers to its object's parts.
fn read_items(
    reader: Box<dyn BufRead + Send>,
    name: &str,
    base: &Path,
    limits: &LoadOptions,
    mut each: impl FnMut(Record) -> Result<Drawable, SceneError>,
) -> Result<Scene, SceneError> {
    let mut checks = Objects::default();
    let mut objects: HashMap<String, Arc<Vec<Part>>> = HashMap::new();
    // Each object's polygons per placement, and the frame's so far.
    let mut sizes: HashMap<String, u64> = HashMap::new();
    let mut total = 0u64;
    let mut count = |part: &Part, index: usize, sizes: &HashMap<String, u64>| {
        total = total.saturating_add(part.polygons(sizes));
        if total > limits.max_polygons {
            return Err(SceneError::TooMuchWork {
                index,
                polygons: total,
                limit: limits.max_polygons,
            });
        }
        Ok(())
    };
    let mut scene = Scene::default();
    // Whether the stream places any polygon at all, and which objects hold
    // one (their counts above are at least 1 a placement): a stream of
    // instances of empty objects, or of meshes whose faces all have no
    // area, gave a blank frame with no word (a hostile-input review).
    let (mut elements, mut places_any) = (0u64, false);
    let mut holds_any: HashSet<String> = HashSet::new();
    let place = |inst: Instance, objects: &HashMap<String, Arc<Vec<Part>>>| {
        Part::Place(Box::new(Placement {
            index: inst.index,
            object: objects[&inst.object].clone(),
            transform: inst.transform,
            animated: inst
                .fields
                .get("transform")
                .filter(|t| Transform::is_animated(t))
                .cloned(),
            name: inst.object,
        }))
    };
    for_each_item_in(reader, name, base, |item| {
        elements += 1;
        match item {
            Item::Record(rec) => {
                let index = rec.index;
                let part = Part::Draw(each(rec)?);
                count(&part, index, &sizes)?;
                scene.push(part);
                places_any = true;
            }
            Item::Object(def) => {
                checks.define(def.skeleton()).map_err(|e| e.named(name))?;
                scene.files.extend(def.files);
                let mut parts = Vec::with_capacity(def.items.len());
                let mut holds = false;
                for it in def.items {
                    parts.push(match it {
                        Item::Record(rec) => {
                            holds = true;
                            Part::Draw(each(rec)?)
                        }
                        Item::Instance(inst) => {
                            holds |= holds_any.contains(&inst.object);
                            place(inst, &objects)
                        }
                        Item::Object(_) | Item::Light(_) => unreachable!(
                            "Objects::define rejects definitions and lights inside objects"
                        ),
                    });
                }
                let size = parts
                    .iter()
                    .fold(0u64, |n, p| n.saturating_add(p.polygons(&sizes)));
                sizes.insert(def.name.clone(), size);
                if holds {
                    holds_any.insert(def.name.clone());
                }
                objects.insert(def.name, Arc::new(parts));
            }
            Item::Light(light) => scene.lights.add(light.light),
            Item::Instance(inst) => {
                checks.check_instance(&inst).map_err(|e| e.named(name))?;
                let index = inst.index;
                places_any |= holds_any.contains(&inst.object);
                let part = place(inst, &objects);
                count(&part, index, &sizes)?;
                scene.push(part);
            }
        }
        Ok::<(), SceneError>(())
    })?;
    scene.limit = Some(Counted {
        read: total,
        limit: limits.max_polygons,
    });
    if elements > 0 && !places_any {
        scene.warnings.push(format!(
            "{name}: no frame draws anything: the stream places no polygon (lights and \
             object definitions draw nothing themselves; an object may be empty, or a \
             mesh's faces all without area)"
        ));
    }
    Ok(scene)
}

/// Clips and projects parts into screen polygons. `placed` is the transform
/// of the instance being drawn (object to world) and `order` its position in
/// the stream: every polygon of an instance draws at the instance's place, as
/// when the instance is expanded. An instance's polygons are never copied:
/// the view's matrix is multiplied by the instance's, so the clip-space
/// vertices the clipper makes anyway are the only transformed buffer.
#[allow(clippy::too_many_arguments)]
fn project_parts(
    parts: &[Part],
    base: &View,
    placed: Option<Transform>,
    order: Option<u32>,
    how: &DrawOptions,
    frame: u64,
    lights: &Lights,
    out: &mut Projected,
) -> Result<(), SceneError> {
    let moved;
    let view = match placed {
        Some(t) => {
            moved = View {
                world_to_clip: base.world_to_clip * t.matrix(),
                ..base.clone()
            };
            &moved
        }
        None => base,
    };
    for part in parts {
        match part {
            Part::Draw(d) => {
                let order = match order {
                    Some(o) => o,
                    None => d.index,
                };
                let to_world = placed.unwrap_or_default();
                if let Shape::Quadric(q) = &d.shape {
                    let lit = Lit::new(lights, d, to_world);
                    project_quadric(d, q, view, order, how, frame, lit, out)?;
                    continue;
                }
                // A record's own animated transform moves it as an instance
                // transform would: the view takes it on.
                let animated_view;
                let (view, to_world) = match d.animated() {
                    Some(v) => {
                        let t =
                            record_transform_at(d, v, frame).in_record(None, d.index as usize)?;
                        animated_view = View {
                            world_to_clip: view.world_to_clip * t.matrix(),
                            ..view.clone()
                        };
                        (&animated_view, t.then(to_world))
                    }
                    None => (view, to_world),
                };
                let outline = match &d.shape {
                    Shape::Polygon(v) => std::borrow::Cow::Borrowed(&v[..]),
                    other => std::borrow::Cow::Owned(crate::geom::outline(
                        other,
                        curve_tolerance(other, view),
                    )),
                };
                let lit = Lit::new(lights, d, to_world).map(|l| Lit {
                    normals: d.normals(),
                    ..l
                });
                draw_polygon(d, view, &outline, d.uv(), order, how, lit, out)
                    .in_record(None, d.index as usize)?;
            }
            Part::Place(p) => {
                let (total, order) = p.at(placed, order, frame)?;
                project_parts(
                    &p.object,
                    base,
                    Some(total),
                    Some(order),
                    how,
                    frame,
                    lights,
                    out,
                )?;
            }
        }
    }
    Ok(())
}

/// [`project_parts`]'s walk with only its transforms: the animated ones
/// evaluated at `frame` and instances composed with what places them
/// ([`Placement::at`], which projection calls too, so the errors are its
/// own; [`Scene::check_transforms_at`]).
fn check_transforms(
    parts: &[Part],
    placed: Option<Transform>,
    order: Option<u32>,
    frame: u64,
) -> Result<(), SceneError> {
    for part in parts {
        match part {
            Part::Draw(d) => {
                if let Some(v) = d.animated() {
                    record_transform_at(d, v, frame).in_record(None, d.index as usize)?;
                }
            }
            Part::Place(p) => {
                let (total, order) = p.at(placed, order, frame)?;
                check_transforms(&p.object, Some(total), Some(order), frame)?;
            }
        }
    }
    Ok(())
}

impl Placement {
    /// Where this instance puts its object at `frame`, placed by `placed`
    /// (the instances around it, if any), and the draw order of its
    /// polygons: the top-level instance's (`order`, else its own). Each
    /// error names the record as it draws.
    fn at(
        &self,
        placed: Option<Transform>,
        order: Option<u32>,
        frame: u64,
    ) -> Result<(Transform, u32), SceneError> {
        let transform = match &self.animated {
            Some(v) => Transform::from_json_at(v, frame)
                .map_err(|error| RecordError::InstanceTransform {
                    object: self.name.clone(),
                    frame,
                    error,
                })
                .in_record(None, self.index)?,
            None => self.transform,
        };
        let order = match order {
            Some(o) => o,
            None => draw_order(self.index)?,
        };
        let total = match placed {
            Some(outer) => transform
                .then_checked(outer)
                .map_err(|error| RecordError::PlacedTransform {
                    object: self.name.clone(),
                    error,
                })
                // The top-level instance's record, as it draws.
                .in_record(None, order as usize)?,
            None => transform,
        };
        Ok((total, order))
    }
}

/// A record's own animated `"transform"` (its JSON, `v`) at `frame`.
fn record_transform_at(
    d: &Drawable,
    v: &serde_json::Value,
    frame: u64,
) -> Result<Transform, RecordError> {
    Transform::from_json_at(v, frame).map_err(|error| RecordError::Transform {
        kind: d.shape.key(),
        frame,
        error,
    })
}

/// An instance's index as its draw order.
fn draw_order(index: usize) -> Result<u32, SceneError> {
    u32::try_from(index).map_err(|_| SceneError::TooManyRecords)
}

/// A record's index as [`Drawable::index`] keeps it: refused past 32 bits,
/// where draw order ends. Checked last of the record's fields, so that a
/// record with another fault is refused for that one.
fn record_index(index: usize) -> Result<u32, RecordError> {
    u32::try_from(index).map_err(|_| RecordError::TooManyRecords)
}

/// How one polygon is lit: the scene's lights, the transform from the
/// coordinates its outline is given in to the world's (where the lights
/// are), and its per-vertex normals in those coordinates when it has them.
#[derive(Clone, Copy)]
struct Lit<'a> {
    lights: &'a Lights,
    to_world: Transform,
    normals: Option<&'a [DVec3]>,
    shade: Shade,
}

impl<'a> Lit<'a> {
    /// `None` in an unlit scene and for a record that asks not to be lit.
    fn new(lights: &'a Lights, d: &Drawable, to_world: Transform) -> Option<Lit<'a>> {
        (!lights.is_empty() && d.shade != Shade::None).then_some(Lit {
            lights,
            to_world,
            normals: None,
            shade: d.shade,
        })
    }
}

/// Projects one polygon of a record and gives it its texture: `outline` in
/// the record's coordinates, `uv` its texture coordinates in texels (uv mode).
#[allow(clippy::too_many_arguments)]
fn draw_polygon(
    d: &Drawable,
    view: &View,
    outline: &[DVec3],
    uv: Option<&[[f64; 2]]>,
    order: u32,
    how: &DrawOptions,
    lit: Option<Lit>,
    out: &mut Projected,
) -> Result<(), RecordError> {
    let mut p = match raster::try_project(view, outline, d.color, order, how.cull) {
        Ok(p) => p,
        Err(why) => {
            out.drop(why);
            return Ok(());
        }
    };
    match d.texture() {
        TextureSource::Flat => {}
        TextureSource::Screen(texels) => p.set_shader(Shader::Screen(texels.clone())),
        TextureSource::Stripe(st) => match stripe::shader(st, view, outline, how.stripe_lod)? {
            Some(t) => {
                let t = match &lit {
                    // Stripes are lit flat: the face's irradiance scales
                    // both ends of the modulation.
                    Some(l) => t.lit(flat_irradiance(l, outline)),
                    None => t,
                };
                p.set_shader(Shader::Stripe(Arc::new(
                    t.with_footprint(how.stripe_footprint),
                )))
            }
            // Edge-on: a sliver of rounding; nothing to draw.
            None => {
                out.drop(raster::Dropped::NoArea);
                return Ok(());
            }
        },
        TextureSource::Placed {
            pattern,
            mode,
            texels,
            state,
        } => {
            let tex = crate::texture::place::place(
                &state.over(&how.texture),
                d.color,
                view,
                outline,
                pattern,
                *mode,
                uv,
                texels.clone(),
            )?;
            match tex {
                Some(mut t) => {
                    if let Some(l) = &lit {
                        light_texture(&mut t, &mut p, view, outline, l)?;
                    }
                    p.set_shader(Shader::Texture(Arc::new(t)));
                    out.push(p);
                    return Ok(());
                }
                // Visible by the projection but not by the fit: rounding at a
                // sliver; nothing to draw.
                None => {
                    out.drop(raster::Dropped::NoArea);
                    return Ok(());
                }
            }
        }
    }
    if let (Some(l), Shader::Flat | Shader::Screen(_)) = (&lit, p.shader()) {
        let colour = p.color;
        match smooth_field(l, view, outline, colour) {
            Some(field) => p.set_shade(Some(field)),
            None => p.color = lit_flat(colour, flat_irradiance(l, outline)),
        }
    }
    out.push(p);
    Ok(())
}

/// The unit front normal (Newell's, counter-clockwise seen from the front)
/// and the vertex centroid of `outline`, in world coordinates.
fn world_plane(l: &Lit, outline: &[DVec3]) -> (DVec3, DVec3) {
    let world: Vec<DVec3> = outline.iter().map(|&p| l.to_world.apply(p)).collect();
    let (mut n, mut c) = (DVec3::ZERO, DVec3::ZERO);
    for (i, &a) in world.iter().enumerate() {
        let b = world[(i + 1) % world.len()];
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
        c += a;
    }
    (n.normalize_or_zero(), c / world.len() as f64)
}

/// The light a flat-shaded polygon receives: at its centroid, along its
/// plane's normal (`light::Lights::irradiance`).
fn flat_irradiance(l: &Lit, outline: &[DVec3]) -> [f64; 3] {
    let (n, c) = world_plane(l, outline);
    l.lights.irradiance(c, n)
}

/// `colour` lit by irradiance `e`: `min(1, C e)` per channel (GL's clamp).
fn lit_flat(colour: [f64; 3], e: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|ch| (colour[ch] * e[ch]).min(1.0))
}

/// Smooth lighting's factor over a polygon of linear colour `colour`, or
/// `None` where the polygon is lit flat (`"shade": "flat"`, or `"auto"`
/// without per-vertex normals) or the fit fails (a sliver). At each vertex
/// the factor is the lit colour over the unlit one, `min(1, C e_i) / C`
/// (0 where `C` is 0: the product is 0 either way), with `e_i` the light at
/// the vertex along its normal (the face's where the record gives none);
/// [`crate::raster::ShadeField`] interpolates it.
fn smooth_field(
    l: &Lit,
    view: &View,
    outline: &[DVec3],
    colour: [f64; 3],
) -> Option<Arc<raster::ShadeField>> {
    let smooth = match l.shade {
        Shade::Smooth => true,
        Shade::Auto => l.normals.is_some(),
        Shade::Flat | Shade::None => false,
    };
    if !smooth {
        return None;
    }
    let (face, _) = world_plane(l, outline);
    let (mut rg, mut b) = (Vec::new(), Vec::new());
    for (i, &p) in outline.iter().enumerate() {
        let n = match l.normals {
            Some(ns) => l.to_world.apply_normal(ns[i]),
            None => face,
        };
        let e = l.lights.irradiance(l.to_world.apply(p), n);
        let f = [0, 1, 2].map(|ch| match colour[ch] > 0.0 {
            true => (colour[ch] * e[ch]).min(1.0) / colour[ch],
            false => 0.0,
        });
        rg.push(glam::DVec2::new(f[0], f[1]));
        b.push(glam::DVec2::new(f[2], 0.0));
    }
    use crate::texture::map::TexMap;
    Some(Arc::new(raster::ShadeField {
        rg: TexMap::fit(view, outline, &rg, true)?,
        b: TexMap::fit(view, outline, &b, true)?,
    }))
}

/// Lights a textured polygon as OpenGL's texture environment sees the lit
/// colour: `modulate` multiplies the texel by it (flat: the intrinsic
/// colour lit; smooth: the factor over the polygon); `replace`, `blend` and
/// `decal` do not use the polygon's colour, so light does not reach them;
/// `blend_intrinsic` and `decal_intrinsic` mix the texel with the colour,
/// which only flat lighting can give them exactly (smooth is refused).
fn light_texture(
    t: &mut crate::texture::PolyTexture,
    p: &mut ScreenPoly,
    view: &View,
    outline: &[DVec3],
    l: &Lit,
) -> Result<(), RecordError> {
    use crate::texture::compose::Compose;
    match t.compose {
        Compose::Replace | Compose::Blend | Compose::Decal => Ok(()),
        Compose::Modulate => {
            match smooth_field(l, view, outline, t.intrinsic) {
                Some(field) => p.set_shade(Some(field)),
                None => t.intrinsic = lit_flat(t.intrinsic, flat_irradiance(l, outline)),
            }
            Ok(())
        }
        Compose::BlendIntrinsic | Compose::DecalIntrinsic => {
            if smooth_field(l, view, outline, t.intrinsic).is_some() {
                return Err(RecordError::SmoothCompose(t.compose));
            }
            t.intrinsic = lit_flat(t.intrinsic, flat_irradiance(l, outline));
            Ok(())
        }
    }
}

/// Tessellates a quadric record for this view (`geom::quadric`: the slices
/// and stacks it leaves out come from the quadric tolerance at this camera
/// and this instance's placement, so every instance and frame is as fine as
/// it needs) and draws its triangles with their texel coordinates.
#[allow(clippy::too_many_arguments)]
fn project_quadric(
    d: &Drawable,
    q: &crate::geom::quadric::QuadricShape,
    view: &View,
    order: u32,
    how: &DrawOptions,
    frame: u64,
    lit: Option<Lit>,
    out: &mut Projected,
) -> Result<(), SceneError> {
    let index = d.index as usize;
    let moved;
    let q = match d.animated() {
        Some(v) => {
            let mut m = q.clone();
            m.transform = record_transform_at(d, v, frame).in_record(None, index)?;
            moved = m;
            &moved
        }
        None => q,
    };
    let own_to_clip = view.world_to_clip * q.transform.matrix();
    let tolerance = crate::geom::quadric::tolerance_at(
        &q.quadric,
        own_to_clip,
        view.width,
        view.height,
        how.quadric_tolerance,
    );
    let size = match d.texture() {
        TextureSource::Placed { texels, .. } => (texels.width(), texels.height()),
        _ => (1, 1),
    };
    if let (Some(room), None, _) | (Some(room), _, None) = (out.room, q.slices, q.stacks) {
        let more = q.triangle_bound(tolerance).saturating_sub(1);
        out.quadrics.push((index, more));
        if !room.take(more) {
            return Ok(()); // Past the limit: the join refuses the frame.
        }
    }
    q.for_each_texel_triangle(tolerance, size, |t| {
        // GLU's smooth normals: the triangle's vertices' own.
        let lit = lit.map(|l| Lit {
            normals: Some(&t.n),
            ..l
        });
        draw_polygon(d, view, &t.v, Some(&t.uv), order, how, lit, out)
    })
    .in_record(None, index)
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

/// Renders one frame's polygons, projected through `view`, with the
/// anti-aliasing `aa`, in an image of the view's size. With the `mip` skip
/// off (benchmarks), every textured polygon's MIP pyramid is built first.
pub fn render(polys: &[ScreenPoly], bg: &Background, view: &View, aa: Aa) -> Image {
    render_with(polys, bg, view, aa, &Silent)
}

/// [`render`], reporting its tiles to `progress` (a transparent background
/// draws each tile twice, over black and over white, and reports it once).
pub fn render_with(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
) -> Image {
    match render_encoded(polys, bg, view, aa, progress, Encoding::Srgb8).image {
        AnyImage::Srgb8(image) => image,
        _ => unreachable!("8-bit sRGB asked for"),
    }
}

/// A frame rendered by [`render_encoded`].
pub struct Rendered {
    /// The image in the encoding asked for.
    pub image: AnyImage,
    /// Textured fragments `--aa exact` estimated rather than integrated
    /// ([`raster::Frame::estimated`]); 0 elsewhere.
    pub estimated: u64,
}

impl Rendered {
    /// How far an estimated fragment can be from its exact value, in 8-bit
    /// codes: the largest [`crate::texture::PolyTexture::contrast_codes`]
    /// of the frame's textures (each texture once) or
    /// [`crate::stripe::StripeTexture::contrast_codes`] of its stripes, or
    /// `None` when nothing was estimated.
    pub fn estimate_bound(&self, polys: &[ScreenPoly]) -> Option<u32> {
        if self.estimated == 0 {
            return None;
        }
        let mut seen = Vec::new();
        polys
            .iter()
            .filter_map(ScreenPoly::texture)
            .filter(|t| {
                let key = t.appearance();
                let new = !seen.contains(&key);
                if new {
                    seen.push(key);
                }
                new
            })
            .map(|t| t.contrast_codes())
            .chain(
                polys
                    .iter()
                    .filter_map(ScreenPoly::stripe)
                    .map(|s| s.contrast_codes()),
            )
            .max()
    }
}

/// [`render_with`] in any encoding: 8- or 16-bit sRGB, or the frame's
/// linear values (PFM). A transparent background gives RGBA, and in linear
/// float the colour over black ([`raster::render_encoded_with_alpha`]).
pub fn render_encoded(
    polys: &[ScreenPoly],
    bg: &Background,
    view: &View,
    aa: Aa,
    progress: &dyn Progress,
    encoding: Encoding,
) -> Rendered {
    build_mips_eagerly(polys);
    let (image, estimated) = if bg.is_transparent() {
        // Two passes, over black and over white, tile by tile: the
        // difference is the coverage (Background::transparent).
        raster::render_encoded_with_alpha(polys, bg, view, aa, progress, encoding)
    } else {
        raster::render_encoded(polys, bg, view, aa, progress, encoding)
    };
    Rendered { image, estimated }
}

/// `--no-skip mip` (benchmarks): every textured polygon's MIP pyramid is
/// built before rendering, whether or not any pixel minifies, instead of on
/// the first minified sample. Each pattern's pyramid is still built once
/// (it is shared), so this costs what the lazy build saves.
fn build_mips_eagerly(polys: &[ScreenPoly]) {
    for tex in polys.iter().filter_map(ScreenPoly::texture) {
        if !tex.skips.mip {
            tex.texels.pyramid(tex.mip_key());
        }
    }
}

#[cfg(test)]
mod part_size {
    use crate::geom::Shape;

    /// A million polygons keep a million parts: the fields few records have
    /// stay out of line ([`super::Extras`], [`super::Placement`]), and a
    /// triangle's or quad's vertices inline ([`crate::geom::Vertices`]).
    /// At 336 bytes a part, the scene took a third of a gigabyte for a
    /// million triangles before projecting them; at 72 bytes and a heap
    /// block of 80, 152 MB; at 136 (a `SmallVec` of vertices, a word of
    /// index), the scene was a single frame's peak (bench/memory.sh).
    #[test]
    fn a_triangles_part_is_at_most_120_bytes_and_no_heap_block() {
        assert!(std::mem::size_of::<super::Part>() <= 120);
        assert!(std::mem::size_of::<super::Drawable>() <= 120);
        let scene = super::Scene::read(
            Box::new(&b"{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3]}\n"[..]),
            "-",
            std::path::Path::new("."),
        )
        .unwrap();
        let super::Part::Draw(d) = &scene.waves[0][0] else {
            panic!("a polygon is drawn")
        };
        let Shape::Polygon(v) = &d.shape else {
            panic!("a polygon")
        };
        assert!(v.is_inline() && d.extras.is_none());
    }

    /// The 2^32nd record and later are refused, each naming itself: no
    /// stream that long is at hand, so the conversion is tested alone.
    #[test]
    fn a_record_past_32_bits_of_draw_order_is_refused_by_name() {
        use super::InRecord;
        assert_eq!(super::record_index(7).unwrap(), 7);
        assert_eq!(super::record_index(u32::MAX as usize).unwrap(), u32::MAX);
        let past = u32::MAX as usize + 1;
        let e = super::record_index(past).in_record(Some("big.ndjson"), past);
        assert_eq!(
            crate::test_util::chain(&e.unwrap_err()),
            "big.ndjson: record 4294967296: more than 2^32 records in one stream: \
             draw order is 32 bits"
        );
    }
}

#[cfg(test)]
mod read_tests {
    use super::Scene;

    /// A stream read from a buffer, named as if it lay elsewhere, with a
    /// folder of its own: its meshes resolve in that folder, as its
    /// patterns do (they resolved beside the name, which held no model).
    #[test]
    fn meshes_resolve_against_base_as_patterns_do() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("sq.obj"),
            "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nf 1 2 3 4\n",
        )
        .unwrap();
        let stream = r#"{"mesh": {"obj": "sq.obj"}, "color": [200, 100, 50]}"#;
        let read = Scene::read(
            Box::new(std::io::Cursor::new(stream)),
            "elsewhere/scene.json",
            dir.path(),
        );
        assert!(read.is_ok(), "{:?}", read.err().map(|e| e.to_string()));
    }
}

#[cfg(test)]
mod project_tests {
    use super::{DrawOptions, Scene};
    use crate::camera::Camera;
    use crate::view::View;

    fn send_and_sync<T: Send + Sync>() {}

    /// Projection runs in parallel over runs of parts, a wave at a time: the
    /// polygons still come in stream order, one per visible record, whatever
    /// the number of threads, across runs and waves.
    #[test]
    fn polygons_come_in_stream_order_across_runs_and_waves() {
        send_and_sync::<Scene>();
        let n = super::PROJECT_RUN * super::PROJECT_WAVE + 3 * super::PROJECT_RUN / 2;
        let mut stream = String::new();
        for i in 0..n {
            // Every fifth triangle lies outside the view: fewer polygons than
            // parts in each run.
            let x = if i % 5 == 4 { -50.0 } else { (i % 90) as f64 };
            stream += &format!(
                "{{\"vertices\":[[{x},0],[{},0],[{x},{}]],\"color\":[1,2,3]}}\n",
                x + 5.0,
                1 + i % 7
            );
        }
        let scene = Scene::read(
            Box::new(std::io::Cursor::new(stream)),
            "s.json",
            std::path::Path::new("."),
        )
        .unwrap();
        let view = View::new(&Camera::ortho2(0.0, 100.0, 0.0, 10.0), 100, 10);
        let how = DrawOptions::default();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (polys, tally) = two
            .install(|| scene.project_tallied(&view, &how, 0))
            .unwrap();
        let orders: Vec<u32> = polys.iter().map(|p| p.order()).collect();
        let want: Vec<u32> = (0..n as u32).filter(|i| i % 5 != 4).collect();
        assert_eq!(orders, want);
        assert_eq!(tally.drawn as usize, want.len());
        assert_eq!(tally.outside as usize, n - want.len());
        let (alone, _) = one
            .install(|| scene.project_tallied(&view, &how, 0))
            .unwrap();
        assert_eq!(polys, alone);
        // Freeing each wave once projected changes nothing.
        let (once, once_tally) = two.install(|| scene.into_frame(&view, &how, 0)).unwrap();
        assert_eq!(polys, once);
        assert_eq!(tally, once_tally);
    }
}
