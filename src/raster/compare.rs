//! Image error against a reference (docs/rendering.md): RMSE in 8-bit sRGB units over
//! the R, G and B channels of every pixel, PSNR, the largest channel error, and
//! the share of pixels with some channel off by more than [`OFF_THRESHOLD`].
//! Alpha, if any, is ignored (both images are compared as opaque RGB).
//! Images deeper than 8 bits (16-bit sRGB, PFM) are measured in the same
//! unit, fractional, and in linear light ([`compare_any`], [`DeepMetrics`]).
//!
//! ```
//! use patkit::io::Image;
//! use patkit::raster::compare::compare;
//!
//! let reference = Image { width: 2, height: 1, channels: 3, data: vec![0, 0, 0, 255, 255, 255] };
//! let mut image = reference.clone();
//! image.data[0] = 6; // one channel of one pixel off by 6
//! let m = compare(&image, &reference)?;
//! assert_eq!(m.max_error, 6);
//! assert_eq!(m.pixels_off, 1);
//! assert!((m.rmse - 6.0 / 6f64.sqrt()).abs() < 1e-12); // sqrt(36 / 6 channel values)
//! # Ok::<(), patkit::raster::compare::SizeMismatch>(())
//! ```

use crate::color::{linear_to_srgb_f64, srgb8_to_linear_f64};
use crate::io::{AnyImage, Image};
use crate::math;

/// Two images compared must have the same size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("image is {}x{} but the reference is {}x{}", image.0, image.1, reference.0, reference.1)]
pub struct SizeMismatch {
    /// Width and height of the image.
    pub image: (u32, u32),
    /// Width and height of the reference.
    pub reference: (u32, u32),
}

/// [`SizeMismatch`] unless the two images have the same size.
fn same_size(img: &Image, reference: &Image) -> Result<(), SizeMismatch> {
    let (image, reference) = ((img.width, img.height), (reference.width, reference.height));
    if image == reference {
        Ok(())
    } else {
        Err(SizeMismatch { image, reference })
    }
}

/// A pixel is "off" when some channel differs by more than this many codes.
pub const OFF_THRESHOLD: u8 = 4;

/// Default gain of the difference image: an error of 1 code shows as 16, an
/// error of 16 codes or more saturates.
pub const DIFF_GAIN: u32 = 16;

/// The error of an image against a reference.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Width in pixels of both images.
    pub width: u32,
    /// Height in pixels of both images.
    pub height: u32,
    /// Root mean square error over all RGB channel values, 8-bit units.
    pub rmse: f64,
    /// `20 log10(255 / rmse)` in dB; `None` (JSON null) for identical images.
    pub psnr: Option<f64>,
    /// Largest absolute channel difference. Serialized as `largest_error`
    /// (`max_error` once named another report in `scene-render --json`, and
    /// the key stays as scripts read it: docs/json.md).
    #[serde(rename = "largest_error")]
    pub max_error: u8,
    /// Share (0..=1) of pixels with a channel off by more than [`OFF_THRESHOLD`].
    pub share_off: f64,
    /// Number of such pixels.
    pub pixels_off: u64,
}

/// RGB bytes of an image, whatever its channel count.
fn rgb(img: &Image) -> impl Iterator<Item = [u8; 3]> + '_ {
    let c = img.channels as usize;
    img.data.chunks_exact(c).map(|p| [p[0], p[1], p[2]])
}

/// Compares `img` with `reference`; they must have the same size.
pub fn compare(img: &Image, reference: &Image) -> Result<Metrics, SizeMismatch> {
    same_size(img, reference)?;
    let mut sum_sq = 0u64;
    let mut max_error = 0u8;
    let mut pixels_off = 0u64;
    for (a, b) in rgb(img).zip(rgb(reference)) {
        let mut worst = 0u8;
        for ch in 0..3 {
            let d = a[ch].abs_diff(b[ch]);
            sum_sq += d as u64 * d as u64;
            worst = worst.max(d);
        }
        max_error = max_error.max(worst);
        if worst > OFF_THRESHOLD {
            pixels_off += 1;
        }
    }
    let n_px = img.width as u64 * img.height as u64;
    let rmse = (sum_sq as f64 / (3 * n_px) as f64).sqrt();
    Ok(Metrics {
        width: img.width,
        height: img.height,
        rmse,
        psnr: psnr(rmse),
        max_error,
        share_off: pixels_off as f64 / n_px as f64,
        pixels_off,
    })
}

/// The amplified difference: each channel `min(255, gain * |a - b|)`, so black
/// means equal.
pub fn diff_image(img: &Image, reference: &Image, gain: u32) -> Result<Image, SizeMismatch> {
    same_size(img, reference)?;
    let data = rgb(img)
        .zip(rgb(reference))
        .flat_map(|(a, b)| [0, 1, 2].map(|ch| (a[ch].abs_diff(b[ch]) as u32 * gain).min(255) as u8))
        .collect();
    Ok(Image {
        width: img.width,
        height: img.height,
        channels: 3,
        data,
    })
}

/// The error of an image against a reference when either is deeper than 8
/// bits (16-bit sRGB, or linear float from a PFM): the measures of
/// [`Metrics`], in the same unit, 8-bit sRGB codes, but fractional (a
/// 16-bit code c is c/257 of them, a linear value the exact sRGB value
/// times 255), so they resolve errors below one 8-bit code; and the same
/// errors in linear light.
///
/// Linear values (a PFM's) are clamped to 0..=1 first, as every encoder
/// here clamps them; alpha is ignored, as in [`compare`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DeepMetrics {
    /// Width in pixels of both images.
    pub width: u32,
    /// Height in pixels of both images.
    pub height: u32,
    /// Root mean square error over all RGB channel values, in 8-bit sRGB
    /// codes (fractional).
    pub rmse: f64,
    /// `20 log10(255 / rmse)` in dB; `None` (JSON null) for identical images.
    pub psnr: Option<f64>,
    /// Largest absolute channel difference, in 8-bit sRGB codes
    /// (fractional); `largest_error` as in [`Metrics`].
    #[serde(rename = "largest_error")]
    pub max_error: f64,
    /// Share (0..=1) of pixels with a channel off by more than
    /// [`OFF_THRESHOLD`] codes.
    pub share_off: f64,
    /// Number of such pixels.
    pub pixels_off: u64,
    /// The same errors in linear light.
    pub linear: LinearError,
    /// What the image measured is: `8-bit sRGB`, `16-bit sRGB` or `linear
    /// float` ([`crate::io::Encoding::name`]).
    pub image_encoding: &'static str,
    /// What the reference is, in the same words.
    pub reference_encoding: &'static str,
}

/// RMSE and largest channel error in linear light (0..=1).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LinearError {
    /// Root mean square over all RGB channel values.
    pub rmse: f64,
    /// Largest absolute channel difference.
    pub largest_error: f64,
}

/// A comparison's measures: [`Metrics`] when both images are 8-bit (the
/// report as it always was), [`DeepMetrics`] otherwise.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum AnyMetrics {
    /// Both images 8-bit sRGB.
    Eight(Metrics),
    /// Either image deeper.
    Deep(DeepMetrics),
}

impl AnyMetrics {
    /// The human-readable report ([`Metrics::report`], [`DeepMetrics::report`]).
    pub fn report(&self) -> String {
        match self {
            AnyMetrics::Eight(m) => m.report(),
            AnyMetrics::Deep(m) => m.report(),
        }
    }
}

/// Each channel of an image as a pair: its sRGB value in 8-bit code units
/// (fractional) and its linear-light value, RGB only, pixel by pixel.
fn channels(img: &AnyImage) -> Box<dyn Iterator<Item = [(f64, f64); 3]> + '_> {
    match img {
        AnyImage::Srgb8(i) => {
            Box::new(rgb(i).map(|p| p.map(|c| (c as f64, srgb8_to_linear_f64(c)))))
        }
        AnyImage::Srgb16(i) => {
            let c = i.channels as usize;
            Box::new(i.data.chunks_exact(c).map(|p| {
                [p[0], p[1], p[2]]
                    .map(|v| (v as f64 / 257.0, crate::color::srgb16_to_linear_f64(v)))
            }))
        }
        AnyImage::Linear(i) => Box::new(i.data.chunks_exact(3).map(|p| {
            [p[0], p[1], p[2]].map(|v| {
                let l = (v as f64).clamp(0.0, 1.0);
                (linear_to_srgb_f64(l) * 255.0, l)
            })
        })),
    }
}

/// [`SizeMismatch`] unless the two images have the same size.
fn same_size_any(img: &AnyImage, reference: &AnyImage) -> Result<(), SizeMismatch> {
    let (image, reference) = (img.size(), reference.size());
    if image == reference {
        Ok(())
    } else {
        Err(SizeMismatch { image, reference })
    }
}

/// Compares images of any encodings: [`compare`] when both are 8-bit,
/// [`DeepMetrics`] otherwise (an 8-bit image against a PFM shows its
/// quantisation in the error).
pub fn compare_any(img: &AnyImage, reference: &AnyImage) -> Result<AnyMetrics, SizeMismatch> {
    if let (AnyImage::Srgb8(a), AnyImage::Srgb8(b)) = (img, reference) {
        return compare(a, b).map(AnyMetrics::Eight);
    }
    same_size_any(img, reference)?;
    let (mut sum_sq, mut max_error, mut pixels_off) = (0f64, 0f64, 0u64);
    let (mut lin_sq, mut lin_max) = (0f64, 0f64);
    for (a, b) in channels(img).zip(channels(reference)) {
        let mut worst = 0f64;
        for ch in 0..3 {
            let d = (a[ch].0 - b[ch].0).abs();
            sum_sq += d * d;
            worst = worst.max(d);
            let dl = (a[ch].1 - b[ch].1).abs();
            lin_sq += dl * dl;
            lin_max = lin_max.max(dl);
        }
        max_error = max_error.max(worst);
        if worst > OFF_THRESHOLD as f64 {
            pixels_off += 1;
        }
    }
    let (width, height) = img.size();
    let n_px = width as u64 * height as u64;
    let values = (3 * n_px) as f64;
    let rmse = (sum_sq / values).sqrt();
    Ok(AnyMetrics::Deep(DeepMetrics {
        width,
        height,
        rmse,
        psnr: psnr(rmse),
        max_error,
        share_off: pixels_off as f64 / n_px as f64,
        pixels_off,
        linear: LinearError {
            rmse: (lin_sq / values).sqrt(),
            largest_error: lin_max,
        },
        image_encoding: img.encoding().name(),
        reference_encoding: reference.encoding().name(),
    }))
}

/// [`diff_image`] for images of any encodings: still an 8-bit picture,
/// each channel `min(255, gain * |a - b|)` with `a`, `b` in 8-bit sRGB codes
/// (fractional, as [`DeepMetrics`] measures them), rounded.
pub fn diff_any(img: &AnyImage, reference: &AnyImage, gain: u32) -> Result<Image, SizeMismatch> {
    if let (AnyImage::Srgb8(a), AnyImage::Srgb8(b)) = (img, reference) {
        return diff_image(a, b, gain);
    }
    same_size_any(img, reference)?;
    let data = channels(img)
        .zip(channels(reference))
        .flat_map(|(a, b)| {
            [0, 1, 2].map(|ch| ((a[ch].0 - b[ch].0).abs() * gain as f64).min(255.0).round() as u8)
        })
        .collect();
    let (width, height) = img.size();
    Ok(Image {
        width,
        height,
        channels: 3,
        data,
    })
}

/// The PSNR of an RMSE in 8-bit codes; `None` when the images are the
/// same. [`compare`] and [`compare_any`] measure it alike.
fn psnr(rmse: f64) -> Option<f64> {
    (rmse > 0.0).then(|| 20.0 * math::log10(255.0 / rmse))
}

/// The `psnr` line's value in both reports.
fn psnr_text(psnr: Option<f64>) -> String {
    match psnr {
        Some(p) => format!("{p:.2} dB"),
        None => "inf (identical)".to_string(),
    }
}

impl DeepMetrics {
    /// The human-readable report: the lines of [`Metrics::report`] with six
    /// decimals, then the linear-light errors and what was compared.
    pub fn report(&self) -> String {
        let psnr = psnr_text(self.psnr);
        format!(
            "size      {}x{}\nrmse      {:.6}\npsnr      {psnr}\nmax       {:.6}\noff>{OFF_THRESHOLD}     {:.4}% ({} pixels)\n\
             linear    rmse {:.3e}, max {:.3e} (linear light)\n\
             compared  {} image against {} reference (rmse, max: 8-bit sRGB codes, fractional)\n",
            self.width,
            self.height,
            self.rmse,
            self.max_error,
            self.share_off * 100.0,
            self.pixels_off,
            self.linear.rmse,
            self.linear.largest_error,
            self.image_encoding,
            self.reference_encoding,
        )
    }
}

impl Metrics {
    /// The human-readable report: one line per measure.
    pub fn report(&self) -> String {
        let psnr = psnr_text(self.psnr);
        format!(
            "size      {}x{}\nrmse      {:.4}\npsnr      {psnr}\nmax       {}\noff>{OFF_THRESHOLD}     {:.4}% ({} pixels)\n",
            self.width,
            self.height,
            self.rmse,
            self.max_error,
            self.share_off * 100.0,
            self.pixels_off
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(data: Vec<u8>, w: u32, h: u32) -> Image {
        Image {
            width: w,
            height: h,
            channels: 3,
            data,
        }
    }

    #[test]
    fn metrics_on_known_images() {
        let a = img(vec![0; 12], 2, 2);
        let mut b = a.clone();
        // One pixel off by 6 in red: sum of squares 36 over 12 values.
        b.data[0] = 6;
        let m = compare(&a, &b).unwrap();
        assert!((m.rmse - 3.0f64.sqrt()).abs() < 1e-12);
        assert!((m.psnr.unwrap() - 20.0 * math::log10(255.0 / 3.0f64.sqrt())).abs() < 1e-9);
        assert_eq!(m.max_error, 6);
        assert_eq!(m.pixels_off, 1);
        assert_eq!(m.share_off, 0.25);
        let same = compare(&a, &a).unwrap();
        assert_eq!((same.rmse, same.psnr, same.max_error), (0.0, None, 0));
        // Off by exactly 4 is not "off by more than 4".
        b.data[0] = 4;
        assert_eq!(compare(&a, &b).unwrap().pixels_off, 0);
        let d = diff_image(&a, &b, DIFF_GAIN).unwrap();
        assert_eq!(&d.data[..3], &[64, 0, 0]);
        assert!(compare(&a, &img(vec![0; 6], 2, 1)).is_err());
    }

    #[test]
    fn deep_images_are_measured_below_one_code() {
        use crate::io::{Image16, LinearImage};
        let lin = LinearImage {
            width: 2,
            height: 1,
            data: vec![0.0, 0.5, 1.0, 0.2, 0.002, 0.9],
        };
        let sixteen = Image16 {
            width: 2,
            height: 1,
            channels: 3,
            data: lin
                .data
                .iter()
                .map(|&l| crate::color::linear_to_srgb16(l))
                .collect(),
        };
        let (l, s) = (
            AnyImage::Linear(lin.clone()),
            AnyImage::Srgb16(sixteen.clone()),
        );
        // Each against itself: zero.
        for x in [&l, &s] {
            let AnyMetrics::Deep(m) = compare_any(x, x).unwrap() else {
                panic!()
            };
            assert_eq!(
                (m.rmse, m.psnr, m.max_error, m.linear.largest_error),
                (0.0, None, 0.0, 0.0)
            );
        }
        // 16-bit rounding against the linear values: at most half a 16-bit
        // code, 0.5/257 of an 8-bit one.
        let AnyMetrics::Deep(m) = compare_any(&s, &l).unwrap() else {
            panic!()
        };
        assert!(
            m.max_error > 0.0 && m.max_error <= 0.5 / 257.0 + 1e-9,
            "{m:?}"
        );
        assert_eq!(
            (m.image_encoding, m.reference_encoding),
            ("16-bit sRGB", "linear float")
        );
        assert!(m
            .report()
            .contains("compared  16-bit sRGB image against linear float reference"));
        // An 8-bit image against the PFM shows its quantisation: at most
        // half a code, and more than the 16-bit one's.
        let eight = AnyImage::Srgb8(Image {
            width: 2,
            height: 1,
            channels: 3,
            data: lin
                .data
                .iter()
                .map(|&l| crate::color::linear_to_srgb(l))
                .collect(),
        });
        let AnyMetrics::Deep(m8) = compare_any(&eight, &l).unwrap() else {
            panic!()
        };
        assert!(
            m8.max_error <= 0.5 + 1e-9 && m8.max_error > m.max_error,
            "{m8:?}"
        );
        // Two 8-bit images: the 8-bit report, unchanged.
        assert!(matches!(
            compare_any(&eight, &eight).unwrap(),
            AnyMetrics::Eight(_)
        ));
        // The difference stays an 8-bit picture.
        let d = diff_any(&eight, &l, DIFF_GAIN).unwrap();
        assert_eq!((d.width, d.channels), (2, 3));
        assert!(compare_any(&l, &AnyImage::Srgb8(img(vec![0; 3], 1, 1))).is_err());
    }

    #[test]
    fn alpha_is_ignored() {
        let a = Image {
            width: 1,
            height: 1,
            channels: 4,
            data: vec![1, 2, 3, 0],
        };
        let b = img(vec![1, 2, 3], 1, 1);
        assert_eq!(compare(&a, &b).unwrap().rmse, 0.0);
    }
}
