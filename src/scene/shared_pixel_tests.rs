//! Textured polygons sharing minified pixels: demo 2 drawn a few pixels
//! wide, and two finely textured planes crossing inside their pixels.
//!
//! Every textured fragment here meets hundreds to thousands of texel cells
//! and shares its pixel with another polygon. It is swept whole and its
//! cells are cut from the part of it that shows
//! (`raster::coverage::CUT_LATER`); where the planes cross, the later
//! fragment overtakes the earlier and the cut follows the new visible part. Cut
//! cell by cell instead, these pixels cost each other a subtraction per
//! pair of cells (demo 2 at 8x8 took 34 s). The default must equal
//! `--reference`, which shares none of that code (scanline events and
//! strips), in every 8-bit pixel and to f32 storage in linear light.

use super::{DrawOptions, Scene};
use crate::camera::Camera;
use crate::color::Rgb8;
use crate::raster::{reference, Aa, Background, ScreenPoly};
use crate::view::View;
use std::path::Path;

/// The polygons of the stream `text` (patterns named relative to `dir`)
/// through the camera `camera` (docs/camera.md's JSON) at `w` x `h`.
fn project(
    text: &str,
    dir: &Path,
    camera: serde_json::Value,
    w: u32,
    h: u32,
) -> (View, Vec<ScreenPoly>) {
    let stream = Box::new(std::io::Cursor::new(text.to_owned()));
    let scene = Scene::read(stream, "scene.json", dir).unwrap();
    let camera = Camera::from_json(&camera, "camera").unwrap();
    let view = View::new(&camera, w, h);
    let polys = scene.project(&view, &DrawOptions::default(), 0).unwrap();
    (view, polys)
}

/// The default against the reference: certain everywhere, the same 8-bit
/// codes everywhere, and within `1e-6` in linear light.
fn assert_default_is_the_reference(name: &str, polys: &[ScreenPoly], view: &View) {
    let bg = Background::color(Rgb8([90, 140, 200]));
    let w = view.width;
    let exact = crate::raster::render(polys, &bg, view, Aa::Exact);
    let r = reference::render(polys, &bg, view, 24);
    let code = |v: f32| Rgb8::from_linear([v; 3]).0[0];
    for (i, (p, q, e)) in r.pixels_against(&exact).enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        assert!(
            p.iter().all(|&v| code(v - e) == code(v + e)),
            "{name}, pixel ({x}, {y}): the reference is uncertain ({e})"
        );
        assert_eq!(p.map(code), q.map(code), "{name}, pixel ({x}, {y})");
        for ch in 0..3 {
            assert!(
                (p[ch] - q[ch]).abs() <= 1e-6,
                "{name}, pixel ({x}, {y}): {p:?} against {q:?}"
            );
        }
    }
    assert_eq!(exact.estimated, 0, "{name}");
}

/// Demo 2 (the plain and the pyramid, thousands of texels each) through
/// its own camera at 8x8, 3x2 and 1x1 pixels.
#[test]
fn demo2_in_a_few_pixels_is_the_reference() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let text = std::fs::read_to_string(dir.join("demo2.json")).unwrap();
    let camera = serde_json::json!({
        "lookat": {"eye": [0, 100, -5], "center": [0, 0, -900]},
        "perspective": {"fovy": 55, "aspect": 1, "near": 0, "far": 1000}
    });
    for (w, h) in [(8, 8), (3, 2), (1, 1)] {
        let (view, polys) = project(&text, &dir, camera.clone(), w, h);
        assert_default_is_the_reference(&format!("demo 2 at {w}x{h}"), &polys, &view);
    }
}

/// Two planes crossing along x = 0, through the middle of a pixel column,
/// each under a pattern about a tenth of a pixel per texel (one turned
/// 30°): every pixel holds both planes' cells, and the column where they
/// cross is where fragments overtake.
#[test]
fn crossing_textured_planes_are_the_reference() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/patterns");
    let text = r#"[
        {"vertices": [[-4,-4,-1.2],[4,-4,1.2],[4,4,1.2],[-4,4,-1.2]],
         "pattern": {"file": "chex.pat", "incr": 0.07, "rotate": 30}},
        {"vertices": [[-4,-4,1.0],[4,-4,-1.0],[4,4,-1.0],[-4,4,1.0]],
         "pattern": {"file": "pyr.pat", "incr": 0.05}}
    ]"#;
    let camera = serde_json::json!({
        "lookat": {"eye": [0, 0, 0], "center": [0, 0, -1]},
        "ortho": {"left": -3.7, "right": 3.6, "bottom": -3.3, "top": 3.9, "near": -10, "far": 10}
    });
    for (w, h) in [(8, 8), (5, 3)] {
        let (view, polys) = project(text, &dir, camera.clone(), w, h);
        assert_default_is_the_reference(&format!("crossing planes at {w}x{h}"), &polys, &view);
    }
}
