//! MIP maps: the pattern's pyramid of ever coarser copies, for the MIP
//! filters of [`super::filter`] (XGL Programmer's Guide, texture chapter,
//! "MIP Maps"; OpenGL's mipmaps).
//!
//! Levels are built in **linear light** from the pattern's linear texels, with
//! premultiplied alpha (a transparent texel is `[0, 0, 0, 0]`, an opaque one
//! `[r, g, b, 1]`), so averaging never darkens colours next to transparent
//! texels and a checker of black and white averages to linear mid grey.
//!
//! Sizes: a `.pat` side is a multiple of 16 up to 4096, not always a power of
//! two. Level `k` has side `s_k = floor(s_{k-1} / 2)` down to 1 (48, 24, 12,
//! 6, 3, 1), and each level is resampled from the one above by a separable
//! filter whose scale is the exact ratio `s_{k-1} / s_k` (2, or 3 for 3 → 1).
//! A texel of level `k` covers `scale_k = s_0 / s_k` texels of the base, the
//! factor by which texel coordinates are divided to address it. An image is
//! `W x H`: the same rule applies to each axis, a side that reaches 1 stays
//! 1 (1024 x 512, ..., 2 x 1, 1 x 1), so each axis has its own scale
//! (`W / w_k`, `H / h_k`) and the longer side sets the number of levels.
//!
//! Edges: the build needs texels beyond the pattern's edges. Under the
//! repeat and mirror boundary conditions those are the pattern's own repeated
//! or mirrored texels, so coarse levels still tile seamlessly; under
//! transparent, clamp and edge the level is extended by its nearest edge
//! texel, so neither the polygon's colour nor the clamp colour bleeds into
//! the pattern (they apply outside it at every level, at sampling time).
//!
//! Built lazily: [`crate::texture::Texels::pyramid`] builds it the first
//! time a pixel minifies and shares it between all polygons of the pattern.

/// The filter that builds each level from the one above.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum MipBuild {
    /// The area average: each coarse texel is the mean of the fine texels it
    /// covers (exact area weights when the ratio is odd, 3 → 1).
    Box,
    /// The Mitchell-Netravali cubic (B = C = 1/3), as XGL's
    /// `xgl_mipmap_texture_build` ("XGL uses the Mitchell filter"): sharper
    /// than the box, with slight negative lobes (results are clamped to the
    /// valid range).
    #[default]
    Mitchell,
}

/// How the build extends a level past one of its edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extend {
    /// Wrap around to the opposite edge (the repeat boundary).
    Repeat,
    /// Reflect about the edge, the edge texel repeated once (the mirror
    /// boundary).
    Mirror,
    /// The nearest edge texel (transparent, clamp and edge boundaries).
    Edge,
}

impl Extend {
    /// The extension that matches boundary condition `b`: a level is built
    /// from the texels a lookup past the edge would read.
    pub fn of(b: super::boundary::Boundary) -> Extend {
        use super::boundary::Boundary;
        match b {
            Boundary::Repeat => Extend::Repeat,
            Boundary::Mirror => Extend::Mirror,
            Boundary::Transparent | Boundary::Clamp | Boundary::Edge => Extend::Edge,
        }
    }

    #[inline]
    fn index(self, i: i64, size: i64) -> usize {
        (match self {
            Extend::Repeat => i.rem_euclid(size),
            Extend::Mirror => {
                let m = i.rem_euclid(2 * size);
                if m < size {
                    m
                } else {
                    2 * size - 1 - m
                }
            }
            Extend::Edge => i.clamp(0, size - 1),
        }) as usize
    }
}

/// What a pyramid was built with: a pattern's pyramid is shared only between
/// uses with the same key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MipKey {
    /// The filter that built each level from the one above.
    pub build: MipBuild,
    /// How the build extended past the left and right edges (columns).
    pub u: Extend,
    /// How the build extended past the bottom and top edges (rows).
    pub v: Extend,
}

/// One level: `width x height` premultiplied linear RGBA texels, row 0 at
/// the bottom. f32 halves the memory of a 4096 pattern's pyramid (~180 MB in
/// f64) and keeps 24 bits, far below what 8-bit output shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Width in texels: half the finer level's, rounded down, at least 1.
    pub width: u32,
    /// Height in texels: half the finer level's, rounded down, at least 1.
    pub height: u32,
    /// `width * height` texels, row-major, row 0 at the bottom.
    pub texels: Vec<[f32; 4]>,
    /// The filtered coverage of each texel (the share of shown texels, alpha
    /// aside), only for an image with partial alpha
    /// ([`crate::texture::Texels::texel_over`]); empty otherwise, where it
    /// equals the alpha.
    pub cover: Vec<f32>,
}

impl Level {
    /// Texel (column `c`, row `r` from the bottom), premultiplied linear RGBA;
    /// both must be below the level's sides.
    #[inline]
    pub fn at(&self, c: u32, r: u32) -> [f64; 4] {
        self.texels[(r * self.width + c) as usize].map(|x| x as f64)
    }

    /// [`Level::at`] shown over the colour `under` where the texels it
    /// filters were partly transparent images texels: the polygon's colour
    /// fills the share `cover - alpha`, as it does under each texel.
    #[inline]
    pub fn at_over(&self, c: u32, r: u32, under: [f64; 3]) -> [f64; 4] {
        let p = self.at(c, r);
        if self.cover.is_empty() {
            return p;
        }
        let v = self.cover[(r * self.width + c) as usize] as f64;
        let w = v - p[3];
        [
            p[0] + w * under[0],
            p[1] + w * under[1],
            p[2] + w * under[2],
            v,
        ]
    }
}

/// Levels 1.. of a pattern (level 0 is the pattern itself).
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    /// How the levels were built.
    pub key: MipKey,
    /// Levels 1, 2, ... in order, down to 1 x 1 texel
    /// (`levels[i]` is level `i + 1`; sides as [`level_dims`]).
    pub levels: Vec<Level>,
}

/// The sides of levels 1.. of a pattern of side `s0`.
pub fn level_sizes(s0: u32) -> Vec<u32> {
    let mut out = Vec::new();
    let mut s = s0;
    while s > 1 {
        s /= 2;
        out.push(s);
    }
    out
}

/// The sides (width, height) of levels 1.. of a `w x h` store: each side
/// halved, rounded down, at least 1, until both are 1. A square store's
/// sides are [`level_sizes`] on both axes; otherwise the longer side sets
/// the number of levels, and the shorter stays at 1 once it gets there.
pub fn level_dims(w: u32, h: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let (mut a, mut b) = (w, h);
    while a > 1 || b > 1 {
        a = (a / 2).max(1);
        b = (b / 2).max(1);
        out.push((a, b));
    }
    out
}

/// The Mitchell-Netravali cubic with B = C = 1/3 (Mitchell & Netravali,
/// "Reconstruction Filters in Computer Graphics", 1988): support [-2, 2],
/// integral 1.
pub fn mitchell(x: f64) -> f64 {
    const B: f64 = 1.0 / 3.0;
    const C: f64 = 1.0 / 3.0;
    let x = x.abs();
    if x < 1.0 {
        ((12.0 - 9.0 * B - 6.0 * C) * x * x * x
            + (-18.0 + 12.0 * B + 6.0 * C) * x * x
            + (6.0 - 2.0 * B))
            / 6.0
    } else if x < 2.0 {
        ((-B - 6.0 * C) * x * x * x
            + (6.0 * B + 30.0 * C) * x * x
            + (-12.0 * B - 48.0 * C) * x
            + (8.0 * B + 24.0 * C))
            / 6.0
    } else {
        0.0
    }
}

/// The taps of output texel `i` of a `from` → `to` resampling: source index
/// and normalized weight.
fn taps(build: MipBuild, i: u32, from: u32, to: u32, out: &mut Vec<(i64, f64)>) {
    out.clear();
    let r = from as f64 / to as f64;
    match build {
        MipBuild::Box => {
            // Exact overlap of source texel [t, t+1] with [i r, (i+1) r].
            let (a, b) = (i as f64 * r, (i + 1) as f64 * r);
            for t in a.floor() as i64..b.ceil() as i64 {
                let w = (b.min((t + 1) as f64) - a.max(t as f64)).max(0.0) / r;
                if w > 0.0 {
                    out.push((t, w));
                }
            }
        }
        MipBuild::Mitchell => {
            let c = (i as f64 + 0.5) * r;
            let (lo, hi) = ((c - 2.0 * r).floor() as i64, (c + 2.0 * r).ceil() as i64);
            let mut sum = 0.0;
            for t in lo..=hi {
                let w = mitchell((t as f64 + 0.5 - c) / r);
                if w != 0.0 {
                    out.push((t, w));
                    sum += w;
                }
            }
            for tap in out.iter_mut() {
                tap.1 /= sum;
            }
        }
    }
}

/// One level from the one above: rows first, then columns. `src(c, r)` is
/// texel (c, r) of the `fw x fh` level above. The horizontal pass is kept
/// only for the rows that output rows still need, so building a level holds
/// a few rows of it, not the whole `tw x fh` intermediate (a 4096 store's
/// would take 256 MB).
fn downsample<const N: usize>(
    src: impl Fn(u32, u32) -> [f64; N],
    (fw, fh): (u32, u32),
    (tw, th): (u32, u32),
    key: MipKey,
) -> Vec<[f64; N]> {
    let t = tw as usize;
    let mut taps_v = Vec::new();
    // The horizontal taps of each output column, found once.
    let taps_h: Vec<Vec<(usize, f64)>> = (0..tw)
        .map(|x| {
            if fw == tw {
                return vec![(x as usize, 1.0)];
            }
            taps(key.build, x, fw, tw, &mut taps_v);
            taps_v
                .iter()
                .map(|&(s, w)| (key.u.index(s, fw as i64), w))
                .collect()
        })
        .collect();
    let row_taps = |y: u32, out: &mut Vec<(usize, f64)>| {
        if fh == th {
            out.clear();
            out.push((y as usize, 1.0));
        } else {
            let mut v = Vec::new();
            taps(key.build, y, fh, th, &mut v);
            out.clear();
            out.extend(v.iter().map(|&(s, w)| (key.v.index(s, fh as i64), w)));
        }
    };
    // The last output row that reads each source row.
    let mut last_use = vec![None::<u32>; fh as usize];
    let mut tv = Vec::new();
    for y in 0..th {
        row_taps(y, &mut tv);
        for &(s, _) in &tv {
            last_use[s] = Some(y);
        }
    }
    let mut mid: Vec<Option<Vec<[f64; N]>>> = vec![None; fh as usize];
    let mut out = vec![[0.0f64; N]; t * th as usize];
    for y in 0..th {
        row_taps(y, &mut tv);
        for &(s, _) in &tv {
            if mid[s].is_none() {
                // Horizontal: source row s, fw -> tw.
                mid[s] = Some(
                    taps_h
                        .iter()
                        .map(|th| {
                            let mut acc = [0.0; N];
                            for &(c, w) in th {
                                let p = src(c as u32, s as u32);
                                for ch in 0..N {
                                    acc[ch] += w * p[ch];
                                }
                            }
                            acc
                        })
                        .collect(),
                );
            }
        }
        for x in 0..t {
            let mut acc = [0.0; N];
            for &(s, w) in &tv {
                let p = mid[s].as_ref().expect("computed above")[x];
                for ch in 0..N {
                    acc[ch] += w * p[ch];
                }
            }
            // Mitchell's negative lobes can overshoot: keep a valid
            // premultiplied colour (alpha in [0, 1], channels in [0, alpha],
            // coverage in [alpha, 1]).
            let a = acc[3].clamp(0.0, 1.0);
            let mut o = [0.0; N];
            for ch in 0..3 {
                o[ch] = acc[ch].clamp(0.0, a);
            }
            o[3] = a;
            for ch in 4..N {
                o[ch] = acc[ch].clamp(a, 1.0);
            }
            out[y as usize * t + x] = o;
        }
        for &(s, _) in &tv {
            if last_use[s] == Some(y) {
                mid[s] = None;
            }
        }
    }
    out
}

/// Builds levels 1.. of a `w x h` store whose premultiplied texel (c, r)
/// is `base(c, r)`: RGBA, or RGBA and coverage when `N` is 5 (an image with
/// partial alpha, [`Level::cover`]). Each level is built from the f64
/// values of the one above and stored as f32.
pub fn build<const N: usize>(
    base: impl Fn(u32, u32) -> [f64; N],
    w: u32,
    h: u32,
    key: MipKey,
) -> Pyramid {
    let mut levels = Vec::new();
    let mut cur: Vec<[f64; N]> = Vec::new();
    let mut from = (w, h);
    for to in level_dims(w, h) {
        cur = if levels.is_empty() {
            downsample(&base, from, to, key)
        } else {
            let fw = from.0 as usize;
            downsample(|c, r| cur[r as usize * fw + c as usize], from, to, key)
        };
        levels.push(Level {
            width: to.0,
            height: to.1,
            texels: cur
                .iter()
                .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32])
                .collect(),
            cover: if N > 4 {
                cur.iter().map(|p| p[N - 1] as f32).collect()
            } else {
                Vec::new()
            },
        });
        from = to;
    }
    Pyramid { key, levels }
}

#[cfg(test)]
mod tests {
    use super::*;

    const REPEAT: MipKey = MipKey {
        build: MipBuild::Mitchell,
        u: Extend::Repeat,
        v: Extend::Repeat,
    };

    /// [`build`] from a square store's texels in a vector.
    fn build_vec(base: &[[f64; 4]], s: u32, key: MipKey) -> Pyramid {
        build(|c, r| base[(r * s + c) as usize], s, s, key)
    }

    /// Premultiplied texels of a black/white checker of single texels.
    fn checker(s: u32) -> Vec<[f64; 4]> {
        (0..s * s)
            .map(|i| {
                let w = ((i % s + i / s) % 2) as f64;
                [w, w, w, 1.0]
            })
            .collect()
    }

    /// Largest rounding of the f32 levels: ~1e-7 relative, far below 8 bits.
    const F32_TOL: f64 = 1e-6;

    #[test]
    fn sizes_halve_down_to_one_for_any_multiple_of_16() {
        assert_eq!(level_sizes(16), vec![8, 4, 2, 1]);
        assert_eq!(level_sizes(48), vec![24, 12, 6, 3, 1]);
        assert_eq!(level_sizes(4096).len(), 12);
    }

    #[test]
    fn every_level_of_a_checker_is_linear_mid_grey() {
        for b in [MipBuild::Box, MipBuild::Mitchell] {
            for s in [16, 48] {
                let p = build_vec(&checker(s), s, MipKey { build: b, ..REPEAT });
                for (k, l) in p.levels.iter().enumerate() {
                    for t in &l.texels {
                        assert!(
                            (t[0] as f64 - 0.5).abs() < F32_TOL
                                && (t[3] as f64 - 1.0).abs() < F32_TOL,
                            "{b:?} size {s} level {} texel {t:?}",
                            k + 1
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn filter_weights_sum_to_one() {
        let mut v = Vec::new();
        for build in [MipBuild::Box, MipBuild::Mitchell] {
            for (from, to) in [(16, 8), (3, 1), (48, 24)] {
                for i in 0..to {
                    taps(build, i, from, to, &mut v);
                    let s: f64 = v.iter().map(|t| t.1).sum();
                    assert!((s - 1.0).abs() < 1e-12, "{build:?} {from}->{to} {i}: {s}");
                }
            }
        }
    }

    #[test]
    fn transparent_texels_do_not_darken_their_neighbours() {
        // Left half opaque red, right half transparent: premultiplied, the
        // un-premultiplied colour of every partly covered coarse texel is red.
        let s = 16u32;
        let base: Vec<[f64; 4]> = (0..s * s)
            .map(|i| {
                if i % s < 8 {
                    [1.0, 0.0, 0.0, 1.0]
                } else {
                    [0.0; 4]
                }
            })
            .collect();
        let p = build_vec(
            &base,
            s,
            MipKey {
                build: MipBuild::Box,
                ..REPEAT
            },
        );
        for l in &p.levels {
            for t in &l.texels {
                if t[3] > 0.0 {
                    assert!(
                        ((t[0] / t[3]) as f64 - 1.0).abs() < F32_TOL && t[1] == 0.0,
                        "{t:?}"
                    );
                }
            }
        }
        // Level 4 (1x1) is half covered.
        assert!((p.levels[3].texels[0][3] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_edge_extension_keeps_a_gradient_monotone() {
        // Under repeat, column 0 of level 1 mixes in the far edge; under
        // edge extension it does not.
        let s = 16u32;
        let base: Vec<[f64; 4]> = (0..s * s)
            .map(|i| {
                let g = (i % s) as f64 / 15.0;
                [g, g, g, 1.0]
            })
            .collect();
        let edge = build_vec(
            &base,
            s,
            MipKey {
                build: MipBuild::Mitchell,
                u: Extend::Edge,
                v: Extend::Edge,
            },
        );
        let rep = build_vec(&base, s, REPEAT);
        let row = |p: &Pyramid| (0..8).map(|c| p.levels[0].at(c, 0)[0]).collect::<Vec<_>>();
        let e = row(&edge);
        assert!(e.windows(2).all(|w| w[0] <= w[1]), "{e:?}");
        assert!(row(&rep)[0] > e[0]);
    }

    #[test]
    fn a_non_square_store_halves_each_side_down_to_one() {
        assert_eq!(
            level_dims(8, 2),
            vec![(4, 1), (2, 1), (1, 1)],
            "the short side stays at 1"
        );
        assert_eq!(level_dims(48, 48).len(), level_sizes(48).len());
        assert_eq!(level_dims(5, 3), vec![(2, 1), (1, 1)]);
        // A 32 x 16 checker stays linear mid grey at every level.
        let base: Vec<[f64; 4]> = (0..32 * 16)
            .map(|i| {
                let w = ((i % 32 + i / 32) % 2) as f64;
                [w, w, w, 1.0]
            })
            .collect();
        for b in [MipBuild::Box, MipBuild::Mitchell] {
            let p = build(
                |c, r| base[(r * 32 + c) as usize],
                32,
                16,
                MipKey { build: b, ..REPEAT },
            );
            assert_eq!(p.levels.len(), 5);
            for l in &p.levels {
                assert_eq!(l.texels.len(), (l.width * l.height) as usize);
                for t in &l.texels {
                    assert!((t[0] as f64 - 0.5).abs() < F32_TOL, "{b:?} {t:?}");
                }
            }
        }
    }
}
