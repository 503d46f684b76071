//! Draws the thesis's patterns as RGBA PNG images: the first half of
//! `fixtures/make-patterns.sh`, which turns them into `.pat` files with
//! `pat-from-image`. Everything is procedural and deterministic (a fixed hash,
//! no random generator), so rerunning the script reproduces the fixtures.
//!
//! Usage: cargo run --example draw_fixtures -- OUT_DIR

use image::{Rgba, RgbaImage};
use patkit::math;
use std::f64::consts::PI;
use std::path::Path;

/// A pixel colour or transparent.
type Px = Option<[u8; 3]>;

/// A deterministic hash to pick shades (SplitMix64's finalizer).
fn hash(a: u64, b: u64) -> u64 {
    let mut z = a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_add(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Draws a `size` x `size` image from a function of pattern coordinates
/// (x right, y UP, as in the .pat format); the PNG's top row is y = size-1.
fn draw(size: u32, f: impl Fn(u32, u32) -> Px) -> RgbaImage {
    RgbaImage::from_fn(size, size, |x, row| {
        let y = size - 1 - row;
        match f(x, y) {
            Some([r, g, b]) => Rgba([r, g, b, 255]),
            None => Rgba([0, 0, 0, 0]),
        }
    })
}

/// Running-bond masonry: courses `h` high, units `w` long, every other course
/// shifted by half a unit, one texel of mortar. `shades` colour the units by hash.
fn masonry(x: u32, y: u32, w: u32, h: u32, mortar: [u8; 3], shades: &[[u8; 3]], seed: u64) -> Px {
    let course = y / h;
    let shift = if course % 2 == 1 { w / 2 } else { 0 };
    let xs = x + shift;
    if y % h == h - 1 || xs % w == w - 1 {
        return Some(mortar);
    }
    let unit = (xs / w) as u64 + 97 * course as u64;
    let mut shade = shades[(hash(unit, seed) % shades.len() as u64) as usize];
    // A few speckles so the surface is not flat.
    if hash(x as u64 * 131 + y as u64, seed + 1).is_multiple_of(23) {
        shade = shades[(hash(unit + 1, seed) % shades.len() as u64) as usize];
    }
    Some(shade)
}

fn brick() -> RgbaImage {
    let reds = [[156, 52, 38], [178, 66, 44], [135, 44, 34], [190, 88, 60]];
    draw(64, |x, y| masonry(x, y, 16, 8, [205, 200, 190], &reds, 1))
}

fn pyr() -> RgbaImage {
    // Sandstone blocks for the pyramid faces.
    let sand = [
        [214, 178, 112],
        [196, 160, 98],
        [226, 196, 136],
        [180, 144, 86],
    ];
    draw(64, |x, y| masonry(x, y, 32, 16, [120, 96, 60], &sand, 7))
}

fn wood() -> RgbaImage {
    // Grain lines that wave along x; both the wave (period 64 in x) and the ring
    // spacing (8 in y) divide 64, so the pattern tiles without a seam.
    let browns = [
        [94, 56, 28],
        [122, 76, 38],
        [150, 98, 52],
        [172, 120, 68],
        [136, 86, 44],
    ];
    draw(64, |x, y| {
        let t = 2.0 * PI * x as f64 / 64.0;
        let v = y as f64 + 2.5 * math::sin(t) + 1.2 * math::sin(2.0 * t + 1.0);
        let ring = (v / 8.0).rem_euclid(1.0);
        let i = ((ring * 5.0) as usize).min(4);
        Some(browns[i])
    })
}

fn weave() -> RgbaImage {
    // Basket weave of 8x8 cells: horizontal and vertical threads take turns on
    // top; the holes where threads part are transparent.
    let warp = [[70, 90, 150], [96, 120, 180]];
    let weft = [[200, 170, 90], [230, 205, 130]];
    draw(32, |x, y| {
        let (cx, cy) = (x / 8, y / 8);
        let (ix, iy) = (x % 8, y % 8);
        if ix == 0 && iy == 0 {
            return None;
        }
        let horizontal_on_top = (cx + cy) % 2 == 0;
        if horizontal_on_top {
            if iy == 0 {
                return None;
            }
            Some(weft[(iy == 3 || iy == 4) as usize])
        } else {
            if ix == 0 {
                return None;
            }
            Some(warp[(ix == 3 || ix == 4) as usize])
        }
    })
}

fn modern() -> RgbaImage {
    // A modern motif: a red disc, a blue diamond and a yellow bar on a clear ground.
    draw(32, |x, y| {
        let (fx, fy) = (x as f64 + 0.5, y as f64 + 0.5);
        if (fx - 10.0).powi(2) + (fy - 22.0).powi(2) <= 36.0 {
            return Some([210, 40, 40]);
        }
        if (fx - 23.0).abs() + (fy - 10.0).abs() <= 7.0 {
            return Some([30, 70, 180]);
        }
        if (3..29).contains(&x) && (2..5).contains(&y) {
            return Some([240, 200, 30]);
        }
        if x == 31 || y == 31 {
            return Some([20, 20, 20]);
        }
        None
    })
}

fn bkgrnd() -> RgbaImage {
    // Night sky for the 3D demo's colorclear: navy with faint diagonal bands,
    // scattered stars, and some transparent texels left to what lies beneath.
    draw(64, |x, y| {
        let h = hash(x as u64, y as u64 * 64 + 5);
        if h.is_multiple_of(97) {
            return Some([255, 250, 220]);
        }
        if h.is_multiple_of(53) {
            return Some([170, 190, 255]);
        }
        if h.is_multiple_of(11) {
            return None;
        }
        if (x + y) % 16 < 2 {
            Some([28, 36, 84])
        } else {
            Some([16, 22, 60])
        }
    })
}

fn chex() -> RgbaImage {
    // The checkered plain: 4x4 squares of two greens, with a lighter texel at
    // each square's corner.
    draw(16, |x, y| {
        if x % 4 == 0 && y % 4 == 0 {
            return Some([150, 200, 120]);
        }
        if (x / 4 + y / 4) % 2 == 0 {
            Some([40, 120, 40])
        } else {
            Some([90, 160, 70])
        }
    })
}

/// Periodic value noise: lattice values on a `cells` x `cells` grid that wraps,
/// smoothly interpolated, so the picture it makes tiles without a seam.
fn value_noise(x: f64, y: f64, cells: u64, seed: u64) -> f64 {
    let lattice = |i: i64, j: i64| {
        let (i, j) = (
            i.rem_euclid(cells as i64) as u64,
            j.rem_euclid(cells as i64) as u64,
        );
        (hash(i * 7919 + j, seed) % 10_000) as f64 / 10_000.0
    };
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    let (fx, fy) = (x - x.floor(), y - y.floor());
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let top = lattice(i, j) * (1.0 - sx) + lattice(i + 1, j) * sx;
    let bottom = lattice(i, j + 1) * (1.0 - sx) + lattice(i + 1, j + 1) * sx;
    top * (1.0 - sy) + bottom * sy
}

/// A photo-like 256x256 marble: many smooth shades, for `pat-from-image` to
/// quantize (the bundled example's input picture, not a fixture pattern).
fn marble() -> RgbaImage {
    const SIDE: u32 = 256;
    RgbaImage::from_fn(SIDE, SIDE, |x, y| {
        let mut turbulence = 0.0;
        for (octave, cells) in [4u64, 8, 16, 32].into_iter().enumerate() {
            let scale = cells as f64 / SIDE as f64;
            turbulence +=
                value_noise(x as f64 * scale, y as f64 * scale, cells, 11) / (1 << octave) as f64;
        }
        let phase = 2.0 * PI * (2.0 * x as f64 / SIDE as f64 + y as f64 / SIDE as f64);
        let vein = math::powf(math::sin(phase + 5.0 * turbulence).abs(), 0.35);
        let base = [232.0, 228.0, 220.0];
        let dark = [70.0, 80.0, 98.0];
        let px = |k: usize| (dark[k] + (base[k] - dark[k]) * vein) as u8;
        Rgba([px(0), px(1), px(2), 255])
    })
}

/// An earth-like map for seed 002's textured globe (`gluSphere` with
/// `gluQuadricTexture`): equirectangular, x the longitude (GLU's s) and y the
/// latitude from the south pole (t), so one copy wraps the sphere. Continents
/// are periodic value noise above a threshold (the map tiles left to right,
/// so the sphere's seam is invisible); ice caps past 70 degrees; five flat
/// colours so the conversion to a .pat is exact.
fn earth() -> RgbaImage {
    const SIDE: u32 = 64;
    draw(SIDE, |x, y| {
        let lat = (y as f64 + 0.5) / SIDE as f64 * 180.0 - 90.0;
        if lat.abs() > 70.0 {
            return Some([236, 242, 248]);
        }
        let (fx, fy) = (x as f64 / SIDE as f64, y as f64 / SIDE as f64);
        let h = value_noise(fx * 4.0, fy * 4.0, 4, 2) * 0.7
            + value_noise(fx * 8.0, fy * 8.0, 8, 3) * 0.3;
        Some(if h > 0.68 {
            [150, 120, 70] // highlands
        } else if h > 0.56 {
            [60, 140, 60] // lowlands
        } else if h > 0.5 {
            [40, 110, 190] // shallow sea
        } else {
            [20, 50, 130] // ocean
        })
    })
}

/// A moon-like map for the second sphere: grey highlands, darker maria from
/// value noise, and a few round craters with bright rims placed by hash.
fn moon() -> RgbaImage {
    const SIDE: u32 = 32;
    let craters: Vec<(f64, f64, f64)> = (0..6)
        .map(|k| {
            let h = hash(k, 17);
            (
                (h % 32) as f64,
                ((h >> 8) % 20 + 6) as f64,
                ((h >> 16) % 3 + 2) as f64,
            )
        })
        .collect();
    draw(SIDE, |x, y| {
        let (fx, fy) = (x as f64 / SIDE as f64, y as f64 / SIDE as f64);
        for &(cx, cy, r) in &craters {
            // Distance across the left-right wrap, so craters tile too.
            let dx = (x as f64 - cx).abs();
            let d = math::hypot(dx.min(SIDE as f64 - dx), y as f64 - cy);
            if d < r - 1.0 {
                return Some([95, 95, 100]);
            }
            if d < r {
                return Some([215, 215, 210]);
            }
        }
        Some(if value_noise(fx * 4.0, fy * 4.0, 4, 5) > 0.55 {
            [120, 120, 125] // maria
        } else {
            [175, 175, 170] // highlands
        })
    })
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .expect("usage: draw_fixtures OUT_DIR");
    let out = Path::new(&out);
    std::fs::create_dir_all(out).expect("creating the output directory");
    let patterns = [
        ("brick", brick()),
        ("wood", wood()),
        ("weave", weave()),
        ("mod", modern()),
        ("bkgrnd", bkgrnd()),
        ("pyr", pyr()),
        ("chex", chex()),
        ("earth", earth()),
        ("moon", moon()),
    ];
    let pictures = patterns.into_iter().chain([("marble", marble())]);
    for (name, img) in pictures {
        let path = out.join(format!("{name}.png"));
        img.save(&path)
            .unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
        println!("{}", path.display());
    }
}
