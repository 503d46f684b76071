//! Triangulation benchmark (a table, not a timed test; not run in CI): the
//! concave outlines of issue 16 (a star and a notched circle, 1,000 to
//! 1,000,000 vertices) cut into triangles by the ear clipping `raster::project`
//! used before (copied below as it was) and by `geom::triangulate` (monotone
//! pieces, O(n log n)), and the simplicity test every record now passes
//! (`geom::simple`, a Shamos–Hoey sweep; a convex outline takes its O(n)
//! shortcut).
//!
//! Run: `cargo bench --bench triangulate` (prints the table), or
//! `bench/triangulate.sh`, which adds the tools end to end on a
//! million-vertex star; bench/RESULTS-triangulate.md keeps a run.

use glam::{DVec2, DVec3};
use patkit::geom::polygon::area2;
use patkit::geom::simple;
use patkit::geom::triangulate::triangulate;
use patkit::math::sum_compensated;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Time this thread has spent on a CPU (`CLOCK_THREAD_CPUTIME_ID`): the
/// machine is shared by several builds, and a run's wall time there can be
/// three times its own work. `None` but on 64-bit Linux.
#[cfg(all(target_os = "linux", target_pointer_width = "64"))]
fn cpu_time() -> Option<Duration> {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, t: *mut Timespec) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: clock_gettime writes one timespec (two longs on 64-bit Linux)
    // to the pointer it is given, which points to one.
    let ok = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    ok.then(|| Duration::new(t.sec as u64, t.nsec as u32))
}

#[cfg(not(all(target_os = "linux", target_pointer_width = "64")))]
fn cpu_time() -> Option<Duration> {
    None
}

/// A run's times: on a CPU (wall time where unknown), and wall.
#[derive(Clone, Copy)]
struct Times {
    cpu: Duration,
    wall: Duration,
}

/// Fastest of at least `reps` runs (by CPU time), repeated until `BUDGET`
/// has been spent: the fastest run is the least disturbed one.
fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> (Times, T) {
    const BUDGET: Duration = Duration::from_millis(1500);
    let mut best = Times {
        cpu: Duration::MAX,
        wall: Duration::MAX,
    };
    let mut last = None;
    let start = Instant::now();
    let mut n = 0;
    while n < reps || start.elapsed() < BUDGET {
        let (c0, t) = (cpu_time(), Instant::now());
        let r = black_box(f());
        let wall = t.elapsed();
        let cpu = match (c0, cpu_time()) {
            (Some(a), Some(b)) => b.saturating_sub(a),
            _ => wall,
        };
        if cpu < best.cpu {
            best = Times { cpu, wall };
        }
        last = Some(r);
        n += 1;
    }
    (best, last.expect("reps > 0"))
}

/// An outline of `n` vertices.
type Shape = fn(usize) -> Vec<DVec2>;

/// A star: `n` vertices alternating between radii 1 and 0.5 (n/2 spikes).
fn star(n: usize) -> Vec<DVec2> {
    ring(n, |i| if i % 2 == 0 { 1.0 } else { 0.5 })
}

/// A notched circle (a comb bent round): vertices in pairs at radius 1,
/// then 0.9, so the outline is square teeth of a quarter of its edges.
fn comb(n: usize) -> Vec<DVec2> {
    ring(n, |i| if (i / 2) % 2 == 0 { 1.0 } else { 0.9 })
}

/// A circle, convex: for the simplicity test's shortcut.
fn circle(n: usize) -> Vec<DVec2> {
    ring(n, |_| 1.0)
}

fn ring(n: usize, r: impl Fn(usize) -> f64) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            DVec2::new(r(i) * patkit::math::cos(a), r(i) * patkit::math::sin(a))
        })
        .collect()
}

/// The ear clipping of `raster::project` before this change
/// (`geom::polygon::ear_clip`, removed), verbatim: the baseline.
fn ear_clip(poly: &[DVec2]) -> Vec<Vec<DVec2>> {
    let mut idx: Vec<usize> = (0..poly.len()).collect();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    while idx.len() > 3 {
        let m = idx.len();
        let mut cut = None;
        let mut best = (f64::MIN, 0usize);
        for i in 0..m {
            let (a, b, c) = (
                poly[idx[(i + m - 1) % m]],
                poly[idx[i]],
                poly[idx[(i + 1) % m]],
            );
            let turn = (b - a).perp_dot(c - b);
            if turn > best.0 {
                best = (turn, i);
            }
            if turn <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&k| {
                let p = poly[k];
                p != a && p != b && p != c && in_triangle(p, a, b, c)
            });
            if !blocked {
                cut = Some(i);
                break;
            }
        }
        let i = cut.unwrap_or(best.1);
        let (a, b, c) = (
            poly[idx[(i + m - 1) % m]],
            poly[idx[i]],
            poly[idx[(i + 1) % m]],
        );
        if (b - a).perp_dot(c - b) > 0.0 {
            out.push(vec![a, b, c]);
        }
        idx.remove(i);
    }
    let (a, b, c) = (poly[idx[0]], poly[idx[1]], poly[idx[2]]);
    if (b - a).perp_dot(c - b) > 0.0 {
        out.push(vec![a, b, c]);
    }
    out
}

fn in_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    (b - a).perp_dot(p - a) >= 0.0
        && (c - b).perp_dot(p - b) >= 0.0
        && (a - c).perp_dot(p - c) >= 0.0
}

/// Relative difference between the triangles' total area and the outline's.
fn area_error(p: &[DVec2], tris: &[[u32; 3]]) -> f64 {
    let o = p[0];
    let n = p.len();
    let whole = sum_compensated((0..n).map(|i| (p[i] - o).perp_dot(p[(i + 1) % n] - o)));
    let parts = sum_compensated(
        tris.iter()
            .map(|t| area2(&[p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]])),
    );
    (parts - whole).abs() / whole.abs()
}

fn secs(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// "12.3 ms (30.1 ms)": CPU time, then wall time.
fn both(t: Times) -> String {
    format!("{} ({})", secs(t.cpu), secs(t.wall))
}

/// Ear clipping is measured while it is expected to take at most this long;
/// past it the time is extrapolated (quadratically) from the last size measured.
const EAR_CLIP_CAP: f64 = 60.0;

fn main() {
    // `-- simple` runs the simplicity test alone, `-- triangulate` the
    // triangulation alone (without ear clipping); cargo adds `--bench`.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let only = |part: &str| args.is_empty() || args.iter().any(|a| a == part);
    if only("triangulate") {
        triangulation_table(args.is_empty());
    }
    if only("simple") {
        simplicity_table();
    }
}

fn triangulation_table(with_ear_clipping: bool) {
    println!("## Triangulation of concave outlines");
    println!();
    println!(
        "CPU time of the fastest of several runs (one run where a run takes over \
         a second), wall time of that run in brackets; \"est.\": not run, \
         extrapolated as n² from the largest size measured."
    );
    println!();
    println!(
        "| outline | vertices | ear clipping (before) | monotone pieces (now) | speed-up | triangles | area error (relative) | all positive |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---|");
    let shapes: [(&str, Shape); 2] = [("star", star), ("notched circle", comb)];
    for (name, shape) in shapes {
        let mut last_ear: Option<(usize, f64)> = None;
        for n in [1_000, 10_000, 100_000, 1_000_000] {
            let p = shape(n);
            let estimate = last_ear.map(|(m, t)| t * (n as f64 / m as f64).powi(2));
            let (old, old_secs) = match estimate {
                _ if !with_ear_clipping => ("-".to_string(), f64::NAN),
                Some(e) if e > EAR_CLIP_CAP => (format!("~{e:.0} s est."), e),
                _ => {
                    let reps = if estimate.unwrap_or(0.0) > 1.0 { 1 } else { 3 };
                    let (t, tris) = best(reps, || ear_clip(&p));
                    assert_eq!(tris.len(), n - 2);
                    last_ear = Some((n, t.cpu.as_secs_f64()));
                    (both(t), t.cpu.as_secs_f64())
                }
            };
            let (t, tris) = best(3, || triangulate(&p));
            let positive = tris
                .iter()
                .all(|t| area2(&[p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]]) > 0.0);
            println!(
                "| {name} | {n} | {old} | {} | {} | {} | {:.1e} | {} |",
                both(t),
                if old_secs.is_nan() {
                    "-".to_string()
                } else {
                    format!("{:.0}x", old_secs / t.cpu.as_secs_f64())
                },
                tris.len(),
                area_error(&p, &tris),
                if positive { "yes" } else { "NO" },
            );
        }
    }
}

fn simplicity_table() {
    println!();
    println!("## Simplicity test (`geom::simple::check`, as every record is read)");
    println!();
    println!("CPU time of the fastest of several runs, wall time in brackets.");
    println!();
    println!("| outline | vertices | time | per vertex (CPU) | result |");
    println!("|---|---:|---:|---:|---|");
    let shapes: [(&str, Shape); 3] = [
        ("star", star),
        ("notched circle", comb),
        ("circle (convex: O(n) shortcut)", circle),
    ];
    for (name, shape) in shapes {
        for n in [1_000, 10_000, 100_000, 1_000_000] {
            let p: Vec<DVec3> = shape(n).iter().map(|v| DVec3::new(v.x, v.y, 0.0)).collect();
            let (t, r) = best(3, || simple::check(&p));
            println!(
                "| {name} | {n} | {} | {:.0} ns | {} |",
                both(t),
                t.cpu.as_secs_f64() * 1e9 / n as f64,
                match r {
                    Ok(()) => "simple".to_string(),
                    Err(e) => e.to_string(),
                }
            );
        }
    }
}
