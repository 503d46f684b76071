//! Cameras and the renderer: scenes far from the origin, polygons through the
//! eye plane or behind the camera, grazing angles, near = 0 and huge far/near.

use glam::DVec3;
use patkit::camera::Camera;
use patkit::math;
use patkit::raster::{render, try_project, Aa, Background, Cull};
use patkit::view::View;
use patkit::Rgb8;
use proptest::prelude::*;
use serde_json::json;

const W: u32 = 48;
const H: u32 = 36;

/// Largest difference, in 8-bit sRGB codes, allowed between a scene and the
/// same scene (camera included) translated 1e7 away: coordinates there keep
/// ~2e-9 absolute precision, a millionth of a pixel at these views, so at
/// most one rounding step of the 8-bit encoding may differ.
const TRANSLATED_MAX_CODE: u8 = 1;

fn view(camera: serde_json::Value) -> View {
    View::new(&Camera::from_json(&camera, "test").unwrap(), W, H)
}

fn perspective(eye: DVec3, center: DVec3, near: f64, far: f64) -> View {
    view(json!({
        "lookat": {"eye": eye.to_array(), "center": center.to_array()},
        "perspective": {"fovy": 60, "aspect": W as f64 / H as f64, "near": near, "far": far}
    }))
}

const COLORS: [Rgb8; 3] = [
    Rgb8([230, 40, 20]),
    Rgb8([20, 200, 60]),
    Rgb8([40, 60, 250]),
];

/// Renders polygons with exact anti-aliasing over black; asserts every
/// linear-light value is finite and in [0, 1]; returns the 8-bit image.
fn draw(v: &View, polys: &[Vec<DVec3>], aa: Aa) -> Vec<u8> {
    let mut screen = Vec::new();
    for (i, p) in polys.iter().enumerate() {
        if let Ok(s) = try_project(v, p, COLORS[i % 3], i as u32, Cull::None) {
            screen.push(s);
        }
    }
    let frame = render(&screen, &Background::color(Rgb8([0, 0, 0])), v, aa);
    for px in &frame.pixels {
        for &c in px {
            assert!(
                c.is_finite() && (-1e-6..=1.0 + 1e-6).contains(&c),
                "pixel {px:?}"
            );
        }
    }
    frame.to_image().data
}

fn max_diff(a: &[u8], b: &[u8]) -> u8 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap()
}

/// Rows (0 = bottom) holding a non-black pixel.
fn lit_rows(img: &[u8]) -> Vec<u32> {
    let ch = img.len() / (W * H) as usize;
    (0..H)
        .filter(|&y| {
            let top_row = (H - 1 - y) as usize;
            img[top_row * W as usize * ch..(top_row + 1) * W as usize * ch]
                .iter()
                .any(|&b| b != 0)
        })
        .collect()
}

fn tri(p: [[f64; 3]; 3]) -> Vec<DVec3> {
    p.iter().map(|&a| DVec3::from(a)).collect()
}

proptest! {
    #![proptest_config(crate::config())]

    #[test]
    fn translated_1e7_scene_matches_origin_within_1_code(
        pts in prop::array::uniform9(-2.0f64..2.0),
        depth in 3.0f64..20.0,
        dir in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let d = DVec3::from(dir);
        prop_assume!(d.length() > 0.1);
        let t = d.normalize() * 1e7;
        let scene = |t: DVec3| -> Vec<Vec<DVec3>> {
            vec![
                tri([[pts[0], pts[1], -depth + pts[2]], [pts[3], pts[4], -depth + pts[5]],
                     [pts[6], pts[7], -depth + pts[8]]]),
                tri([[-3.0, -2.0, -depth], [3.0, -2.0, -depth], [0.0, 2.5, -depth - 1.0]]),
            ]
            .into_iter()
            .map(|p| p.into_iter().map(|q| q + t).collect())
            .collect()
        };
        let a = draw(&perspective(DVec3::ZERO, -DVec3::Z, 0.5, 100.0), &scene(DVec3::ZERO), Aa::Exact);
        let b = draw(&perspective(t, t - DVec3::Z, 0.5, 100.0), &scene(t), Aa::Exact);
        prop_assert!(max_diff(&a, &b) <= TRANSLATED_MAX_CODE);
    }

    #[test]
    fn polygon_crossing_eye_plane_never_mirrors(
        x in prop::array::uniform4(-3.0f64..3.0),
        z_front in -30.0f64..-0.001, z_back in 0.001f64..30.0,
        below in 0.1f64..2.0, near_zero in prop::bool::ANY,
    ) {
        // A floor below the eye reaching from in front of it to behind it:
        // only its front part is drawn, always below the horizon. A mirrored
        // back part would show above the horizon.
        let near = if near_zero { 0.0 } else { 0.01 };
        let v = perspective(DVec3::ZERO, -DVec3::Z, near, 1000.0);
        let floor = vec![
            DVec3::new(x[0] - 4.0, -below, z_back),
            DVec3::new(x[1] + 4.0, -below, z_back),
            DVec3::new(x[2] + 4.0, -below, z_front),
            DVec3::new(x[3] - 4.0, -below, z_front),
        ];
        for aa in [Aa::Exact, Aa::None, Aa::Ss(4)] {
            let img = draw(&v, std::slice::from_ref(&floor), aa);
            prop_assert!(lit_rows(&img).iter().all(|&y| y < H / 2), "{aa:?}");
        }
    }

    #[test]
    fn polygon_wholly_behind_the_camera_draws_nothing(
        pts in prop::array::uniform9(-5.0f64..5.0), behind in 0.0f64..50.0,
    ) {
        let v = perspective(DVec3::ZERO, -DVec3::Z, 0.0, 100.0);
        let p = tri([[pts[0], pts[1], behind + pts[2].abs()],
                     [pts[3], pts[4], behind + pts[5].abs()],
                     [pts[6], pts[7], behind + pts[8].abs()]]);
        let img = draw(&v, &[p], Aa::Exact);
        prop_assert!(img.iter().all(|&b| b == 0));
    }

    #[test]
    fn grazing_polygon_stays_inside_its_screen_bounds_with_finite_pixels(
        tilt_e in -12.0f64..-1.0, y in -1.0f64..1.0,
    ) {
        // A wall almost edge-on to the eye: it may cover a thin band or
        // nothing, but never pixels outside the band of its vertices.
        let t = math::powf(10f64, tilt_e);
        let v = perspective(DVec3::ZERO, -DVec3::Z, 0.1, 100.0);
        let p = vec![
            DVec3::new(-50.0, y, -1.0),
            DVec3::new(50.0, y, -1.0),
            DVec3::new(50.0, y + t * 99.0, -100.0),
            DVec3::new(-50.0, y + t * 99.0, -100.0),
        ];
        let img = draw(&v, &[p], Aa::Exact);
        // Screen row of a point `dist` in front of the eye: y/dist mapped by
        // the 60° field.
        let row = |y: f64, dist: f64| (y / dist / math::tan(30f64.to_radians()) * 0.5 + 0.5) * H as f64;
        let (lo, hi) = (row(y, 1.0).min(row(y + t * 99.0, 100.0)), row(y, 1.0).max(row(y + t * 99.0, 100.0)));
        for r in lit_rows(&img) {
            prop_assert!(r as f64 >= lo.floor() - 1.0 && r as f64 <= hi.ceil() + 1.0, "{r} {lo} {hi}");
        }
    }
}

#[test]
fn near_zero_and_far_over_near_1e9_draw_the_same_nearby_scene() {
    // A scene between 2 and 20 units away looks the same through any depth
    // range that contains it: near 0, 1e-6..1e3 (far/near 1e9), 0.1..100.
    let scene = vec![
        tri([[-2.0, -1.5, -4.0], [2.5, -1.0, -6.0], [0.0, 2.0, -5.0]]),
        tri([[-3.0, 0.0, -2.0], [3.0, -0.5, -20.0], [1.0, 1.5, -8.0]]),
    ];
    let base = draw(
        &perspective(DVec3::ZERO, -DVec3::Z, 0.1, 100.0),
        &scene,
        Aa::Exact,
    );
    assert!(base.iter().any(|&b| b != 0));
    for (near, far) in [
        (0.0, 100.0),
        (0.0, 1e9),
        (1e-6, 1e3),
        (1e-3, 1e6),
        (1.0, 1e9),
    ] {
        let img = draw(
            &perspective(DVec3::ZERO, -DVec3::Z, near, far),
            &scene,
            Aa::Exact,
        );
        assert!(max_diff(&base, &img) <= 1, "near {near} far {far}");
    }
}
