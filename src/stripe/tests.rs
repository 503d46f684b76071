//! Per-pixel shading against the exact reference.

use super::*;
use crate::camera::Camera;
use glam::DVec3;
use serde_json::json;

/// Supersampling with k x k points per pixel misses at most the area of the
/// sample cells cut by iso-lines: for the few stripes crossing these pixels a
/// 1/64 budget in linear light is generous and still far below a visible error.
const SUPERSAMPLE_TOLERANCE: f64 = 1.0 / 64.0;

/// A deterministic pseudo-random map (xorshift), so tests need no files.
fn noise_map(n: usize, seed: u64, fade: Fade) -> ModulationMap {
    let mut s = seed;
    let values = (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 56) as u8
        })
        .collect();
    ModulationMap::new(values, fade).unwrap()
}

fn ground_camera() -> Camera {
    Camera::from_json(
        &json!({
            "lookat": {"eye": [0, 1.7, 0], "center": [0, 0.2, -20], "up": [0, 1, 0]},
            "perspective": {"fovy": 50, "aspect": 4.0/3.0, "near": 0.1, "far": 1e5}
        }),
        "test",
    )
    .unwrap()
}

fn ground_texture(map: &ModulationMap, mode: LodMode, w: u32, h: u32) -> StripeTexture {
    let v = PatternVector::new(
        Orientation::YawPitch {
            yaw: 60.0,
            pitch: 0.0,
        },
        0.02,
        5.0,
    )
    .unwrap();
    let n = map.len();
    let mapping = ScreenMapping::new(
        &ground_camera(),
        w,
        h,
        DVec3::Y,
        DVec3::ZERO,
        v.gradient(n),
        v.p0(n),
    )
    .unwrap();
    StripeTexture::new(
        Arc::new(Modulation::new(map, &Translation::identity())),
        mapping,
        Select::default(),
        Rgb8([200, 180, 120]),
        mode,
    )
}

/// RMSE in 8-bit sRGB over RGB of `shade` against the reference, over the
/// pixels the reference can average; and the number of such pixels.
fn rmse(t: &StripeTexture, w: u32, h: u32) -> (f64, usize) {
    let (mut sum, mut count) = (0.0, 0usize);
    for py in 0..h {
        for px in 0..w {
            let Ok(r) = t.reference_shade(px, py) else {
                continue;
            };
            let s = t.shade(px, py);
            for c in 0..3 {
                let d = s.0[c] as f64 - r.0[c] as f64;
                sum += d * d;
            }
            count += 1;
        }
    }
    ((sum / (3 * count) as f64).sqrt(), count)
}

#[test]
fn reference_agrees_with_supersampling() {
    let map = noise_map(64, 7, Fade::None);
    let t = ground_texture(&map, LodMode::Blend, 64, 48);
    let k = 64;
    let mut checked = 0;
    for &(px, py) in &[(10u32, 5u32), (32, 20), (50, 12), (3, 1)] {
        let Ok(exact) = t.reference_modulation(&[
            DVec2::new(px as f64, py as f64),
            DVec2::new(px as f64 + 1.0, py as f64),
            DVec2::new(px as f64 + 1.0, py as f64 + 1.0),
            DVec2::new(px as f64, py as f64 + 1.0),
        ]) else {
            continue;
        };
        let mut sum = 0.0;
        for j in 0..k {
            for i in 0..k {
                let x = px as f64 + (i as f64 + 0.5) / k as f64;
                let y = py as f64 + (j as f64 + 0.5) / k as f64;
                sum += t.modulation.crisp(t.mapping.p(x, y));
            }
        }
        let approx = sum / (k * k) as f64;
        assert!(
            (exact - approx).abs() < SUPERSAMPLE_TOLERANCE,
            "({px},{py}) {exact} {approx}"
        );
        checked += 1;
    }
    assert!(checked >= 3);
}

#[test]
fn reference_of_a_pixel_inside_one_sample_is_that_sample() {
    // A wall facing the camera, one map sample 10 pixels wide.
    let cam = Camera::from_json(&json!({"ortho2": [0, 100, 0, 100]}), "t").unwrap();
    let map = ModulationMap::new(vec![0, 255, 128, 64], Fade::None).unwrap();
    let v = PatternVector::new(
        Orientation::YawPitch {
            yaw: 0.0,
            pitch: 0.0,
        },
        10.0,
        0.0,
    )
    .unwrap();
    let mapping = ScreenMapping::new(
        &cam,
        100,
        100,
        DVec3::Z,
        DVec3::ZERO,
        v.gradient(4),
        v.p0(4),
    )
    .unwrap();
    let t = StripeTexture::new(
        Arc::new(Modulation::new(&map, &Translation::identity())),
        mapping,
        Select::default(),
        Rgb8::WHITE,
        LodMode::Blend,
    );
    assert_eq!(t.reference_shade(12, 40).unwrap(), Rgb8([255; 3]));
    assert_eq!(t.shade(12, 40), Rgb8([255; 3]));
    assert_eq!(t.shade(25, 40), Rgb8([128; 3]));
    // Pixel 9 is all sample 0 (x in [9, 10)); a pixel across x = 10 would be half.
    assert_eq!(t.reference_shade(9, 0).unwrap(), Rgb8::BLACK);
    let half = t
        .reference_modulation(&[
            DVec2::new(9.5, 0.0),
            DVec2::new(10.5, 0.0),
            DVec2::new(10.5, 1.0),
            DVec2::new(9.5, 1.0),
        ])
        .unwrap();
    assert!((half - 0.5).abs() < 1e-15, "{half}");
}

#[test]
fn select_and_face_colour_modulate_only_the_chosen_channels() {
    let cam = Camera::from_json(&json!({"ortho2": [0, 8, 0, 8]}), "t").unwrap();
    let map = ModulationMap::new(vec![0, 255], Fade::None).unwrap();
    let v = PatternVector::new(
        Orientation::YawPitch {
            yaw: 0.0,
            pitch: 0.0,
        },
        4.0,
        0.0,
    )
    .unwrap();
    let mapping =
        ScreenMapping::new(&cam, 8, 8, DVec3::Z, DVec3::ZERO, v.gradient(2), v.p0(2)).unwrap();
    let modulation = Arc::new(Modulation::new(&map, &Translation::identity()));
    let face = Rgb8([200, 100, 50]);
    let t = StripeTexture::new(
        modulation,
        mapping,
        Select([false, true, false]),
        face,
        LodMode::Blend,
    );
    assert_eq!(t.shade(1, 1), Rgb8([200, 0, 50]));
    assert_eq!(t.shade(5, 1), face);
}

#[test]
fn translation_is_applied_per_sample() {
    let map = ModulationMap::new(vec![100, 200], Fade::None).unwrap();
    let m = Modulation::new(&map, &Translation::brightness(-100.0).unwrap());
    assert_eq!(m.crisp(0.1), 0.0);
    assert!((m.crisp(0.6) - crate::color::srgb_to_linear_f64(100.0 / 255.0)).abs() < 1e-15);
    // Level 1 is the linear-light average of the translated samples.
    assert!((m.sample(1, 0.3) as f64 - m.crisp(0.6) / 2.0).abs() < 1e-7);
}

#[test]
fn blended_levels_beat_the_nearest_level_on_a_receding_ground_plane() {
    let (w, h) = (160, 120);
    let map = noise_map(1024, 99, Fade::None);
    let (nearest, n) = rmse(&ground_texture(&map, LodMode::Nearest, w, h), w, h);
    let (blend, _) = rmse(&ground_texture(&map, LodMode::Blend, w, h), w, h);
    let (cig, _) = rmse(&ground_texture(&map, LodMode::Cig, w, h), w, h);
    eprintln!("ground plane {w}x{h}, {n} pixels: RMSE nearest {nearest:.3}, blend {blend:.3}, cig {cig:.3}");
    assert!(n > 5000, "{n}");
    assert!(blend < nearest, "blend {blend} nearest {nearest}");
    // The seed's rule reads one entry per level (no interpolation within a
    // level), so it is only checked to be finite here; the numbers above are
    // the comparison.
    assert!(cig.is_finite());
}

/// Two exact integrals of the same function differ by f64 rounding only; the
/// comparison runs through f32 colours, so 1e-6 (a few f32 ulps of values up
/// to 1) is the budget.
const EXACT_AGREEMENT: f64 = 1e-6;

proptest::proptest! {
    /// The fixed-buffer integrator of `--aa exact` is the reference's
    /// computation: wherever it answers, on any pixel-sized convex fragment,
    /// it agrees with `reference_modulation`.
    #[test]
    fn few_crossing_integral_is_the_reference(
        px in 0u32..320, py in 0u32..120,
        cut in 0.0f64..1.0, slope in -3.0f64..3.0, seed in 1u64..1000,
    ) {
        let t = ground_texture(&noise_map(64, seed, Fade::None), LodMode::Blend, 320, 240);
        let (x, y) = (px as f64, py as f64);
        // The pixel square cut by the line v = cut + slope (u - 0.5): a
        // convex fragment of 3 to 5 vertices, as coverage.rs makes them.
        let square = crate::geom::polygon::pixel_square(px, py);
        let f = |v: DVec2| (v.y - y) - (cut + slope * (v.x - x - 0.5));
        let mut frag = Vec::new();
        for i in 0..4 {
            let (p, q) = (square[i], square[(i + 1) % 4]);
            if f(p) <= 0.0 {
                frag.push(p);
            }
            if (f(p) < 0.0) != (f(q) < 0.0) && f(p) != 0.0 && f(q) != 0.0 {
                frag.push(p + (q - p) * (f(p) / (f(p) - f(q))));
            }
        }
        for shape in [&square[..], &frag[..]] {
            if let Some(m) = t.box_modulation_few(shape) {
                let r = t.reference_modulation(shape).unwrap();
                proptest::prop_assert!((m - r).abs() <= EXACT_AGREEMENT, "{m} vs {r}");
            }
        }
    }
}

#[test]
fn fragments_are_exact_where_few_samples_cross_and_filtered_elsewhere() {
    let (w, h) = (320, 240);
    // The seed's rule keeps FEW_CROSSINGS, so both paths run; the default
    // modes integrate every fragment short of the horizon exactly.
    let t = ground_texture(&noise_map(64, 7, Fade::None), LodMode::Cig, w, h);
    let blend = ground_texture(&noise_map(64, 7, Fade::None), LodMode::Blend, w, h);
    for py in (0..110).step_by(3) {
        for px in (0..w).step_by(7) {
            if let Ok(r) = blend.reference_linear(px, py) {
                let (c, estimated) = blend.fragment_linear(px, py, &[]);
                assert!(!estimated, "{px},{py}");
                for ch in 0..3 {
                    assert!((c[ch] as f64 - r[ch]).abs() <= EXACT_AGREEMENT, "{px},{py}");
                }
            }
        }
    }
    let (mut exact, mut filtered) = (0, 0);
    for py in (0..110).step_by(3) {
        for px in (0..w).step_by(7) {
            let Ok(r) = t.reference_linear(px, py) else {
                continue;
            };
            let (c, estimated) = t.fragment_linear(px, py, &[]);
            assert!(
                !estimated,
                "--cig-compat's filter is asked for, not an estimate"
            );
            let square = [
                DVec2::new(px as f64, py as f64),
                DVec2::new(px as f64 + 1.0, py as f64),
                DVec2::new(px as f64 + 1.0, py as f64 + 1.0),
                DVec2::new(px as f64, py as f64 + 1.0),
            ];
            if t.box_modulation_few(&square).is_some() {
                exact += 1;
                for ch in 0..3 {
                    assert!((c[ch] as f64 - r[ch]).abs() <= EXACT_AGREEMENT, "{px},{py}");
                }
            } else {
                filtered += 1;
                let centre = t.linear_at(px as f64 + 0.5, py as f64 + 0.5);
                assert_eq!(
                    c, centre,
                    "{px},{py}: the full square's centroid is the centre"
                );
            }
        }
    }
    // The near rows are magnified, the far ones minified: both paths ran.
    assert!(
        exact > 50 && filtered > 50,
        "{exact} exact, {filtered} filtered"
    );
}

#[test]
fn footprint_scales_the_level_of_detail() {
    let t = ground_texture(&noise_map(64, 3, Fade::None), LodMode::Blend, 320, 240);
    let half = t.clone().with_footprint(0.5);
    // At a minified pixel, halving the footprint reads one level finer.
    let (x, y) = (100.5, 110.5);
    let (_, gx, gy) = t.mapping.p_and_gradient(x, y);
    let m = &t.modulation;
    let full = LodMode::Blend.select(gx, gy, m.len(), m.levels());
    let finer = LodMode::Blend.select(gx * 0.5, gy * 0.5, m.len(), m.levels());
    assert!(full.level as f32 + full.a - (finer.level as f32 + finer.a) > 0.99);
    assert_eq!(half.modulation_at(x, y), m.lookup(t.mapping.p(x, y), finer));
}

proptest::proptest! {
    #[test]
    fn floor_i64_is_floor(x in -1e15f64..1e15, frac in proptest::sample::select(vec![0.0, 0.5, -0.5, 1e-9, -1e-9])) {
        let v = x.trunc() + frac;
        proptest::prop_assert_eq!(floor_i64(v), v.floor() as i64);
        proptest::prop_assert_eq!(floor_i64(x), x.floor() as i64);
    }
}

#[test]
fn floor_i64_edges() {
    for v in [
        0.0,
        -0.0,
        -1.0,
        -1.5,
        2.0,
        1e300,
        -1e300,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        assert_eq!(floor_i64(v), v.floor() as i64, "{v}");
    }
}
