//! Step 2: the palette. The opaque pixels become a histogram of distinct
//! colours weighted by their pixel counts, and everything after runs on it:
//! median cut gives K starting colours ([`super::median_cut`]), k-means and its
//! refinements improve them ([`super::kmeans`]). The histogram is sorted by
//! colour and nothing is random, so the same image always gives the same
//! palette.

use super::kmeans::{integer_lloyd, kmeans, neighbour_search, split_merge};
use super::median_cut::median_cut;
use super::space::{point, Point};
use crate::color::Rgb8;
use crate::progress::{Progress, Silent};

/// Distinct colours and their pixel counts, sorted by colour (deterministic).
pub fn histogram(colors: impl Iterator<Item = [u8; 3]>) -> Vec<([u8; 3], u64)> {
    let mut packed: Vec<u32> = colors
        .map(|[r, g, b]| (r as u32) << 16 | (g as u32) << 8 | b as u32)
        .collect();
    packed.sort_unstable();
    let mut out: Vec<([u8; 3], u64)> = Vec::new();
    for p in packed {
        let c = [(p >> 16) as u8, (p >> 8) as u8, p as u8];
        match out.last_mut() {
            Some((last, n)) if *last == c => *n += 1,
            _ => out.push((c, 1)),
        }
    }
    out
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
    let points: Vec<(Point, f64)> = hist.iter().map(|(c, n)| (point(*c), *n as f64)).collect();
    progress.phase("median cut", 0);
    let centres = median_cut(&points, k);
    progress.phase("k-means", 0);
    let clustering = split_merge(&points, kmeans(&points, centres), progress);
    progress.phase("refine", 0);
    let mut palette: Vec<Rgb8> = neighbour_search(&points, integer_lloyd(&points, clustering))
        .iter()
        .map(|c| Rgb8(c.map(|v| v as u8)))
        .collect();
    palette.sort();
    palette.dedup();
    palette
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::test_data::lcg;

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
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        assert_eq!(
            one.install(|| choose_palette(&hist, 16)),
            three.install(|| choose_palette(&hist, 16))
        );
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
