//! patkit: texture patterns (`.pat`) and textured-polygon rendering.
//!
//! The modules are layers, listed here in the order the data flows; each uses
//! only those above it in this list (a test, `layering`, keeps the rule), and
//! none knows the command line. `docs/architecture.md` draws the pipeline.
//!
//! **Foundations**
//! - [`color`]: sRGB and linear light, exactly rounded encoding.
//! - [`error`]: errors every layer may raise (an option named by its field).
//! - [`math`]: sines, powers and logarithms that give the same bits on every
//!   host.
//! - [`vector`]: directions and lengths of vectors whose squares overflow
//!   or underflow.
//! - [`text`]: the whitespace tokenizer of the text formats and their
//!   [`ParseError`].
//! - [`io`]: standard streams, atomic output files, image decoding and encoding.
//!
//! **Patterns**
//! - [`pat`]: the `.pat` format of the thesis (a [`Pattern`]).
//! - [`quantize`]: a picture turned into a pattern (`pat-from-image`).
//!
//! **Geometry and the stream**
//! - [`geom`]: record shapes, the 2D polygon kernel, transforms, planes, the
//!   partition into texture point polygons, quadrics.
//! - [`light`]: ambient and Lambert diffuse lighting from directional and
//!   point lights, in linear light.
//! - [`stream`]: the polygon stream of records, objects, instances and lights.
//!
//! **Seeing**
//! - [`camera`]: the IRIS GL / GLU and textbook cameras, reduced to matrices.
//! - [`view`]: a camera on an image of a given size; view-volume clipping.
//!
//! **Colour sources**
//! - [`texture`]: placed patterns: texel maps, filters, MIP maps, composition.
//! - [`stripe`]: the flight simulator's level-of-detail stripe textures.
//!
//! **Drawing**
//! - [`raster`]: screen polygons resolved into pixels (point sampling, exact
//!   area, the reference).
//! - [`scene`]: a stream loaded as a scene and projected frame by frame; the
//!   partition job of `polyfill3`.
//!
//! **The tools** (cargo feature `cli`, on by default)
//! - `cli`: each tool's flags and `run`, over the library. The binaries in
//!   `src/bin/` are one-line shims.
//!
//! **First steps.** The types a program meets first are also at the crate
//! root: read a scene with [`Scene::load`], point a [`Camera`] at it through a
//! [`View`] of the image's size, [`Scene::project`] a frame and
//! [`scene::render`] it into an [`Image`] (the `scene` module's example, and
//! `examples/render_scene.rs`, do exactly that); read and write patterns with
//! [`Pattern`].
//!
//! **Errors.** Each stage has its own error type, an enum (or a struct) that
//! keeps what a program may act on — the record's index, the field, the
//! value, the file — and implements [`std::error::Error`]: `Display` is this
//! stage's words and `source()` the cause, so printing the chain
//! (`anyhow`'s `{:#}`, as the tools do) reads
//! `scene.json: record 3: ./pyr.pat: No such file or directory (os error 2)`. The
//! main ones: [`StreamError`] (the stream), [`CameraError`], [`IoError`] (files,
//! images), [`ParseError`] (the text formats), [`SceneError`] (reading and
//! projecting a scene), [`scene::PartitionError`] (`polyfill3`'s job). Option
//! errors ([`error::OptionError`]) name the option by its field, so that a
//! front end can name it its own way. The library does not use `anyhow`.

#![warn(missing_docs)]

pub mod color;
pub mod error;
pub mod math;
pub mod progress;
pub mod text;
pub mod vector;

pub mod io;

pub mod pat;
pub mod quantize;

pub mod geom;
pub mod light;
pub mod stream;

pub mod camera;
pub mod view;

pub mod stripe;
pub mod texture;

pub mod raster;
pub mod scene;

#[cfg(feature = "cli")]
// The flag structs' doc comments are the tools' --help text and man pages,
// written for the command line; they are not rewritten to satisfy this lint.
#[allow(missing_docs)]
pub mod cli;

// The types a program meets first (see "First steps" and "Errors" above).
pub use camera::{Camera, CameraError};
pub use color::Rgb8;
pub use io::{Image, ImageFormat, IoError};
pub use pat::{Pattern, TRANSPARENT};
pub use raster::{Aa, Background};
pub use scene::{DrawOptions, Scene, SceneError};
pub use stream::{Record, StreamError};
pub use text::ParseError;
pub use view::View;

#[cfg(test)]
mod layering;
#[cfg(test)]
mod test_util;
