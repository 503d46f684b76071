//! For `bench/clip_bound.sh`: one plain way of the cut that exact
//! per-pixel anti-aliasing of a triangle soup does before visibility, each
//! triangle into its pixel fragments, timed: one thread, no binning, no
//! storage, each triangle clipped to each of its pixel rows and each row's
//! piece to each of its pixels (Sutherland-Hodgman in f64, on the stack),
//! the fragment's area summed. It cuts every fragment, hidden or not, and
//! other ways of cutting may be cheaper, so it is a yardstick, not a lower
//! bound on every design. It knows nothing of the project's code and draws
//! no picture.
//!
//!     clip_bound SCENE.ndjson WIDTH HEIGHT RUNS
//!
//! Prints one line: triangles, fragments, full-pixel fragments, the summed
//! area (a check), and the median seconds of the clipping over RUNS runs
//! (reading the file not included).

use std::io::BufRead;

#[derive(Clone, Copy, Default)]
struct P {
    x: f64,
    y: f64,
}

/// The part of convex `inp` on one side of the line x = c (or y = c):
/// `v >= 0` with v = coordinate - c, negated when `below`.
#[inline(always)]
fn clip(inp: &[P], out: &mut [P; 16], on_x: bool, c: f64, below: bool) -> usize {
    let val = |p: &P| {
        let v = if on_x { p.x - c } else { p.y - c };
        if below {
            -v
        } else {
            v
        }
    };
    let n = inp.len();
    let mut m = 0;
    for i in 0..n {
        let (a, b) = (inp[i], inp[if i + 1 == n { 0 } else { i + 1 }]);
        let (da, db) = (val(&a), val(&b));
        if da >= 0.0 {
            out[m] = a;
            m += 1;
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            out[m] = P {
                x: a.x + (b.x - a.x) * t,
                y: a.y + (b.y - a.y) * t,
            };
            m += 1;
        }
    }
    m
}

fn area2(v: &[P]) -> f64 {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[if i + 1 == n { 0 } else { i + 1 }]);
            a.x * b.y - a.y * b.x
        })
        .sum()
}

fn read(path: &str) -> Vec<[P; 3]> {
    let f = std::io::BufReader::new(std::fs::File::open(path).expect("open the scene"));
    let mut tris = Vec::new();
    for line in f.lines() {
        let line = line.expect("read the scene");
        let Some(rest) = line.split("\"vertices\":").nth(1) else {
            continue;
        };
        let nums: Vec<f64> = rest
            .split(|c: char| c == '[' || c == ']' || c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .take(9)
            .map(|t| t.parse().expect("a number"))
            .collect();
        let mut t = [0, 3, 6].map(|i| P {
            x: nums[i],
            y: nums[i + 1],
        });
        if area2(&t) < 0.0 {
            t.swap(1, 2);
        }
        tris.push(t);
    }
    tris
}

fn cut(tris: &[[P; 3]], w: f64, h: f64) -> (u64, u64, f64) {
    let (mut frags, mut full, mut area) = (0u64, 0u64, 0.0);
    let (mut b1, mut b2, mut c1, mut c2) = (
        [P::default(); 16],
        [P::default(); 16],
        [P::default(); 16],
        [P::default(); 16],
    );
    for t in tris {
        let lo = |f: fn(&P) -> f64| t.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = |f: fn(&P) -> f64| t.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        let (y0, y1) = (lo(|p| p.y).max(0.0).floor(), hi(|p| p.y).min(h).ceil());
        let mut y = y0;
        while y < y1 {
            let n = clip(t, &mut b1, false, y, false);
            let n = clip(&b1[..n], &mut b2, false, y + 1.0, true);
            if n >= 3 {
                let band = &b2[..n];
                let x0 = band
                    .iter()
                    .map(|p| p.x)
                    .fold(f64::INFINITY, f64::min)
                    .max(0.0)
                    .floor();
                let x1 = band
                    .iter()
                    .map(|p| p.x)
                    .fold(f64::NEG_INFINITY, f64::max)
                    .min(w)
                    .ceil();
                let mut x = x0;
                while x < x1 {
                    let m = clip(band, &mut c1, true, x, false);
                    let m = clip(&c1[..m], &mut c2, true, x + 1.0, true);
                    if m >= 3 {
                        let a = area2(&c2[..m]);
                        area += a;
                        frags += 1;
                        full += u64::from(a >= 2.0 - 1e-9);
                    }
                    x += 1.0;
                }
            }
            y += 1.0;
        }
    }
    (frags, full, 0.5 * area)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, w, h, runs] = &args[..] else {
        eprintln!("usage: clip_bound SCENE.ndjson WIDTH HEIGHT RUNS");
        std::process::exit(2);
    };
    let (w, h): (f64, f64) = (w.parse().unwrap(), h.parse().unwrap());
    let tris = read(path);
    let mut times = Vec::new();
    let mut last = (0, 0, 0.0);
    for _ in 0..runs.parse::<usize>().unwrap() {
        let t0 = std::time::Instant::now();
        last = std::hint::black_box(cut(std::hint::black_box(&tris), w, h));
        times.push(t0.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let (frags, full, area) = last;
    println!(
        "{} {} {} {:.3} {:.6}",
        tris.len(),
        frags,
        full,
        area,
        times[times.len() / 2]
    );
}
