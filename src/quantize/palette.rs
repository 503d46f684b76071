//! Step 2: the palette. The opaque pixels become a histogram of distinct
//! colours weighted by their pixel counts, and everything after runs on it
//! (on its [`super::coreset`] when it has more than 32,768 colours, and
//! with fewer k-means steps when colours x K exceed 2^20): median
//! cut gives K starting colours ([`super::median_cut`]), k-means and its
//! refinements improve them ([`super::kmeans`]). The histogram is sorted by
//! colour and nothing is random, so the same image always gives the same
//! palette.

use super::coreset::{coreset_of_histogram, CORESET_KMEANS_ITERATIONS, CORESET_POINTS};
use super::kmeans::{integer_lloyd, kmeans, kmeans_at_most, neighbour_search, split_merge};
use super::median_cut::median_cut;
use super::packed::{pack, slot, unpack, EMPTY};
use super::space::{point, Point};
use crate::color::Rgb8;
use crate::progress::{Progress, Silent};

/// Distinct colours and their pixel counts, sorted by colour (deterministic).
pub fn histogram(colors: impl Iterator<Item = [u8; 3]>) -> Vec<([u8; 3], u64)> {
    let mut packed: Vec<u32> = colors.map(pack).collect();
    if let Some(few) = count_few(&packed) {
        return few;
    }
    packed.sort_unstable();
    let mut out: Vec<([u8; 3], u64)> = Vec::new();
    for p in packed {
        let c = unpack(p);
        match out.last_mut() {
            Some((last, n)) if *last == c => *n += 1,
            _ => out.push((c, 1)),
        }
    }
    out
}

/// [`count_few`] gives up past this many distinct colours, and the pixels
/// are sorted instead. Its table (twice as many slots, 12 bytes each: 768
/// KiB) stays in cache: the histograms of the six 1024x1024 images of
/// `bench/pat_from_image_large.sh` with 370 to 28,252 colours took 1-4 ms
/// through it against 5-15 by sorting their 10^6 pixels (median of 15),
/// and the photos, which give up within their first few per cent, took
/// the same 10-25 ms as before, within 1 ms.
const FEW_COLOURS: usize = 1 << 15;

/// The histogram of `packed` colours (`r << 16 | g << 8 | b`), counted in a
/// hash table, a run of one colour at a time; `None` if they hold more than
/// [`FEW_COLOURS`] distinct colours.
fn count_few(packed: &[u32]) -> Option<Vec<([u8; 3], u64)>> {
    // No more slots than twice the pixels: a 64x64 image's table is 8,192
    // slots, not the 65,536 of a large one (768 KiB to clear for 4,096
    // pixels).
    let slots = (2 * packed.len())
        .next_power_of_two()
        .clamp(2, 2 * FEW_COLOURS);
    let mut keys = vec![EMPTY; slots];
    let mut counts = vec![0u64; slots];
    let mut distinct = 0;
    let mut rest = packed;
    while let Some(&c) = rest.first() {
        let run = rest.iter().take_while(|&&p| p == c).count();
        rest = &rest[run..];
        let s = slot(&keys, c);
        if keys[s] == EMPTY {
            distinct += 1;
            if distinct > FEW_COLOURS {
                return None;
            }
            keys[s] = c;
        }
        counts[s] += run as u64;
    }
    let mut out: Vec<(u32, u64)> = keys
        .into_iter()
        .zip(counts)
        .filter(|&(k, _)| k != EMPTY)
        .collect();
    out.sort_unstable();
    Some(out.into_iter().map(|(p, n)| (unpack(p), n)).collect())
}

/// Chooses at most `k` colours for the weighted colour histogram `hist`. With
/// `k` or fewer distinct colours the palette is exactly those colours.
pub fn choose_palette(hist: &[([u8; 3], u64)], k: usize) -> Vec<Rgb8> {
    choose_palette_with(hist, k, &Silent)
}

/// [`choose_palette`], telling `progress` each step as it begins ("median
/// cut", "k-means", "split/merge" trial by trial, "refine").
pub fn choose_palette_with(
    hist: &[([u8; 3], u64)],
    k: usize,
    progress: &dyn Progress,
) -> Vec<Rgb8> {
    let k = k.max(1);
    if hist.len() <= k {
        return hist.iter().map(|(c, _)| Rgb8(*c)).collect();
    }
    if hist.len() > CORESET_POINTS {
        return finish(search(
            &coreset_of_histogram(hist),
            k,
            Histogram::Coreset,
            progress,
        ));
    }
    let all: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
    finish(if all.len() * k > LIGHT_SEARCH_WORK {
        search(&all, k, Histogram::Large, progress)
    } else {
        search(&all, k, Histogram::Whole, progress)
    })
}

/// The searched centres as 8-bit colours, sorted, without repeats.
fn finish(centres: Vec<Point>) -> Vec<Rgb8> {
    let mut palette: Vec<Rgb8> = centres.iter().map(|c| Rgb8(c.map(|v| v as u8))).collect();
    palette.sort();
    palette.dedup();
    palette
}

/// Histograms of at most [`CORESET_POINTS`] colours whose colours x palette
/// size exceed this are searched as a coreset is ([`Histogram::Large`]):
/// fewer Lloyd steps and no split/merge trials. On the 1024x1024 images of
/// `bench/pat_from_image_large.sh` at K = 256 (`choose_palette` alone,
/// median of 3) this took the logo's search (28,252 colours) from 93 to 67
/// ms, the drawing's (10,150) from 55 to 28 and netscape's (16,823) from 32
/// to 19, for 0.015, 0.076 and 0 dB, all three still 0.3-2.0 dB above
/// pngquant; at K = 64 the logo's from 90 to 40 ms for 0.057 dB. 2^20 is
/// the most a histogram of the small benchmark (`bench/pat_from_image.sh`:
/// at most 32,768 colours at K <= 32) can reach, so those keep the whole
/// search.
///
/// What it costs where k-means' local optima are worst, a smooth ramp (the
/// split/merge trials are what escape them): a 256x256 gradient of exactly
/// 32,768 colours (a hostile-input review's, `--crop --size 256`) lost
/// 1.0 dB, 33.65 to 32.61 at K = 64 and 39.60 to 38.59 at K = 256, in 0.02-0.03
/// s against 0.14-0.19, and fell 0.04-0.08 dB below `pngquant --nofs`
/// (32.69 and 38.63, 0.03 s). Trials with k-means cut to 50 steps
/// ([`CORESET_KMEANS_ITERATIONS`]) gave the 1.0 dB back but not the time
/// (0.17-0.18 s); trials of 10, 16 or 24 Lloyd steps each after a 50-step
/// first run gave 33.59-33.61 dB at K = 64 and 38.61-38.82 at K = 256 in
/// 0.06-0.11 s, but added 0.01-0.025 s to the logo, the drawing and
/// netscape at 1024x1024, K = 256 (whole process to /dev/null, median of 5,
/// taking turns), which would put them over pngquant's time there. Not
/// resolved: the benchmark images keep their margins over pngquant, this
/// kind of picture does not.
const LIGHT_SEARCH_WORK: usize = 1 << 20;

/// What the palette search runs on.
#[derive(Clone, Copy)]
enum Histogram {
    /// The whole histogram: k-means to convergence (within its work
    /// budget), then split/merge trials.
    Whole,
    /// The whole histogram, but large for its palette size (colours x K
    /// over [`LIGHT_SEARCH_WORK`]): searched as a coreset is.
    Large,
    /// A coreset ([`coreset`]): fewer Lloyd steps
    /// ([`CORESET_KMEANS_ITERATIONS`]) and no split/merge trials (each a
    /// whole k-means run), which on the 1024x1024 photos added 30-45 ms to
    /// runs of 0.24-0.32 s for 0.01 dB.
    Coreset,
}

/// The palette search: median cut, k-means as `histogram` says, Lloyd steps
/// on the rounded palette and, for small problems, its one-code neighbours.
fn search(
    points: &[(Point, f64)],
    k: usize,
    histogram: Histogram,
    progress: &dyn Progress,
) -> Vec<Point> {
    progress.phase("median cut", 0);
    let centres = median_cut(points, k);
    progress.phase("k-means", 0);
    let clustering = match histogram {
        Histogram::Whole => split_merge(points, kmeans(points, centres), progress),
        Histogram::Large | Histogram::Coreset => {
            kmeans_at_most(points, centres, CORESET_KMEANS_ITERATIONS)
        }
    };
    progress.phase("refine", 0);
    neighbour_search(points, integer_lloyd(points, clustering))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::test_data::lcg;

    #[test]
    fn counting_few_colours_is_sorting_them() {
        let by_sorting = |colours: &[[u8; 3]]| {
            let mut v = colours.to_vec();
            v.sort_unstable();
            let mut out: Vec<([u8; 3], u64)> = Vec::new();
            for c in v {
                match out.last_mut() {
                    Some((last, n)) if *last == c => *n += 1,
                    _ => out.push((c, 1)),
                }
            }
            out
        };
        let mut seed = 29;
        // Runs of one colour among 64 colours; then more colours than
        // FEW_COLOURS, which are sorted.
        let few: Vec<[u8; 3]> = (0..20_000)
            .map(|i| [(i / 7 % 4) as u8 * 60, lcg(&mut seed) / 64 * 64, 255])
            .collect();
        let many: Vec<[u8; 3]> = (0..3 * FEW_COLOURS)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed)))
            .collect();
        for colours in [few, many, vec![], vec![[255; 3]; 3]] {
            assert_eq!(histogram(colours.iter().copied()), by_sorting(&colours));
        }
        assert!(count_few(&[0xff_ffff, 0, 0xff_ffff]).is_some());
    }

    #[test]
    fn few_colours_give_exactly_those_colours() {
        let hist = histogram([[1, 2, 3], [9, 9, 9], [1, 2, 3]].into_iter());
        assert_eq!(hist, vec![([1, 2, 3], 2), ([9, 9, 9], 1)]);
        let pal = choose_palette(&hist, 2);
        assert_eq!(pal, vec![Rgb8([1, 2, 3]), Rgb8([9, 9, 9])]);
    }

    #[test]
    fn the_palette_does_not_depend_on_the_thread_count() {
        let mut seed = 11;
        let colours: Vec<[u8; 3]> = (0..20_000)
            .map(|_| [0; 3].map(|_: u8| lcg(&mut seed)))
            .collect();
        let hist = histogram(colours.into_iter());
        one_and_three_threads(|| choose_palette(&hist, 16));
    }

    /// `pixels` colours of three blobs, denser at their centres (seeded).
    fn three_blobs(pixels: usize, mut seed: u64) -> impl Iterator<Item = [u8; 3]> {
        (0..pixels).map(move |i| {
            let base = [[40, 90, 200], [220, 60, 30], [120, 200, 90]][i % 3];
            base.map(|b: u8| {
                let spread = lcg(&mut seed) as i32 / 4 + lcg(&mut seed) as i32 / 4 - 64;
                (b as i32 + spread).clamp(0, 255) as u8
            })
        })
    }

    #[test]
    fn a_large_histogram_searched_through_its_coreset_is_nearly_as_good_as_searched_whole() {
        use crate::quantize::test_data::weighted_error;
        // 60,000 pixels of three blobs, denser at their centres: more
        // distinct colours than CORESET_POINTS.
        let hist = histogram(three_blobs(60_000, 13));
        assert!(hist.len() > CORESET_POINTS, "{}", hist.len());
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        let error = |pal: &[Point]| weighted_error(&points, pal);
        let chosen: Vec<Point> = one_and_three_threads(|| choose_palette(&hist, 16))
            .iter()
            .map(|c| point(c.0))
            .collect();
        assert_eq!(chosen.len(), 16);
        let whole = search(&points, 16, Histogram::Whole, &Silent);
        let start = median_cut(&points, 16);
        let (e_core, e_whole, e_start) = (error(&chosen), error(&whole), error(&start));
        assert!(e_core <= 1.01 * e_whole, "{e_core} {e_whole}");
        assert!(e_core < e_start, "{e_core} {e_start}");
    }

    #[test]
    fn a_histogram_large_for_its_palette_is_searched_lightly_and_nearly_as_well() {
        use crate::quantize::test_data::weighted_error;
        // Three blobs again, fewer pixels: under CORESET_POINTS colours,
        // but over LIGHT_SEARCH_WORK with 64 of them.
        let hist = histogram(three_blobs(24_000, 19));
        let k = 64;
        assert!(hist.len() <= CORESET_POINTS && hist.len() * k > LIGHT_SEARCH_WORK);
        let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
        let error = |pal: &[Point]| weighted_error(&points, pal);
        let chosen: Vec<Point> = one_and_three_threads(|| choose_palette(&hist, k))
            .iter()
            .map(|c| point(c.0))
            .collect();
        let mut light = search(&points, k, Histogram::Large, &Silent);
        light.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(chosen, light, "the light search is the one taken");
        let whole = search(&points, k, Histogram::Whole, &Silent);
        let (e_light, e_whole) = (error(&chosen), error(&whole));
        assert!(e_light <= 1.02 * e_whole, "{e_light} {e_whole}");
    }

    /// `f`'s result, the same under one thread and three.
    fn one_and_three_threads<T: PartialEq + std::fmt::Debug + Send>(f: impl Fn() -> T + Sync) -> T {
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let one = pool(1).install(&f);
        assert_eq!(one, pool(3).install(&f));
        one
    }

    #[test]
    fn two_clusters_are_found() {
        let hist = vec![
            ([0, 0, 0], 10),
            ([2, 0, 0], 10),
            ([250, 250, 250], 5),
            ([254, 254, 254], 5),
        ];
        assert_eq!(
            choose_palette(&hist, 2),
            vec![Rgb8([1, 0, 0]), Rgb8([252, 252, 252])]
        );
    }
}
