//! The texel store: a pattern decoded for sampling.

use super::mip::{Extend, MipBuild, MipKey};
use crate::color::srgb_to_linear_f64;
use crate::pat::Pattern;

/// A pattern's texels decoded to linear light once, with what every filter
/// shares: the opaque runs of its rows and its MIP pyramids. One store serves
/// every placement (screen, object, uv) and every polygon that uses the
/// pattern, so each `.pat` is decoded once per run.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    size: u32,
    /// Row 0 at the bottom; `None` is transparent.
    texels: Vec<Option<[f64; 3]>>,
    /// Whether any texel is transparent, found once (resolvers ask per
    /// fragment).
    transparent: bool,
    /// The opaque runs of each texel row, found once for the box filter's
    /// transparent-run skip ([`crate::texture::skip`]).
    runs: super::skip::OpaqueRuns,
    /// Its MIP pyramids, built on first use, one per [`MipKey`] (18 keys:
    /// 2 builds x 3 x 3 edge extensions), shared by every polygon that
    /// holds this pattern.
    pyramids: [std::sync::OnceLock<super::mip::Pyramid>; MIP_KEYS],
}

/// The number of distinct [`MipKey`]s.
const MIP_KEYS: usize = 18;

fn mip_key_index(k: MipKey) -> usize {
    let e = |x: Extend| match x {
        Extend::Repeat => 0,
        Extend::Mirror => 1,
        Extend::Edge => 2,
    };
    (k.build == MipBuild::Mitchell) as usize * 9 + e(k.u) * 3 + e(k.v)
}

impl Texels {
    /// Decodes every texel of `p` (sRGB → linear, f64).
    pub fn new(p: &Pattern) -> Texels {
        let size = p.size();
        let mut texels = Vec::with_capacity((size * size) as usize);
        for row in 0..size {
            for col in 0..size {
                texels.push(
                    p.color_at(col, row)
                        .map(|c| c.0.map(|ch| srgb_to_linear_f64(ch as f64 / 255.0))),
                );
            }
        }
        let runs =
            super::skip::OpaqueRuns::new(size, |c, r| texels[(r * size + c) as usize].is_some());
        Texels {
            size,
            transparent: texels.iter().any(|t| t.is_none()),
            runs,
            texels,
            pyramids: std::array::from_fn(|_| std::sync::OnceLock::new()),
        }
    }

    /// Texel (c, r), `c, r < SIZE`, as premultiplied linear RGBA.
    #[inline]
    pub fn premultiplied(&self, c: u32, r: u32) -> [f64; 4] {
        match self.texels[(r * self.size + c) as usize] {
            Some(t) => [t[0], t[1], t[2], 1.0],
            None => [0.0; 4],
        }
    }

    /// The MIP pyramid built with `key`: built by the first caller (others
    /// wait for it), then shared.
    pub fn pyramid(&self, key: MipKey) -> &super::mip::Pyramid {
        self.pyramids[mip_key_index(key)].get_or_init(|| {
            let s = self.size;
            let base: Vec<[f64; 4]> = (0..s * s)
                .map(|i| self.premultiplied(i % s, i / s))
                .collect();
            super::mip::build(&base, s, key)
        })
    }

    /// Linear colour of pixel (x, y) counted from the lower-left.
    #[inline]
    pub fn at(&self, x: u32, y: u32) -> Option<[f64; 3]> {
        self.texels[((y % self.size) * self.size + x % self.size) as usize]
    }

    /// Linear colour of texel cell (k, j) of the infinite tiling: column
    /// `k mod SIZE`, row `j mod SIZE` (SPEC §2); `None` is transparent.
    #[inline]
    pub fn texel(&self, k: i64, j: i64) -> Option<[f64; 3]> {
        let s = self.size as i64;
        self.texels[(j.rem_euclid(s) * s + k.rem_euclid(s)) as usize]
    }

    /// Side of the pattern in texels.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// Whether any texel is transparent (the pattern has an alpha channel).
    pub fn has_transparency(&self) -> bool {
        self.transparent
    }

    /// The opaque runs of each texel row.
    pub fn runs(&self) -> &super::skip::OpaqueRuns {
        &self.runs
    }
}
