//! patkit: texture patterns (`.pat`) and textured-polygon rendering.
//!
//! One module per idea: [`pat`] is the file format, [`color`] sRGB and linear
//! light, [`io`] streams and images, [`cli`] the shared command-line plumbing
//! and each tool's arguments. The binaries in `src/bin/` are one-line shims.

pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod color;
pub mod geom;
pub mod io;
pub mod pat;
pub mod quantize;
pub mod raster;
pub mod scene;
pub mod stream;
pub mod stripe;
mod text;
pub mod texture;
pub mod view;

pub use color::Rgb8;
pub use pat::{ParseError, Pattern, TRANSPARENT};

#[cfg(test)]
mod layering;
#[cfg(test)]
mod test_util;
