//! Every command-line test, built into one test binary (ripgrep's layout):
//! one module per tool, and `clitest!` gives each test its own directory.

#[macro_use]
mod util;

mod conventions;
mod deep_output;
mod documented;
mod faults;
mod host;
mod image_texture;
mod json;
mod lighting;
mod make;
mod man_pages;
mod mesh;
mod pat_from_image;
mod pat_info;
mod pat_tile;
mod polyfill3;
mod progress;
mod quadric;
mod scene_render;
mod skips;
mod stress;
mod stripe;
mod texture;
mod texture_filters;
mod transforms;
