//! sRGB and linear light (docs/rendering.md).
//!
//! Every 8-bit colour in the toolchain is sRGB. Anything that averages colours
//! (anti-aliasing, texture filtering, MIP levels, resampling, quantization error)
//! decodes to linear light first, averages there, then encodes and rounds once.

use crate::math;
use std::fmt;
use std::str::FromStr;

/// An 8-bit sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Rgb8(pub [u8; 3]);

impl Rgb8 {
    /// sRGB code (0, 0, 0): zero in linear light as well.
    pub const BLACK: Rgb8 = Rgb8([0, 0, 0]);
    /// sRGB code (255, 255, 255): one in linear light as well.
    pub const WHITE: Rgb8 = Rgb8([255, 255, 255]);

    /// `#rrggbb`, lowercase.
    pub fn hex(self) -> String {
        let [r, g, b] = self.0;
        format!("#{r:02x}{g:02x}{b:02x}")
    }

    /// The colour in linear light, each channel in 0..=1.
    pub fn to_linear(self) -> [f32; 3] {
        self.0.map(srgb_to_linear)
    }

    /// The colour in linear light in f64 ([`srgb8_to_linear_f64`]).
    pub fn to_linear_f64(self) -> [f64; 3] {
        self.0.map(srgb8_to_linear_f64)
    }

    /// Encode a linear-light colour, rounding to nearest (channels are clamped to 0..=1).
    pub fn from_linear(c: [f32; 3]) -> Rgb8 {
        Rgb8(c.map(linear_to_srgb))
    }

    /// The largest difference between the two colours in one channel, in
    /// codes: how far apart two linear colours are once encoded (the bound
    /// `scene-render` reports for an estimate between them).
    pub fn code_distance(self, other: Rgb8) -> u32 {
        (0..3)
            .map(|ch| self.0[ch].abs_diff(other.0[ch]) as u32)
            .max()
            .unwrap_or(0)
    }
}

impl fmt::Display for Rgb8 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [r, g, b] = self.0;
        write!(f, "{r},{g},{b}")
    }
}

/// The error of a COLOR argument, repeating what the user gave.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColorParseError(pub String);

impl fmt::Display for ColorParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid colour `{}`: expected `r,g,b` with each 0..=255 or `#rrggbb`",
            self.0
        )
    }
}

impl std::error::Error for ColorParseError {}

impl FromStr for Rgb8 {
    type Err = ColorParseError;

    /// COLOR is `r,g,b` (decimal 0..=255) or `#rrggbb` (the README's Conventions).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = || ColorParseError(s.to_string());
        let t = s.trim();
        if let Some(hex) = t.strip_prefix('#') {
            if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Err(err());
            }
            let ch = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|_| err());
            return Ok(Rgb8([ch(0)?, ch(2)?, ch(4)?]));
        }
        let parts: Vec<&str> = t.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(err());
        }
        let mut c = [0u8; 3];
        for (dst, p) in c.iter_mut().zip(&parts) {
            *dst = p.parse::<u8>().map_err(|_| err())?;
        }
        Ok(Rgb8(c))
    }
}

/// The exact sRGB transfer function (IEC 61966-2-1), decoding, in f64.
pub fn srgb_to_linear_f64(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        math::powf((c + 0.055) / 1.055, 2.4)
    }
}

/// The exact sRGB transfer function, encoding, in f64.
pub fn linear_to_srgb_f64(l: f64) -> f64 {
    if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * math::powf(l, 1.0 / 2.4) - 0.055
    }
}

/// [`srgb_to_linear_f64`] of each 8-bit code over 255: the same bits, looked
/// up. Decoding each projected polygon's colour with three `pow`s was 7.7-9%
/// of rendering a million flat triangles with `--aa none` (perf, one thread).
static DECODE_F64: std::sync::LazyLock<[f64; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|c| srgb_to_linear_f64(c as f64 / 255.0)));

/// An 8-bit sRGB code to linear light in f64: [`srgb_to_linear_f64`]`(c /
/// 255)` bit for bit, from a table.
#[inline]
pub fn srgb8_to_linear_f64(c: u8) -> f64 {
    DECODE_F64[c as usize]
}

/// The table of [`srgb8_to_linear_f64`], for loops that index it directly.
pub fn decode_table_f64() -> &'static [f64; 256] {
    &DECODE_F64
}

/// Decoding table, one entry per 8-bit code: [`DECODE_F64`] stored in f32.
static DECODE: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| DECODE_F64.map(|v| v as f32));

/// Encoding thresholds: `ENCODE_EDGES[k]` is the least f32 whose rounded sRGB
/// code is `k + 1`, the first f32 at or above the linear image of
/// `(k + 0.5) / 255`. Encoding is then a count of the edges at or below a
/// value: exact round-to-nearest of the true transfer function, with no
/// `powf` on the hot path. The f32 *nearest* each image lay below it at 127
/// of the 255 boundaries, and the f32 on such an edge took the code above
/// (test `encode_is_correctly_rounded_at_every_code_boundary`, which also
/// checks that the f64 formula deciding it has the margin to).
static ENCODE_EDGES: std::sync::LazyLock<[f32; 255]> = std::sync::LazyLock::new(|| {
    let mut t = [0f32; 255];
    for (k, v) in t.iter_mut().enumerate() {
        let boundary = k as f64 + 0.5;
        let rounds_up = |l: f32| linear_to_srgb_f64(l as f64) * 255.0 >= boundary;
        let mut edge = srgb_to_linear_f64(boundary / 255.0) as f32;
        while !rounds_up(edge) {
            edge = edge.next_up();
        }
        while rounds_up(edge.next_down()) {
            edge = edge.next_down();
        }
        *v = edge;
    }
    t
});

/// sRGB code to linear light in 0..=1.
#[inline]
pub fn srgb_to_linear(c: u8) -> f32 {
    DECODE[c as usize]
}

/// Buckets of the encoding's first step: 4096 equal slices of 0..1.
const ENCODE_BUCKETS: usize = 4096;

/// `ENCODE_START[i]`: how many [`ENCODE_EDGES`] lie at or below `i / 4096`,
/// the code at the bucket's lower end. A bucket holds at most one edge (the
/// narrowest step, at the dark end, is 3.0e-4 linear; a bucket 2.4e-4), so
/// encoding is a table read and at most one step instead of an 8-step binary
/// search: it was a fifth of a close-up wall's render.
static ENCODE_START: std::sync::LazyLock<[u8; ENCODE_BUCKETS]> = std::sync::LazyLock::new(|| {
    let edges = &*ENCODE_EDGES;
    let mut t = [0u8; ENCODE_BUCKETS];
    for (i, v) in t.iter_mut().enumerate() {
        let lo = i as f32 / ENCODE_BUCKETS as f32;
        *v = edges.partition_point(|&e| e <= lo) as u8;
    }
    t
});

/// Linear light to the nearest sRGB code. NaN maps to 0; values are clamped to 0..=1.
///
/// The result is the number of `ENCODE_EDGES` at or below `l`, exactly as
/// a binary search would count them (tested against one): the bucket of `l`
/// gives the count up to the bucket's lower end (`l * 4096` is exact in f32,
/// so that end is never above `l`), and the edges between it and `l` are
/// stepped over.
#[inline]
pub fn linear_to_srgb(l: f32) -> u8 {
    // NaN and anything not above 0 lie below every edge.
    if l.is_nan() || l <= 0.0 {
        return 0;
    }
    if l >= 1.0 {
        return 255;
    }
    let edges = &*ENCODE_EDGES;
    let mut c = ENCODE_START[(l * ENCODE_BUCKETS as f32) as usize] as usize;
    while c < edges.len() && edges[c] <= l {
        c += 1;
    }
    c as u8
}

/// The largest 16-bit code, as a scale factor.
pub const MAX16: f64 = 65535.0;

/// Linear light to the nearest 16-bit sRGB code. NaN maps to 0; values are
/// clamped to 0..=1.
///
/// **Invariant**: for every f32 `l` in 0..=1 the result is the 16-bit code
/// nearest the exact sRGB value of `l` (IEC 61966-2-1), `65535 * srgb(l)`
/// rounded to nearest. It is computed as that expression in f64: `libm`'s
/// `pow` is within about an ulp (musl's e_pow.c), so the f64 value is within
/// [`SRGB16_EVAL_ERROR`] codes of the exact one, and the test
/// `srgb16_rounding_has_margin_at_every_code_boundary` checks, at every one
/// of the 65535 rounding boundaries, that no f32 lies closer to it than that
/// (the nearest lies 2.8e-9 codes away, measured; the bound is 1e-10): rounding the f64 value
/// rounds the exact one. A table search as [`linear_to_srgb`] does would need
/// 65535 f32 edges, each itself rounded.
///
/// **Precision**: what is rounded is the *stored* f32 value. A frame's pixels
/// are f32 (relative error 2^-24 against the f64 the resolvers sum), which
/// moves the exact code by `l * 2^-24 * d(code)/dl`: at most 1.6e-4 codes on
/// the linear segment (largest at its top, `l = 0.0031308`; near black a
/// code is 1/(65535 * 12.92) = 1.2e-6 linear, 1.1e-13 at the f32 spacing
/// there) and 1.7e-3 codes on the power segment (largest at `l = 1`, where
/// a code is 3.5e-5 linear and the f32 spacing 6e-8). So the 16-bit code is
/// the correctly rounded code of the stored value, and within 0.502 codes of
/// the unstored one.
#[inline]
pub fn linear_to_srgb16(l: f32) -> u16 {
    if l.is_nan() || l <= 0.0 {
        return 0;
    }
    if l >= 1.0 {
        return u16::MAX;
    }
    (linear_to_srgb_f64(l as f64) * MAX16).round() as u16
}

/// Bound, in 16-bit codes, on the error of `65535 * linear_to_srgb_f64(l)`
/// against the exact value. The sRGB value (at most 1) carries `pow`'s ulp,
/// the rounding of the exponent `1/2.4` (up to 1.6e-16 relative, as
/// `|ln l| <= 5.8` on the power segment), and the rounding of the multiply
/// and subtract: about 6e-16 in all, 4e-11 codes once times 65535; 1e-10
/// leaves room. [`linear_to_srgb16`]'s invariant needs every f32 to lie
/// farther than this from a rounding boundary.
pub const SRGB16_EVAL_ERROR: f64 = 1e-10;

/// A 16-bit sRGB code to linear light, in f64.
#[inline]
pub fn srgb16_to_linear_f64(c: u16) -> f64 {
    srgb_to_linear_f64(c as f64 / MAX16)
}

/// The whole decoding table, for loops that want it in a register-friendly slice.
pub fn decode_table() -> &'static [f32; 256] {
    &DECODE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_f64_decoding_table_is_the_transfer_function_bit_for_bit() {
        for c in 0..=255u8 {
            let exact = srgb_to_linear_f64(c as f64 / 255.0);
            assert_eq!(srgb8_to_linear_f64(c).to_bits(), exact.to_bits(), "{c}");
        }
        let grey = srgb_to_linear_f64(128.0 / 255.0);
        assert_eq!(Rgb8([0, 128, 255]).to_linear_f64(), [0.0, grey, 1.0]);
    }

    #[test]
    fn code_distance_is_the_largest_channel_difference() {
        assert_eq!(Rgb8([10, 200, 30]).code_distance(Rgb8([12, 150, 30])), 50);
        assert_eq!(Rgb8::BLACK.code_distance(Rgb8::WHITE), 255);
        assert_eq!(Rgb8::WHITE.code_distance(Rgb8::WHITE), 0);
    }

    /// The bucketed encoder counts the edges exactly as a binary search:
    /// on every 61st f32 in 0..=1 (16 million values), at each edge and its
    /// neighbours one ulp away, and on the out-of-range values.
    #[test]
    fn bucketed_encoding_equals_the_binary_search() {
        let edges = &*ENCODE_EDGES;
        let search = |l: f32| edges.partition_point(|&e| e <= l) as u8;
        for bits in (0..=1.0f32.to_bits()).step_by(61) {
            let l = f32::from_bits(bits);
            assert_eq!(linear_to_srgb(l), search(l), "{l:e}");
        }
        for &e in edges.iter() {
            for l in [
                f32::from_bits(e.to_bits() - 1),
                e,
                f32::from_bits(e.to_bits() + 1),
            ] {
                assert_eq!(linear_to_srgb(l), search(l), "{l:e}");
            }
        }
        for l in [
            f32::NAN,
            -0.0,
            -1.0,
            f32::NEG_INFINITY,
            1.0,
            2.0,
            f32::INFINITY,
        ] {
            assert_eq!(linear_to_srgb(l), search(l), "{l:e}");
        }
    }

    #[test]
    fn encode_inverts_decode_for_every_code() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c);
        }
    }

    #[test]
    fn encode_rounds_to_nearest_like_the_f64_formula() {
        for i in 0..=100_000 {
            let l = i as f64 / 100_000.0;
            let want = (linear_to_srgb_f64(l) * 255.0).round() as u8;
            let got = linear_to_srgb(l as f32);
            // f32 storage of l can only move it across an edge by an ulp.
            assert!(
                (want as i32 - got as i32).abs() <= 1,
                "l={l} want {want} got {got}"
            );
        }
    }

    /// The 8-bit encoder is the correctly rounded code of every f32, not
    /// only within a code: at each of the 255 rounding boundaries the f32
    /// values around its linear preimage encode as the f64 formula rounds
    /// them, and that formula rounds as the exact value would (no such f32
    /// lies within the evaluation error of a boundary, as for 16 bits).
    /// The edges were the f32 nearest each preimage: 127 of them lay below
    /// it, and the f32 on such an edge took the code above.
    #[test]
    fn encode_is_correctly_rounded_at_every_code_boundary() {
        let mut closest = f64::INFINITY;
        for k in 0..255u32 {
            let boundary = k as f64 + 0.5;
            let pre = srgb_to_linear_f64(boundary / 255.0) as f32;
            for step in -3i32..=3 {
                let l = f32::from_bits((pre.to_bits() as i32 + step) as u32);
                let code = linear_to_srgb_f64(l as f64) * 255.0;
                closest = closest.min((code - boundary).abs());
                assert_eq!(
                    linear_to_srgb(l),
                    code.round() as u8,
                    "l = {l:e}, code {code}"
                );
            }
        }
        assert!(closest > 10.0 * SRGB16_EVAL_ERROR / 257.0, "{closest:e}");
    }

    /// The f64 evaluation of [`linear_to_srgb16`] rounds as the exact value
    /// would: for each boundary `(k + 0.5) / 65535` between codes, the f32
    /// values around its linear preimage (which are the f32 values nearest
    /// it, the transfer function being increasing) lie farther from it than
    /// the evaluation error. Prints the smallest margin found.
    #[test]
    fn srgb16_rounding_has_margin_at_every_code_boundary() {
        let mut closest = f64::INFINITY;
        for k in 0..65535u32 {
            let boundary = k as f64 + 0.5;
            let pre = srgb_to_linear_f64(boundary / MAX16) as f32;
            for step in -3i32..=3 {
                let l = f32::from_bits((pre.to_bits() as i32 + step) as u32);
                let code = linear_to_srgb_f64(l as f64) * MAX16;
                closest = closest.min((code - boundary).abs());
            }
        }
        eprintln!("closest f32 to a 16-bit rounding boundary: {closest:.3e} codes");
        assert!(closest > 10.0 * SRGB16_EVAL_ERROR, "{closest:e}");
    }

    #[test]
    fn srgb16_inverts_its_decoding_and_agrees_with_8_bit() {
        for c in 0..=65535u16 {
            assert_eq!(linear_to_srgb16(srgb16_to_linear_f64(c) as f32), c);
        }
        // An 8-bit code c is the 16-bit code 257 c.
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb16(srgb_to_linear(c)), c as u16 * 257);
        }
        assert_eq!(linear_to_srgb16(f32::NAN), 0);
        assert_eq!(linear_to_srgb16(-1.0), 0);
        assert_eq!(linear_to_srgb16(2.0), 65535);
    }

    #[test]
    fn encode_clamps_out_of_range_and_nan() {
        assert_eq!(linear_to_srgb(-1.0), 0);
        assert_eq!(linear_to_srgb(2.0), 255);
        assert_eq!(linear_to_srgb(f32::NAN), 0);
        assert_eq!(linear_to_srgb(f32::INFINITY), 255);
    }

    #[test]
    fn mid_grey_in_linear_light_is_188() {
        // Averaging black and white in linear light gives 0.5, which encodes to 188,
        // not the 128 a naive sRGB average gives.
        let mid = (srgb_to_linear(0) + srgb_to_linear(255)) / 2.0;
        assert_eq!(linear_to_srgb(mid), 188);
    }

    #[test]
    fn parses_both_colour_forms_and_repeats_bad_input() {
        assert_eq!("10,20,30".parse::<Rgb8>().unwrap(), Rgb8([10, 20, 30]));
        assert_eq!(" 10, 20 ,30 ".parse::<Rgb8>().unwrap(), Rgb8([10, 20, 30]));
        assert_eq!("#FFa000".parse::<Rgb8>().unwrap(), Rgb8([255, 160, 0]));
        for bad in [
            "", "1,2", "1,2,3,4", "256,0,0", "#fff", "#gg0000", "-1,0,0", "red",
        ] {
            let e = bad.parse::<Rgb8>().unwrap_err();
            assert!(e.to_string().contains(&format!("`{bad}`")), "{e}");
        }
    }
}
