//! Step 1: the image brought to SIZE x SIZE, the "resampled image" that the
//! pattern is then measured against.
//!
//! Resampling averages *pixels*, and an average of pixels is an average of
//! light: it is done in linear light (a black/white checker shrinks to sRGB 188,
//! the code of 50% light, not to 128) with premultiplied alpha (a fully
//! transparent pixel's colour carries no weight). Shrinking uses a box filter,
//! the exact area average; enlarging a separable Mitchell–Netravali filter with
//! B = C = 1/3, which balances blur against ringing, its negative lobes'
//! overshoot clamped. The result is rounded to 8-bit sRGB once, at the end.
//! [`crop_square`] instead takes pixels as they are.

use crate::color::{decode_table, linear_to_srgb};
use crate::error::OptionError;

/// Mitchell–Netravali parameters B = C = 1/3: the pair its authors recommend,
/// balancing blur against ringing.
const MITCHELL_B: f64 = 1.0 / 3.0;
const MITCHELL_C: f64 = 1.0 / 3.0;
/// The Mitchell filter is zero outside |x| < 2.
const MITCHELL_SUPPORT: f64 = 2.0;

/// A SIZE x SIZE image in 8-bit sRGB with straight alpha, row 0 at the TOP.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SquareImage {
    /// Side in pixels (the pattern's SIZE).
    pub size: u32,
    /// `size * size` RGBA pixels, row-major, row 0 at the top.
    pub pixels: Vec<[u8; 4]>,
}

/// The centred largest square of `img`, resampled to `size` x `size` in linear
/// light with premultiplied alpha (box filter down, Mitchell up).
///
/// When the square already has `size` pixels a side, filtering is the
/// identity (to the bit, even with partial alpha: the test
/// `resampling_at_the_same_size_is_exact_even_with_partial_alpha` runs both
/// routes), so the square is cut out and nothing is filtered.
pub fn resample_square(img: &image::RgbaImage, size: u32) -> SquareImage {
    let (w, h) = img.dimensions();
    if w.min(h) == size {
        return centred_square(img, size);
    }
    resample_filtered(img, size)
}

/// [`resample_square`] by filtering, whatever the sizes.
fn resample_filtered(img: &image::RgbaImage, size: u32) -> SquareImage {
    let (w, h) = img.dimensions();
    let side = w.min(h);
    let (x0, y0) = ((w - side) / 2, (h - side) / 2);
    let lut = decode_table();
    let src_n = side as usize;
    let dst_n = size as usize;
    let weights = filter_weights(src_n, dst_n);
    // Horizontal pass: src_n rows of dst_n, each source row brought to
    // premultiplied linear RGBA only while it is read (16 bytes a pixel
    // for the whole picture would be 3 GB at 14000 x 14000; issue 17).
    let mut row = Vec::with_capacity(src_n);
    let mut tmp = vec![[0f32; 4]; src_n * dst_n];
    for y in 0..src_n {
        row.clear();
        row.extend((0..side).map(|x| {
            let p = img.get_pixel(x0 + x, y0 + y as u32).0;
            let a = p[3] as f32 / 255.0;
            [
                lut[p[0] as usize] * a,
                lut[p[1] as usize] * a,
                lut[p[2] as usize] * a,
                a,
            ]
        }));
        for (x, (start, ws)) in weights.iter().enumerate() {
            tmp[y * dst_n + x] =
                weighted_sum(ws.iter().enumerate().map(|(k, &wt)| (row[start + k], wt)));
        }
    }
    // Vertical pass.
    let mut pixels = Vec::with_capacity(dst_n * dst_n);
    for (start, ws) in &weights {
        for x in 0..dst_n {
            let acc = weighted_sum(
                ws.iter()
                    .enumerate()
                    .map(|(k, &wt)| (tmp[(start + k) * dst_n + x], wt)),
            );
            pixels.push(encode_premultiplied(acc));
        }
    }
    SquareImage { size, pixels }
}

fn weighted_sum(items: impl Iterator<Item = ([f32; 4], f32)>) -> [f32; 4] {
    let mut acc = [0f32; 4];
    for (p, w) in items {
        for c in 0..4 {
            acc[c] += p[c] * w;
        }
    }
    acc
}

/// Premultiplied linear RGBA to straight 8-bit sRGB, clamping the overshoot of
/// the Mitchell filter's negative lobes.
fn encode_premultiplied(p: [f32; 4]) -> [u8; 4] {
    let a = p[3].clamp(0.0, 1.0);
    let a8 = (a * 255.0).round() as u8;
    if a8 == 0 {
        return [0, 0, 0, 0];
    }
    let un = |c: f32| linear_to_srgb((c / a).clamp(0.0, 1.0));
    [un(p[0]), un(p[1]), un(p[2]), a8]
}

/// For each of `dst` output samples, the first source index and the weights
/// (summing to 1) of the source samples it averages.
fn filter_weights(src: usize, dst: usize) -> Vec<(usize, Vec<f32>)> {
    let scale = src as f64 / dst as f64;
    (0..dst)
        .map(|i| {
            if dst <= src {
                // Box: output i covers [i*scale, (i+1)*scale) of the source exactly.
                let lo = i as f64 * scale;
                let hi = (i + 1) as f64 * scale;
                let first = lo.floor() as usize;
                let last = (hi.ceil() as usize).min(src);
                let ws = (first..last)
                    .map(|j| ((hi.min(j as f64 + 1.0) - lo.max(j as f64)) / scale) as f32)
                    .collect();
                (first, ws)
            } else {
                // Mitchell, centred on the output sample's position in source
                // pixel units; taps beyond the edges repeat the edge pixel.
                let centre = (i as f64 + 0.5) * scale - 0.5;
                let first = (centre - MITCHELL_SUPPORT).ceil() as i64;
                let last = (centre + MITCHELL_SUPPORT).floor() as i64;
                let lo = first.clamp(0, src as i64 - 1) as usize;
                let hi = last.clamp(0, src as i64 - 1) as usize;
                let mut ws = vec![0f64; hi - lo + 1];
                for j in first..=last {
                    let k = j.clamp(0, src as i64 - 1) as usize;
                    ws[k - lo] += mitchell(centre - j as f64);
                }
                let total: f64 = ws.iter().sum();
                (lo, ws.iter().map(|w| (w / total) as f32).collect())
            }
        })
        .collect()
}

/// The Mitchell–Netravali cubic.
fn mitchell(x: f64) -> f64 {
    let (b, c) = (MITCHELL_B, MITCHELL_C);
    let x = x.abs();
    let v = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x.powi(3)
            + (-18.0 + 12.0 * b + 6.0 * c) * x * x
            + (6.0 - 2.0 * b)
    } else if x < MITCHELL_SUPPORT {
        (-b - 6.0 * c) * x.powi(3)
            + (6.0 * b + 30.0 * c) * x * x
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    v / 6.0
}

/// The central `size` x `size` region of `img`, pixel for pixel.
pub fn crop_square(
    img: &image::RgbaImage,
    size: u32,
    name: &str,
) -> Result<SquareImage, OptionError> {
    let (w, h) = img.dimensions();
    if w < size || h < size {
        return Err(OptionError::new(
            format!("{name}: the image is {w}x{h}, smaller than the {size}x{size} that "),
            "crop",
            " needs",
        ));
    }
    Ok(centred_square(img, size))
}

/// The centred `size` x `size` square of `img`, which is at least that large.
fn centred_square(img: &image::RgbaImage, size: u32) -> SquareImage {
    let (w, h) = img.dimensions();
    let (x0, y0) = ((w - size) / 2, (h - size) / 2);
    let mut pixels = Vec::with_capacity((size as usize).pow(2));
    // Row by row from the raw bytes, not pixel by pixel through
    // `get_pixel`'s bounds checks: 1 ms against 3-7 for the 1024x1024
    // images of `bench/pat_from_image_large.sh`.
    let (w, x0, n) = (w as usize, x0 as usize, size as usize);
    for y in y0 as usize..y0 as usize + n {
        let row = &img.as_raw()[(y * w + x0) * 4..(y * w + x0 + n) * 4];
        pixels.extend(row.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]));
    }
    SquareImage { size, pixels }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::test_data::lcg;

    fn rgba(w: u32, h: u32, mut f: impl FnMut(u32, u32) -> [u8; 4]) -> image::RgbaImage {
        image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)))
    }

    #[test]
    fn filter_weights_sum_to_one_and_are_identity_at_scale_one() {
        for (src, dst) in [(7, 7), (100, 64), (64, 16), (3, 64), (16, 48)] {
            for (_, ws) in filter_weights(src, dst) {
                let s: f32 = ws.iter().sum();
                assert!((s - 1.0).abs() < 1e-5, "{src}->{dst}: {s}");
            }
        }
        for (i, (start, ws)) in filter_weights(9, 9).into_iter().enumerate() {
            assert_eq!((start, ws), (i, vec![1.0]));
        }
    }

    #[test]
    fn resampling_at_the_same_size_is_exact_even_with_partial_alpha() {
        let mut seed = 1;
        let img = rgba(16, 16, |_, _| {
            let a = lcg(&mut seed).max(1);
            [lcg(&mut seed), lcg(&mut seed), lcg(&mut seed), a]
        });
        // Both routes: the filter, and the cut that resample_square takes.
        for out in [resample_filtered(&img, 16), resample_square(&img, 16)] {
            for (p, q) in img.pixels().zip(&out.pixels) {
                assert_eq!(p.0, *q);
            }
        }
        // And a wider image, whose centred square is cut out.
        let wide = rgba(24, 16, |_, _| {
            let a = lcg(&mut seed).max(1);
            [lcg(&mut seed), lcg(&mut seed), lcg(&mut seed), a]
        });
        assert_eq!(
            resample_filtered(&wide, 16).pixels,
            resample_square(&wide, 16).pixels
        );
    }

    #[test]
    fn shrinking_averages_in_linear_light_and_ignores_transparent_colour() {
        // Black/white checker: the linear average 0.5 encodes to 188, not 128.
        let img = rgba(32, 32, |x, y| {
            let v = if (x + y) % 2 == 0 { 255 } else { 0 };
            [v, v, v, 255]
        });
        let out = resample_square(&img, 16);
        assert!(out.pixels.iter().all(|p| *p == [188, 188, 188, 255]));
        // Red next to a fully transparent (green) pixel stays red, at half alpha.
        let img = rgba(32, 32, |x, _| {
            if x % 2 == 0 {
                [255, 0, 0, 255]
            } else {
                [0, 255, 0, 0]
            }
        });
        let out = resample_square(&img, 16);
        assert!(
            out.pixels.iter().all(|p| *p == [255, 0, 0, 128]),
            "{:?}",
            out.pixels[0]
        );
    }

    #[test]
    fn non_square_images_use_the_centred_square_and_crop_refuses_small_images() {
        // A 48x16 image: only the middle third is blue.
        let img = rgba(48, 16, |x, _| {
            if (16..32).contains(&x) {
                [0, 0, 255, 255]
            } else {
                [255, 0, 0, 255]
            }
        });
        assert!(resample_square(&img, 16)
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        assert!(resample_square(&img, 32)
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        assert!(crop_square(&img, 16, "x")
            .unwrap()
            .pixels
            .iter()
            .all(|p| *p == [0, 0, 255, 255]));
        let e = crop_square(&img, 32, "pic.png").unwrap_err().to_string();
        assert!(
            e.contains("pic.png") && e.contains("48x16") && e.contains("32x32"),
            "{e}"
        );
    }

    #[test]
    fn enlarging_a_flat_image_keeps_it_flat() {
        let img = rgba(5, 5, |_, _| [10, 200, 30, 255]);
        let out = resample_square(&img, 64);
        assert!(out.pixels.iter().all(|p| *p == [10, 200, 30, 255]));
    }
}
