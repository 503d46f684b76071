//! `--max-error`: the cheapest anti-aliasing that keeps a frame within an
//! error budget, chosen per region of the image.
//!
//! The budget `E` is an RMSE in 8-bit sRGB units over R, G and B (docs/rendering.md,
//! [`super::compare`]). The exact resolver ([`super::coverage`]) is the most
//! accurate method (it equals `--reference` on every benchmark scene), so it
//! serves as the truth here and the plan is made in three steps:
//!
//! 1. Every tile gets a *region*: [`Region::Empty`] (no polygon's box meets
//!    it: one sample per pixel is exact), [`Region::Flat`] (flat-coloured
//!    polygons only) or [`Region::Textured`] (some pattern or texture). Edges
//!    cause the error of point sampling in flat regions, texel edges and
//!    minification in textured ones, so the two behave differently.
//! 2. A stratified sample of each region's tiles, the *pilot* (one tile in
//!    [`PILOT_STRIDE`], at least [`PILOT_MIN`]), is rendered with every method
//!    of [`LADDER`]; each cheaper method's squared error against the exact
//!    result estimates its mean squared error over the region.
//! 3. The cheapest pair of methods (one per region, by [`COST`]) whose
//!    estimated RMSE over the whole frame is within [`BUDGET_SHARE`] of `E`
//!    renders the remaining tiles. The pilot tiles keep their exact pixels.
//!
//! The estimate is against `--aa exact`. That equals the reference for flat
//! and pattern-textured polygons, not for stripe textures, whose exact
//! resolver filters by level of detail where many stripes cross a pixel
//! (`bench/RESULTS-stripe.md`: RMSE 2.7 on the ground plane); their error
//! floor is not part of the estimate.
//!
//! The choice depends only on the scene, never on timings or on the number of
//! threads, so the output stays byte-identical for any `--threads`.

use super::{bin, coverage, scan, tiles, Aa, Background, Frame, ScreenPoly, Shader};
use crate::color::linear_to_srgb;
use crate::progress::{Progress, Silent};

/// The methods to choose from, cheapest first: one sample, 2x2
/// supersampling, and exact coverage. (4x4 supersampling is left out: in
/// the benchmarks it costs more than exact coverage for a larger error --
/// demo 2: 0.075 s against 0.064 s, the close-up wall 0.074 s against
/// 0.015 s -- so no plan would choose it, and the pilot need not pay for it.)
pub const LADDER: [Aa; 3] = [Aa::None, Aa::Ss(2), Aa::Exact];

/// Number of [`LADDER`] methods.
const N: usize = LADDER.len();

/// Relative render cost per pixel of each [`LADDER`] method, per region
/// (`[flat, textured]`). A fixed model rather than a measurement, so that the
/// same scene always gets the same plan. Render-only times relative to
/// `--aa none` (2026-11-21, 13:20 UTC): flat, demo 2 through polyfill3 in
/// `bench/RESULTS-scene-render.md`, 1 : 1.3 : 1.7; textured, between the
/// receding plane (1 : 1.5 : 12) and the close-up wall (1 : 2.1 : 1.25) of
/// `bench/RESULTS-texture.md`.
pub const COST: [[f64; N]; 2] = [[1.0, 1.3, 1.7], [1.0, 2.0, 5.0]];

/// One tile in this many of a region is a pilot tile. 16 makes the pilot cost
/// about a fifth of an exact render while giving 48 tiles on a fully covered
/// 1024x768 frame.
pub const PILOT_STRIDE: usize = 16;

/// At least this many pilot tiles per region (all of them when it has fewer):
/// fewer samples make the mean squared error estimate too noisy to trust.
pub const PILOT_MIN: usize = 8;

/// The plan aims at this share of the budget. The estimate is a sample mean
/// over the pilot tiles, and tiles differ (a region's edges are not spread
/// evenly); the headroom keeps the achieved error within `E` on the benchmark
/// scenes (`bench/max_error.sh` checks it).
pub const BUDGET_SHARE: f64 = 0.7;

/// What a tile contains, for the error model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// No polygon's bounding box meets the tile: background only.
    Empty,
    /// Flat-coloured polygons only.
    Flat,
    /// At least one polygon with an "object" or "uv" pattern, sampled through
    /// its texel map, or a stripe texture (`crate::stripe`). (Screen-mode patterns count as flat: one texel per
    /// pixel, so only polygon edges make sampling error there.)
    Textured,
}

/// What [`render_within`] chose and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Plan {
    /// The budget `E` (RMSE, 8-bit sRGB units). Serialized as `budget`:
    /// the report itself is `scene-render --json`'s `max_error`, and a key
    /// repeated inside it would read as a second meaning (docs/json.md).
    #[serde(rename = "budget")]
    pub max_error: f64,
    /// Method of the non-pilot tiles of the flat region (`none`, `ss4`,
    /// `exact`).
    pub flat: String,
    /// Method of the non-pilot tiles of the textured region.
    pub textured: String,
    /// Estimated RMSE of the whole frame against the exact render.
    pub estimate: f64,
    /// Tiles per region: empty, flat, textured.
    pub tiles: [usize; 3],
    /// Pilot tiles (rendered exactly, with every method).
    pub pilot_tiles: usize,
    /// Estimated cost relative to rendering every non-empty tile exactly
    /// ([`COST`] model, pilot included).
    pub relative_cost: f64,
}

impl Plan {
    /// One line for standard error.
    pub fn report(&self) -> String {
        format!(
            "max-error {}: flat tiles {}, textured tiles {}, estimated RMSE {:.3}; \
             {} pilot tiles of {} (empty {}, flat {}, textured {}); \
             modelled cost {:.2} of exact",
            self.max_error,
            self.flat,
            self.textured,
            self.estimate,
            self.pilot_tiles,
            self.tiles.iter().sum::<usize>(),
            self.tiles[0],
            self.tiles[1],
            self.tiles[2],
            self.relative_cost
        )
    }
}

/// The name of a [`LADDER`] method as `--aa` spells it.
pub fn aa_name(aa: Aa) -> String {
    match aa {
        Aa::None => "none".into(),
        Aa::Ss(k) => format!("ss{}", k * k),
        Aa::Exact => "exact".into(),
    }
}

fn region_of(polys: &[ScreenPoly], bin: &[u32]) -> Region {
    if bin.is_empty() {
        Region::Empty
    } else if bin.iter().any(|&i| {
        let p = &polys[i as usize];
        matches!(p.shader, Shader::Texture(_) | Shader::Stripe(_)) || p.shade.is_some()
    }) {
        Region::Textured
    } else {
        Region::Flat
    }
}

/// Every `PILOT_STRIDE`-th member of `members` (starting half a stride in,
/// so the sample is spread over the frame), at least `PILOT_MIN` of them.
fn pilot_sample(members: &[usize]) -> Vec<usize> {
    let n = members.len();
    if n <= PILOT_MIN {
        return members.to_vec();
    }
    let step = PILOT_STRIDE.min(n / PILOT_MIN).max(1);
    members
        .iter()
        .copied()
        .skip(step / 2)
        .step_by(step)
        .collect()
}

/// Sum of squared 8-bit sRGB channel differences between two tile blocks.
fn squared_error(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c], q[c])))
        .map(|(x, y)| {
            let d = linear_to_srgb(x) as f64 - linear_to_srgb(y) as f64;
            d * d
        })
        .sum()
}

/// Points (snapped polygons) for the supersampling resolver, one set per grid.
struct Snapped {
    by_side: Vec<(u32, Vec<scan::FixedPoly>)>,
}

impl Snapped {
    fn new(polys: &[ScreenPoly], methods: &[Aa]) -> Snapped {
        use rayon::prelude::*;
        let mut by_side = Vec::new();
        for aa in methods {
            let k = match aa {
                Aa::None => 1,
                Aa::Ss(k) => *k,
                Aa::Exact => continue,
            };
            if by_side.iter().all(|(s, _)| *s != k) {
                by_side.push((
                    k,
                    polys
                        .par_iter()
                        .map(|p| scan::FixedPoly::new(p, k))
                        .collect(),
                ));
            }
        }
        Snapped { by_side }
    }

    fn tile(
        &self,
        polys: &[ScreenPoly],
        bin: &[u32],
        bg: &Background,
        tile: [u32; 4],
        aa: Aa,
    ) -> Vec<[f32; 3]> {
        let k = match aa {
            Aa::Exact => return coverage::render_bin(polys, bin, bg, tile),
            Aa::None => 1,
            Aa::Ss(k) => k,
        };
        // An empty tile reads no snapped polygon: background only.
        let fixed: &[scan::FixedPoly] = match self.by_side.iter().find(|(s, _)| *s == k) {
            Some((_, f)) => f,
            None if bin.is_empty() => &[],
            None => unreachable!("polygons are snapped for every planned grid"),
        };
        scan::render_tile(polys, fixed, bin, bg, tile, k)
    }
}

/// Renders with the cheapest methods expected to keep the frame's RMSE
/// against the exact render within `max_error` (module docs), and says
/// what it chose. `max_error` must be finite and not negative.
pub fn render_within(
    polys: &[ScreenPoly],
    bg: &Background,
    width: u32,
    height: u32,
    max_error: f64,
) -> (Frame, Plan) {
    render_within_with(polys, bg, width, height, max_error, &Silent)
}

/// [`render_within`], reporting each tile done to `progress` (phases
/// "pilot" and "render").
pub fn render_within_with(
    polys: &[ScreenPoly],
    bg: &Background,
    width: u32,
    height: u32,
    max_error: f64,
    progress: &dyn Progress,
) -> (Frame, Plan) {
    use rayon::prelude::*;
    assert!(max_error.is_finite() && max_error >= 0.0);
    let tiles = tiles(width, height);
    let bins = bin(polys, width, height);
    let regions: Vec<Region> = bins.iter().map(|b| region_of(polys, b)).collect();
    let members =
        |r: Region| -> Vec<usize> { (0..tiles.len()).filter(|&t| regions[t] == r).collect() };
    let (flat, textured) = (members(Region::Flat), members(Region::Textured));
    let pixels = |t: usize| {
        let [x0, y0, x1, y1] = tiles[t];
        ((x1 - x0) * (y1 - y0)) as f64
    };

    // Pilot: exact and every cheaper method on a sample of each region --
    // unless even the cheapest plan would cost more than rendering exactly
    // (small frames, few tiles): then skip it. E = 0: nothing cheaper can
    // promise zero error.
    let mut pilots = vec![pilot_sample(&flat), pilot_sample(&textured)];
    let area = |ts: &[usize]| -> f64 { ts.iter().map(|&t| pixels(t)).sum() };
    let exact_cost = COST[0][N - 1] * area(&flat) + COST[1][N - 1] * area(&textured);
    let pilot_cost = |pilots: &[Vec<usize>]| -> f64 {
        (0..2)
            .map(|r| COST[r].iter().sum::<f64>() * area(&pilots[r]))
            .sum()
    };
    let cheapest = pilot_cost(&pilots)
        + COST[0][0] * (area(&flat) - area(&pilots[0]))
        + COST[1][0] * (area(&textured) - area(&pilots[1]));
    if max_error == 0.0 || cheapest >= exact_cost {
        pilots = vec![Vec::new(), Vec::new()];
    }
    let pilot_tiles: Vec<usize> = pilots.concat();
    let snapped_pilot = Snapped::new(polys, if pilot_tiles.is_empty() { &[] } else { &LADDER });
    if !pilot_tiles.is_empty() {
        progress.phase("pilot", pilot_tiles.len() as u64);
    }
    let pilot_results: Vec<(Vec<[f32; 3]>, [f64; N])> = pilot_tiles
        .par_iter()
        .map(|&t| {
            let exact = coverage::render_bin(polys, &bins[t], bg, tiles[t]);
            let mut sse = [0.0; N];
            for (m, aa) in LADDER.iter().enumerate().take(LADDER.len() - 1) {
                let block = snapped_pilot.tile(polys, &bins[t], bg, tiles[t], *aa);
                sse[m] = squared_error(&block, &exact);
            }
            progress.advance(1);
            (exact, sse)
        })
        .collect();

    // Mean squared channel error of each method per region, and the pixels
    // left to render in each region.
    let mut mse = [[0.0f64; N]; 2];
    let mut rest = [0.0f64; 2];
    let mut start = 0;
    for (r, (pilot, all)) in pilots.iter().zip([&flat, &textured]).enumerate() {
        let results = &pilot_results[start..start + pilot.len()];
        start += pilot.len();
        let px: f64 = pilot.iter().map(|&t| pixels(t)).sum();
        for m in 0..LADDER.len() {
            let sse: f64 = results.iter().map(|(_, s)| s[m]).sum();
            // No pilot (an empty region, or E = 0): only exact is safe.
            mse[r][m] = if px > 0.0 {
                sse / (3.0 * px)
            } else if m + 1 == LADDER.len() {
                0.0
            } else {
                f64::INFINITY
            };
        }
        rest[r] = area(all) - px;
    }

    // The cheapest pair within the budget (exact/exact always is: estimate 0).
    let total = 3.0 * width as f64 * height as f64;
    let budget = (BUDGET_SHARE * max_error).powi(2) * total;
    let mut best = (f64::INFINITY, LADDER.len() - 1, LADDER.len() - 1, 0.0);
    for mf in 0..LADDER.len() {
        for mt in 0..LADDER.len() {
            let sse = 3.0 * (mse[0][mf] * rest[0] + mse[1][mt] * rest[1]);
            if sse.is_finite() && sse <= budget {
                let cost = COST[0][mf] * rest[0] + COST[1][mt] * rest[1];
                if cost < best.0 {
                    best = (cost, mf, mt, sse);
                }
            }
        }
    }
    let (_, mf, mt, sse) = best;
    let chosen = [LADDER[mf], LADDER[mt]];

    // The rest of the frame.
    let snapped = Snapped::new(polys, &chosen);
    let mut pilot_of = vec![usize::MAX; tiles.len()];
    for (i, &t) in pilot_tiles.iter().enumerate() {
        pilot_of[t] = i;
    }
    progress.phase("render", tiles.len() as u64);
    let blocks: Vec<Vec<[f32; 3]>> = (0..tiles.len())
        .into_par_iter()
        .map(|t| {
            let block = match (pilot_of[t], regions[t]) {
                (i, _) if i != usize::MAX => pilot_results[i].0.clone(),
                (_, Region::Empty) => snapped.tile(polys, &bins[t], bg, tiles[t], Aa::None),
                (_, Region::Flat) => snapped.tile(polys, &bins[t], bg, tiles[t], chosen[0]),
                (_, Region::Textured) => snapped.tile(polys, &bins[t], bg, tiles[t], chosen[1]),
            };
            progress.advance(1);
            block
        })
        .collect();

    let cost = COST[0][mf] * rest[0] + COST[1][mt] * rest[1] + pilot_cost(&pilots);
    let plan = Plan {
        max_error,
        flat: aa_name(chosen[0]),
        textured: aa_name(chosen[1]),
        estimate: (sse / total).sqrt(),
        tiles: [
            tiles.len() - flat.len() - textured.len(),
            flat.len(),
            textured.len(),
        ],
        pilot_tiles: pilot_tiles.len(),
        relative_cost: if exact_cost > 0.0 {
            cost / exact_cost
        } else {
            1.0
        },
    };
    (Frame::from_tiles(width, height, &tiles, blocks), plan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb8;
    use crate::raster::render;
    use crate::raster::tests::poly2;
    use crate::view::View;

    /// A frame of many edges: a fan of thin triangles in two colours about
    /// the centre of a 256x192 frame (plus one square: a flat interior).
    fn fan(n: usize) -> Vec<ScreenPoly> {
        fan_in(n, 512, 384)
    }

    fn fan_in(n: usize, w: u32, h: u32) -> Vec<ScreenPoly> {
        let view = View::ortho2(0.0, w as f64, 0.0, h as f64, w, h);
        let mut polys: Vec<ScreenPoly> = (0..n)
            .filter_map(|i| {
                let a0 = i as f64 / n as f64 * std::f64::consts::TAU;
                let a1 = (i as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
                let c = if i % 2 == 0 {
                    Rgb8([250, 40, 40])
                } else {
                    Rgb8([20, 200, 90])
                };
                let (cx, cy) = (w as f64 / 2.0, h as f64 / 2.0);
                let r = 0.47 * h as f64;
                let pts = [
                    [cx, cy],
                    [cx + r * crate::math::cos(a0), cy + r * crate::math::sin(a0)],
                    [cx + r * crate::math::cos(a1), cy + r * crate::math::sin(a1)],
                ];
                poly2(&view, &pts, c, i as u32)
            })
            .collect();
        polys.extend(poly2(
            &view,
            &[[0.0, 0.0], [64.0, 0.0], [64.0, 64.0], [0.0, 64.0]],
            Rgb8([9, 9, 200]),
            n as u32,
        ));
        polys
    }

    fn rmse(a: &Frame, b: &Frame) -> f64 {
        squared_error(&a.pixels, &b.pixels).sqrt() / (3.0 * a.pixels.len() as f64).sqrt()
    }

    #[test]
    fn achieved_error_stays_within_the_budget_for_every_budget() {
        let polys = fan(120);
        let bg = Background::color(Rgb8([255, 255, 255]));
        let exact = render(&polys, &bg, 512, 384, Aa::Exact);
        for e in [0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 100.0] {
            let (frame, plan) = render_within(&polys, &bg, 512, 384, e);
            let achieved = rmse(&frame, &exact);
            assert!(
                achieved <= e + 1e-12,
                "E {e}: achieved {achieved}, plan {plan:?}"
            );
            assert!(plan.estimate <= BUDGET_SHARE * e + 1e-12, "{plan:?}");
        }
    }

    #[test]
    fn zero_budget_renders_exactly_and_a_huge_one_the_cheapest_way() {
        let polys = fan(80);
        let bg = Background::color(Rgb8([0, 0, 0]));
        let exact = render(&polys, &bg, 512, 384, Aa::Exact);
        let (frame, plan) = render_within(&polys, &bg, 512, 384, 0.0);
        assert_eq!(frame, exact);
        assert_eq!((plan.flat.as_str(), plan.pilot_tiles), ("exact", 0));
        let (_, plan) = render_within(&polys, &bg, 512, 384, 1e6);
        assert_eq!(plan.flat, "none");
        // Point sampling's cost against exact's, plus at most 0.2 for the pilot.
        assert!(
            plan.relative_cost < COST[0][0] / COST[0][N - 1] + 0.2,
            "{plan:?}"
        );
        // A frame too small for a pilot to pay: exact everywhere.
        let polys = fan_in(20, 64, 64);
        let (frame, plan) = render_within(&polys, &bg, 64, 64, 1e6);
        assert_eq!(frame, render(&polys, &bg, 64, 64, Aa::Exact));
        assert_eq!((plan.flat.as_str(), plan.pilot_tiles), ("exact", 0));
    }

    #[test]
    fn the_plan_does_not_depend_on_the_thread_count() {
        let polys = fan(100);
        let bg = Background::color(Rgb8([255, 255, 255]));
        let run = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| render_within(&polys, &bg, 512, 384, 1.0))
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn pilot_sample_is_spread_and_never_too_small() {
        let all: Vec<usize> = (0..768).collect();
        let s = pilot_sample(&all);
        assert_eq!(s.len(), 48);
        assert_eq!(s[0], 8);
        assert_eq!(pilot_sample(&all[..5]), vec![0, 1, 2, 3, 4]);
        assert!(pilot_sample(&all[..40]).len() >= PILOT_MIN);
    }
}
