//! A one-texel checker ground seen from a low camera in perspective, its
//! horizon in frame (issue 15, item 6): the case where `--aa exact` once
//! fell back silently to the EWA mean. The pattern is turned 0°, 45° and an
//! irrational angle, so the cells meet the footprints along and across
//! their diagonals. Three routes are compared: the default (texel cells
//! cut from the part that shows and summed), `--reference`
//! (scanline events and Gauss–Legendre strips, none of that code), and a
//! brute-force point-sampled mean on the rows just under the horizon,
//! which reads only the map and the texels.
//!
//! Also a coarse pattern minified about 150 times on a flat quad, each
//! pixel over 16,384 to 65,536 texel cells: what the far rows of
//! `bench/texture.sh`'s photographed plane meet, where the default once
//! estimated pixels the reference is certain of (up to 22 codes off).

use super::{DrawOptions, Scene};
use crate::camera::Camera;
use crate::color::{linear_to_srgb16, Rgb8};
use crate::raster::{reference, Aa, Background};
use crate::view::View;

const WIDTH: u32 = 640;
const HEIGHT: u32 = 360;

/// The `.pat` text of a pattern `size` texels a side in two colours,
/// texel (col, row) taking colour `pick(col, row)` (0 or 1).
fn two_colour_pat(size: u32, colours: [Rgb8; 2], pick: impl Fn(u32, u32) -> u32) -> String {
    let texels = (0..size * size)
        .map(|i| pick(i % size, i / size) as u16)
        .collect();
    crate::pat::Pattern::new(size, colours.to_vec(), texels)
        .unwrap()
        .to_canonical()
}

/// The ground with its checker turned `rotate` degrees, projected.
fn ground(rotate: f64) -> (View, Vec<crate::raster::ScreenPoly>) {
    let dir = std::env::temp_dir().join(format!(
        "patkit-horizon-{}-{}",
        std::process::id(),
        rotate.to_bits()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let colours = [Rgb8([230, 230, 230]), Rgb8([20, 20, 120])];
    let pat = two_colour_pat(16, colours, |col, row| (col + row) % 2);
    std::fs::write(dir.join("c.pat"), pat).unwrap();
    let stream = format!(
        r#"{{"vertices": [[-20000,0,20000],[20000,0,20000],[20000,0,-20000],[-20000,0,-20000]], "pattern": {{"file": "c.pat", "incr": 1, "rotate": {rotate}}}}}"#
    );
    let scene = Scene::read(Box::new(std::io::Cursor::new(stream)), "ground.json", &dir).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let camera = serde_json::json!({
        "lookat": {"eye": [0.3, 3, 0.7], "center": [0.3, 3, -100.7]},
        "perspective": {"fovy": 60, "aspect": "auto", "near": 0.5, "far": 100000}
    });
    projected(&scene, camera, WIDTH, HEIGHT)
}

/// `scene` through the camera `camera` (its JSON form) at `w` x `h`, and
/// the view.
fn projected(
    scene: &Scene,
    camera: serde_json::Value,
    w: u32,
    h: u32,
) -> (View, Vec<crate::raster::ScreenPoly>) {
    let camera = Camera::from_json(&camera, "camera").unwrap();
    let view = View::new(&camera, w, h);
    let polys = scene.project(&view, &DrawOptions::default(), 0).unwrap();
    (view, polys)
}

/// The 8-bit code of linear `v` (one channel).
fn code(v: f64) -> u8 {
    Rgb8::from_linear([v as f32; 3]).0[0]
}

/// A pixel where `exact`'s 8-bit code is not the reference's: (x, y from
/// the bottom, exact's codes, the reference's codes).
type Off = (u32, u32, [u8; 3], [u8; 3]);

/// How many pixels of `exact` (`width` wide) the reference is certain of
/// in 8 bits (its error estimate leaves every channel's code unchanged),
/// and those of them where `exact` gives another code.
fn against_certain_reference(
    r: &reference::Reference,
    exact: &crate::raster::Frame,
    width: u32,
) -> (u32, Vec<Off>) {
    let (mut certain, mut off) = (0, Vec::new());
    for (i, (p, q, e)) in r.pixels_against(exact).enumerate() {
        let sure = p
            .iter()
            .all(|&v| code(v as f64 - e as f64) == code(v as f64 + e as f64));
        if !sure {
            continue;
        }
        certain += 1;
        let (want, got) = (p.map(|v| code(v as f64)), q.map(|v| code(v as f64)));
        if got != want {
            off.push((i as u32 % width, i as u32 / width, got, want));
        }
    }
    (certain, off)
}

/// The default, the reference and brute force on the checker ground at 0°,
/// 45° and an irrational angle:
///
/// - wherever the reference is certain in 8 bits (its error estimate
///   leaves every channel's code unchanged), the default gives its code,
///   and the reference is certain in all but the row over the ground's
///   far edge (a pixel there meets about two million texels);
/// - the default reports the fragments it estimated (that row), never
///   more than two rows' worth;
/// - where the reference's estimate is at most 1e-6 (all but two rows),
///   the two agree in 16-bit output too, within a code (measured: 0);
/// - on the two rows under the far-edge row (500 to 1,000 texels per
///   pixel), both lie within a code of a 512 x 512 point-sampled mean at
///   24 columns.
#[test]
fn the_default_equals_the_reference_wherever_the_reference_is_certain() {
    let bg = Background::color(Rgb8([90, 140, 200]));
    for rotate in [0.0, 45.0, 100.0 / std::f64::consts::E] {
        let (view, polys) = ground(rotate);
        let exact = crate::raster::render(&polys, &bg, &view, Aa::Exact);
        let r = reference::render(&polys, &bg, &view, 6);
        let (certain, off) = against_certain_reference(&r, &exact, WIDTH);
        let all = WIDTH * HEIGHT;
        // In 16 bits: where the reference's estimate is below a 16-bit
        // code, the two agree within a few codes.
        let (mut sure16, mut worst16) = (0u32, 0u16);
        for (p, q, e) in r.pixels_against(&exact) {
            if e > 1e-6 {
                continue;
            }
            sure16 += 1;
            for ch in 0..3 {
                let (a, b) = (linear_to_srgb16(p[ch]), linear_to_srgb16(q[ch]));
                worst16 = worst16.max(a.abs_diff(b));
            }
        }
        assert!(
            sure16 >= all - 2 * WIDTH,
            "rotate {rotate}: {sure16} pixels sure to 1e-6"
        );
        assert!(
            worst16 <= 1,
            "rotate {rotate}: {worst16} 16-bit codes apart"
        );
        assert!(
            off.is_empty(),
            "rotate {rotate}: {} pixels off: {:?}",
            off.len(),
            &off[..off.len().min(8)]
        );
        assert!(
            certain >= all - WIDTH,
            "rotate {rotate}: only {certain} of {all} certain"
        );
        assert!(
            exact.estimated > 0 && exact.estimated <= 2 * WIDTH as u64,
            "rotate {rotate}: {} estimated",
            exact.estimated
        );
        for y in [HEIGHT / 2 - 2, HEIGHT / 2 - 3] {
            for x in (0..WIDTH).step_by((WIDTH / 24) as usize) {
                let want = brute_force(&polys[0], &bg, x, y, 512).map(code);
                let i = (y * WIDTH + x) as usize;
                for (name, got) in [
                    ("default", exact.pixels[i]),
                    ("reference", r.frame.pixels[i]),
                ] {
                    let got = got.map(|v| code(v as f64));
                    let worst = (0..3).map(|ch| got[ch].abs_diff(want[ch])).max().unwrap();
                    assert!(
                        worst <= 1,
                        "rotate {rotate}, pixel ({x}, {y}): {name} {got:?}, brute force {want:?}"
                    );
                }
            }
        }
    }
}

/// A 256-texel pattern of 32-texel blocks on a flat quad seen face on, 150
/// texels a pixel, turned 100/e degrees: every pixel meets about 23,000
/// cells (past the 16,384 at which the default used to estimate), the
/// reference meets about 420 texel lines a pixel and stays certain, and a
/// pixel's box mean depends on where the block edges cross it, which the
/// EWA estimate's Gaussian weights do not follow. The quad's edges cross
/// pixels, so partial fragments (the photographed plane's 10 bad pixels lay
/// on its sides) are checked too.
#[test]
fn a_pattern_minified_150_times_is_integrated_exactly() {
    let (w, h) = (4, 3);
    let dir = std::env::temp_dir().join(format!("patkit-minified-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let colours = [Rgb8([240, 200, 40]), Rgb8([30, 60, 160])];
    let pat = two_colour_pat(256, colours, |col, row| (col / 32 + row / 32) % 2);
    std::fs::write(dir.join("blocks.pat"), pat).unwrap();
    let stream = format!(
        r#"{{"vertices": [[0.3,0.2,-1],[3.7,0.5,-1],[3.6,2.8,-1],[0.4,2.6,-1]], "pattern": {{"file": "blocks.pat", "incr": {}, "rotate": {}}}}}"#,
        1.0 / 150.0,
        100.0 / std::f64::consts::E
    );
    let scene = Scene::read(Box::new(std::io::Cursor::new(stream)), "quad.json", &dir).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let camera = serde_json::json!({
        "ortho": {"left": 0, "right": w, "bottom": 0, "top": h, "near": 0, "far": 10}
    });
    let (view, polys) = projected(&scene, camera, w, h);
    let bg = Background::color(Rgb8::BLACK);
    let exact = crate::raster::render(&polys, &bg, &view, Aa::Exact);
    assert_eq!(exact.estimated, 0);
    let r = reference::render(&polys, &bg, &view, 6);
    let (certain, off) = against_certain_reference(&r, &exact, w);
    assert!(off.is_empty(), "{} pixels off: {:?}", off.len(), off);
    assert_eq!(certain, w * h, "the reference is certain everywhere");
}

/// The mean linear colour of pixel `(x, y)` (frame rows from the bottom) by
/// `n` x `n` point samples, one at a random place in each square of a
/// regular grid (a grid's own points alias with the checker): the ground's
/// texel where a sample lies inside its screen polygon, the background
/// elsewhere. Reads only the polygon's outline, its texture map and its
/// texels.
fn brute_force(
    ground: &crate::raster::ScreenPoly,
    bg: &Background,
    x: u32,
    y: u32,
    n: u32,
) -> [f64; 3] {
    let tex = ground.texture().unwrap();
    let v = ground.verts();
    let inside = |p: glam::DVec2| {
        (0..v.len()).all(|i| (v[(i + 1) % v.len()] - v[i]).perp_dot(p - v[i]) >= 0.0)
    };
    let mut sum = [0.0f64; 3];
    let mut rng = crate::test_util::Rng(0x9e37_79b9_7f4a_7c15 ^ ((x as u64) << 32 | y as u64));
    for a in 0..n {
        for b in 0..n {
            let p = glam::DVec2::new(
                x as f64 + (a as f64 + rng.next()) / n as f64,
                y as f64 + (b as f64 + rng.next()) / n as f64,
            );
            let c = if inside(p) {
                let t = tex.map.uv(p.x, p.y);
                tex.texel(t.x.floor() as i64, t.y.floor() as i64).unwrap()
            } else {
                bg.at(x, y)
            };
            for ch in 0..3 {
                sum[ch] += c[ch];
            }
        }
    }
    sum.map(|s| s / (n * n) as f64)
}

/// The striped ground and wall of `bench/stripe.sh` (runway stripes, the
/// ground to 2,000 units), 1024x768: wherever the reference is certain in
/// 8 bits, the default gives its code. Where the wall hides part of a
/// ground fragment, the stripes are averaged over the part that shows: 33
/// pixels along the wall's sides were one code off when the whole
/// fragment's average was taken.
#[test]
fn striped_ground_default_equals_the_reference_wherever_it_is_certain() {
    let (w, h) = (1024, 768);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/stripes");
    let stream = r#"
        {"vertices": [[-200, 0, 0], [200, 0, 0], [200, 0, -2000], [-200, 0, -2000]], "color": [180, 170, 150], "stripe": {"map": "runway.map", "spacing": 0.05, "yaw": 90}}
        {"vertices": [[-20, 0, -60], [20, 0, -60], [20, 25, -60], [-20, 25, -60]], "color": [200, 120, 90], "stripe": {"map": "runway.map", "spacing": 0.02, "yaw": 30, "pitch": 20}}
    "#;
    let scene = Scene::read(Box::new(std::io::Cursor::new(stream)), "stripe.json", &dir).unwrap();
    let camera = serde_json::json!({
        "lookat": {"eye": [0, 8, 10], "center": [0, 4, -100]},
        "perspective": {"fovy": 50, "aspect": 1.333, "near": 1, "far": 3000}
    });
    let (view, polys) = projected(&scene, camera, w, h);
    let bg = Background::color(Rgb8::BLACK);
    let exact = crate::raster::render(&polys, &bg, &view, Aa::Exact);
    let r = reference::render(&polys, &bg, &view, 24);
    let (certain, off) = against_certain_reference(&r, &exact, w);
    assert!(
        off.is_empty(),
        "{} pixels off: {:?}",
        off.len(),
        &off[..off.len().min(8)]
    );
    // Measured: all but 16 (where the stripes reach the ground's horizon).
    assert!(certain >= w * h - 64, "only {certain} certain");
    assert_eq!(exact.estimated, 0);
}
