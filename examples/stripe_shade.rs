//! The per-pixel stripe shader alone, before `scene-render` calls it: a
//! receding ground plane and a wall facing the camera at 1024x768, shaded with
//! the nearest level, blended levels and the seed's rule (`--cig-compat`),
//! each timed (the linear-light colour per pixel, before encoding) and
//! compared with the exact box-filtered reference.
//!
//! Coverage is decided per pixel by casting the rays of its four corners:
//! only pixels that lie wholly on one face are counted, so the error measured
//! is the texture's alone (edges are the renderer's business).
//!
//! Usage: `cargo run --release --example stripe_shade -- [MAP] [REPEATS]`
//! (default `fixtures/stripes/runway.map`, 5 repeats, timed after a warm-up
//! frame and reported as their median; prints markdown).

use glam::DVec3;
use patkit::camera::Camera;
use patkit::math;
use patkit::stripe::mapping::unproject_to_plane;
use patkit::stripe::{
    LodMode, Modulation, ModulationMap, Orientation, PatternVector, RefPlane, ScreenMapping,
    Select, StripeTexture, Translation,
};
use patkit::Rgb8;
use std::sync::Arc;
use std::time::Instant;

const W: u32 = 1024;
const H: u32 = 768;

/// One face: its plane, bounds test and texture.
struct Face {
    normal: DVec3,
    point: DVec3,
    inside: fn(DVec3) -> bool,
    vector: PatternVector,
    colour: Rgb8,
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let map_path = args
        .get(1)
        .map_or("fixtures/stripes/runway.map", String::as_str);
    let repeats: usize = args.get(2).map_or(Ok(5), |s| s.parse::<usize>())?.max(1);
    let map = ModulationMap::read_file(std::path::Path::new(map_path))?;
    let camera = Camera::from_json(
        &serde_json::json!({
            "lookat": {"eye": [0, 1.7, 0], "center": [0, 1.2, -30], "up": [0, 1, 0]},
            "perspective": {"fovy": 50, "aspect": W as f64 / H as f64, "near": 0.1, "far": 1e5}
        }),
        "stripe_shade",
    )?;
    let faces = [
        // The ground: 400 x 2000 units, stripes 30 degrees off North.
        Face {
            normal: DVec3::Y,
            point: DVec3::ZERO,
            inside: |p| p.x.abs() <= 200.0 && p.z <= 0.0 && p.z >= -2000.0,
            vector: PatternVector::new(
                Orientation::Plane {
                    plane: RefPlane::Zx,
                    theta: 30.0,
                },
                0.01,
                0.0,
            )?,
            colour: Rgb8([140, 150, 110]),
        },
        // A wall facing the camera 40 units away, vertical stripes.
        Face {
            normal: DVec3::Z,
            point: DVec3::new(0.0, 0.0, -40.0),
            inside: |p| p.x.abs() <= 12.0 && p.y >= 0.0 && p.y <= 9.0,
            vector: PatternVector::new(
                Orientation::Plane {
                    plane: RefPlane::Xy,
                    theta: 0.0,
                },
                0.005,
                0.0,
            )?,
            colour: Rgb8([200, 190, 180]),
        },
    ];
    let modulation = Arc::new(Modulation::new(&map, &Translation::identity()));
    let n = map.len();

    // Which face each pixel lies wholly on (the wall is in front of the ground).
    let eye = camera.eye_position().expect("a perspective camera");
    let hit = |x: f64, y: f64| -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        for (i, f) in faces.iter().enumerate() {
            let Some(p) = unproject_to_plane(&camera, W, H, x, y, f.normal, f.point) else {
                continue;
            };
            let clip = camera.world_to_clip() * p.extend(1.0);
            if clip.w <= 0.0 || !(f.inside)(p) {
                continue;
            }
            let d = (p - eye).length();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i));
            }
        }
        best.map(|(_, i)| i)
    };
    let mut pixels: Vec<Vec<(u32, u32)>> = vec![Vec::new(); faces.len()];
    for py in 0..H {
        for px in 0..W {
            let (x, y) = (px as f64, py as f64);
            let corners = [
                hit(x, y),
                hit(x + 1.0, y),
                hit(x, y + 1.0),
                hit(x + 1.0, y + 1.0),
            ];
            if let Some(f) = corners[0] {
                if corners.iter().all(|&c| c == Some(f)) {
                    pixels[f].push((px, py));
                }
            }
        }
    }

    let texture = |f: &Face, mode: LodMode| -> anyhow::Result<StripeTexture> {
        let mapping = ScreenMapping::new(
            &camera,
            W,
            H,
            f.normal,
            f.point,
            f.vector.gradient(n),
            f.vector.p0(n),
        )?;
        Ok(StripeTexture::new(
            Arc::clone(&modulation),
            mapping,
            Select::default(),
            f.colour,
            mode,
        ))
    };

    // The reference, once per face.
    let t0 = Instant::now();
    let mut reference: Vec<Vec<Option<Rgb8>>> = Vec::new();
    for (f, px) in faces.iter().zip(&pixels) {
        let t = texture(f, LodMode::Blend)?;
        reference.push(
            px.iter()
                .map(|&(x, y)| t.reference_shade(x, y).ok())
                .collect(),
        );
    }
    let reference_time = t0.elapsed().as_secs_f64();

    println!("Map `{map_path}` ({n} entries, fade {}), {W}x{H}: ground {} px, wall {} px (interior pixels); reference {reference_time:.2} s.\n",
        map.fade().word(), pixels[0].len(), pixels[1].len());
    println!("| mode | ms / frame | ns / pixel | RMSE ground | RMSE wall | RMSE all | PSNR dB | > 4 off |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let total: usize = pixels.iter().map(Vec::len).sum();
    for (name, mode) in [
        ("nearest", LodMode::Nearest),
        ("blend", LodMode::Blend),
        ("cig-compat", LodMode::Cig),
    ] {
        let textures: Vec<StripeTexture> = faces
            .iter()
            .map(|f| texture(f, mode))
            .collect::<anyhow::Result<_>>()?;
        // Timed: the linear-light colour, which a renderer accumulates over
        // coverage before it encodes each pixel once.
        let mut linear: Vec<Vec<[f32; 3]>> =
            pixels.iter().map(|p| vec![[0.0; 3]; p.len()]).collect();
        // The median of `repeats` frames after a warm-up, the benchmarks'
        // rule (bench/timing.py).
        let mut times = Vec::with_capacity(repeats);
        for i in 0..=repeats {
            let t0 = Instant::now();
            for ((t, px), o) in textures.iter().zip(&pixels).zip(&mut linear) {
                for (slot, &(x, y)) in o.iter_mut().zip(px) {
                    *slot = t.shade_linear(x, y);
                }
            }
            if i > 0 {
                times.push(t0.elapsed().as_secs_f64());
            }
            std::hint::black_box(&linear);
        }
        times.sort_by(f64::total_cmp);
        let n = times.len();
        let median = if n % 2 == 1 {
            times[n / 2]
        } else {
            0.5 * (times[n / 2 - 1] + times[n / 2])
        };
        let out: Vec<Vec<Rgb8>> = linear
            .iter()
            .map(|o| o.iter().map(|&c| Rgb8::from_linear(c)).collect())
            .collect();
        let mut per_face = Vec::new();
        let (mut sum_all, mut count_all, mut off4) = (0.0, 0usize, 0usize);
        for (o, r) in out.iter().zip(&reference) {
            let (mut sum, mut count) = (0.0, 0usize);
            for (s, r) in o.iter().zip(r) {
                let Some(r) = r else { continue };
                let mut worst = 0.0f64;
                for c in 0..3 {
                    let d = s.0[c] as f64 - r.0[c] as f64;
                    sum += d * d;
                    worst = worst.max(d.abs());
                }
                off4 += (worst > 4.0) as usize;
                count += 1;
            }
            per_face.push((sum / (3 * count.max(1)) as f64).sqrt());
            sum_all += sum;
            count_all += count;
        }
        let rmse = (sum_all / (3 * count_all.max(1)) as f64).sqrt();
        let psnr = 20.0 * math::log10(255.0 / rmse);
        println!(
            "| {name} | {:.2} | {:.1} | {:.3} | {:.3} | {rmse:.3} | {psnr:.2} | {:.2}% |",
            median * 1e3,
            median * 1e9 / total as f64,
            per_face[0],
            per_face[1],
            100.0 * off4 as f64 / count_all.max(1) as f64
        );
    }
    Ok(())
}
