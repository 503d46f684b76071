//! The library without the command line: the thesis's demo 2 the Fig. 5.1
//! way (one brick face placed by four instances on the checkered plain), its
//! patterns placed and integrated over texel cells directly, rendered with
//! exact anti-aliasing through the thesis's camera.
//!
//! `cargo run --release --example render_scene -- OUT.png` writes the image;
//! it is byte-identical to
//! `scene-render --perspective 55,1,0,1000 --lookat 0,100,-5,0,0,-900 --cull back
//! --background-pattern fixtures/patterns/bkgrnd.pat -o OUT.png fixtures/scenes/demo2-fig51.json`
//! (the test `the_library_example_renders_what_scene_render_renders` checks).

use glam::DVec3;
use patkit::camera::{Aspect, Camera, CameraSpec, IrisProjection, IrisSpec, LookAt, Perspective};
use patkit::io::{ImageFormat, PngOptions};
use patkit::raster::{Aa, Background, Cull};
use patkit::scene::{self, DrawOptions, Scene};
use patkit::texture::Texels;
use patkit::view::View;
use patkit::{Pattern, Rgb8};

/// The library's errors are ordinary `std::error::Error`s, each typed by its
/// stage (`CameraError`, `SceneError`, `ParseError`, `IoError`): `?` gathers
/// them into a `Box<dyn Error>` with no error crate.
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .ok_or("usage: render_scene OUT.png")?;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));

    // IRIS GL: perspective(550, 1.0, 0.0, 1000.0); lookat(0,100,-5, 0,0,-900, 0).
    let camera = Camera::from_spec(&CameraSpec::Iris(IrisSpec {
        lookat: Some(LookAt {
            eye: DVec3::new(0.0, 100.0, -5.0),
            center: DVec3::new(0.0, 0.0, -900.0),
            up: None,
            twist: None,
        }),
        projection: vec![IrisProjection::Perspective(Perspective {
            fovy: 55.0,
            aspect: Aspect::Ratio(1.0),
            near: 0.0,
            far: 1000.0,
        })],
    }))?;
    let (width, height) = (1024, 768);
    let view = View::new(&camera, width, height);

    let scene = Scene::load(
        &root
            .join("fixtures/scenes/demo2-fig51.json")
            .to_string_lossy(),
    )?;
    let options = DrawOptions {
        cull: Cull::Back,
        ..DrawOptions::default()
    };
    let polygons = scene.project(&view, &options, 0)?;

    // colorclear with bkgrnd.pat behind everything, black where it is transparent.
    let bkgrnd = Pattern::read_file(&root.join("fixtures/patterns/bkgrnd.pat"))?;
    let background = Background::new(Rgb8::BLACK, Some(Texels::new(&bkgrnd)));
    let image = scene::render(&polygons, &background, &view, Aa::Exact);
    image.save_with(&out, ImageFormat::Png, PngOptions::GENERAL)?;
    Ok(())
}
