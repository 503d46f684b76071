//! Work the renderer skips because the scene does not need it (issue 7), and
//! the switches that turn each skip off so the benchmark
//! (`bench/skips.sh`) can show what it saves. Every skip leaves the pixels
//! unchanged; only the time differs.
//!
//! - hidden: an always-opaque texture's filter runs only for fragments that
//!   turn out visible (`raster::coverage`'s deferred colour), and with
//!   `--aa exact` a textured fragment behind everything that covers its
//!   pixel is not even made (the tile sweep's drop; flat polygons are
//!   dropped regardless, as they have nothing to filter).
//! - mip: MIP levels are built on the first minified sample
//!   ([`crate::texture::Texels::pyramid`]), never for a pattern that is
//!   only magnified.
//! - transparent: the exact box filter ([`super::cells`]) skips whole texel
//!   rows and runs of columns that are transparent, using [`OpaqueRuns`].
//! - magnify: a fragment inside one texel cell takes that texel whole
//!   instead of being clipped against the cell's four sides.
//!
//! (Only referenced patterns being read is the fifth skip; it has no switch,
//! since a stream that references a pattern must read it.)

/// Which skips are on. Default value: all on ([`Skips::ALL`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Skips {
    /// Filter an always-opaque texture only where it shows. Default value: true.
    pub hidden: bool,
    /// Build MIP levels only when a sample minifies. Default value: true.
    pub mip: bool,
    /// Skip transparent texel rows and column runs in the box filter's cut.
    /// Default value: true.
    pub transparent: bool,
    /// Take a fragment inside one texel cell whole. Default value: true.
    pub magnify: bool,
}

impl Skips {
    /// Every skip on: the default, and the only setting outside benchmarks
    /// (each skip leaves the image unchanged).
    pub const ALL: Skips = Skips {
        hidden: true,
        mip: true,
        transparent: true,
        magnify: true,
    };

    /// The names `--no-skip` accepts, in the order of the fields.
    pub const NAMES: [&'static str; 4] = ["hidden", "mip", "transparent", "magnify"];

    /// [`Skips::ALL`] with the comma-separated skips of `list` turned off;
    /// the error repeats the unknown name (the caller adds where the list
    /// came from).
    pub fn all_but(list: &str) -> Result<Skips, String> {
        let mut s = Skips::ALL;
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            match name {
                "hidden" => s.hidden = false,
                "mip" => s.mip = false,
                "transparent" => s.transparent = false,
                "magnify" => s.magnify = false,
                other => {
                    return Err(format!(
                        "unknown skip {other:?}; expected a comma list of {}",
                        Skips::NAMES.join(", ")
                    ))
                }
            }
        }
        Ok(s)
    }
}

impl Default for Skips {
    fn default() -> Self {
        Skips::ALL
    }
}

/// The opaque texels of a pattern as runs of columns per row, found once per
/// pattern (it is shared by every polygon that shows it): the box filter's
/// cut asks, per strip of a fragment, which of the strip's cells can hold an
/// opaque texel, and a sparse pattern (dots on a transparent ground) answers
/// "few or none" without one texel lookup per cell.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct OpaqueRuns {
    /// The store's width: the period of the tiling along u.
    width: u32,
    /// Row `r`'s runs are `runs[starts[r]..starts[r + 1]]`.
    starts: Vec<u32>,
    /// Half-open column ranges `[c0, c1)` of opaque texels, ascending and
    /// disjoint within a row.
    runs: Vec<(u32, u32)>,
}

impl OpaqueRuns {
    /// The runs of a `width` x `height` store whose texel (c, r) is opaque
    /// when `opaque(c, r)`.
    pub fn new(width: u32, height: u32, opaque: impl Fn(u32, u32) -> bool) -> OpaqueRuns {
        let mut starts = Vec::with_capacity(height as usize + 1);
        let mut runs = Vec::new();
        for r in 0..height {
            starts.push(runs.len() as u32);
            let mut c = 0;
            while c < width {
                if !opaque(c, r) {
                    c += 1;
                    continue;
                }
                let c0 = c;
                while c < width && opaque(c, r) {
                    c += 1;
                }
                runs.push((c0, c));
            }
        }
        starts.push(runs.len() as u32);
        OpaqueRuns {
            width,
            starts,
            runs,
        }
    }

    /// The opaque runs of pattern row `r < SIZE`.
    pub fn row(&self, r: u32) -> &[(u32, u32)] {
        &self.runs[self.starts[r as usize] as usize..self.starts[r as usize + 1] as usize]
    }

    /// The inclusive spans of tiled columns `k` in `k_lo..=k_hi` whose texel
    /// in pattern row `r` is opaque, ascending, when the pattern repeats
    /// along u (column `k mod width`, docs/stream-format.md).
    pub fn spans(&self, r: u32, k_lo: i64, k_hi: i64) -> impl Iterator<Item = (i64, i64)> + '_ {
        let s = self.width as i64;
        let row = self.row(r);
        let periods = if row.is_empty() || k_hi < k_lo {
            0..0
        } else {
            k_lo.div_euclid(s)..k_hi.div_euclid(s) + 1
        };
        periods.flat_map(move |p| {
            row.iter().filter_map(move |&(c0, c1)| {
                let a = (p * s + c0 as i64).max(k_lo);
                let b = (p * s + c1 as i64 - 1).min(k_hi);
                (a <= b).then_some((a, b))
            })
        })
    }

    /// Whether any tiled column in `k_lo..=k_hi` of pattern row `r` is opaque.
    pub fn any(&self, r: u32, k_lo: i64, k_hi: i64) -> bool {
        if k_hi - k_lo + 1 >= self.width as i64 {
            return !self.row(r).is_empty();
        }
        self.spans(r, k_lo, k_hi).next().is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn unknown_skip_names_are_errors_that_repeat_the_name() {
        let e = Skips::all_but("mip,blur").unwrap_err();
        assert!(e.contains("\"blur\"") && e.contains("hidden, mip"), "{e}");
        let s = Skips::all_but("hidden, magnify").unwrap();
        assert!(!s.hidden && s.mip && s.transparent && !s.magnify);
        assert_eq!(Skips::all_but("").unwrap(), Skips::ALL);
    }

    proptest! {
        /// The spans hold exactly the opaque tiled columns of the range.
        #[test]
        fn spans_are_the_opaque_columns(
            size in 1u32..9,
            bits in proptest::collection::vec(any::<bool>(), 64),
            r in 0u32..8,
            k_lo in -30i64..30,
            len in 0i64..40,
        ) {
            let opaque = |c: u32, r: u32| bits[((r * size + c) % 64) as usize];
            let runs = OpaqueRuns::new(size, size, opaque);
            let r = r % size;
            let k_hi = k_lo + len - 1;
            let got: Vec<i64> = runs.spans(r, k_lo, k_hi).flat_map(|(a, b)| a..=b).collect();
            let want: Vec<i64> = (k_lo..=k_hi)
                .filter(|k| opaque(k.rem_euclid(size as i64) as u32, r))
                .collect();
            prop_assert_eq!(&got, &want);
            prop_assert_eq!(runs.any(r, k_lo, k_hi), !want.is_empty());
        }
    }
}
