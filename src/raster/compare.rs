//! Image error against a reference (docs/rendering.md): RMSE in 8-bit sRGB units over
//! the R, G and B channels of every pixel, PSNR, the largest channel error, and
//! the share of pixels with some channel off by more than [`OFF_THRESHOLD`].
//! Alpha, if any, is ignored (both images are compared as opaque RGB).
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

use crate::io::Image;
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
    /// Largest absolute channel difference. Serialized as `largest_error`:
    /// `max_error` names `--max-error`'s report in `scene-render --json`,
    /// and one key should mean one thing (docs/json.md).
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
        psnr: (rmse > 0.0).then(|| 20.0 * math::log10(255.0 / rmse)),
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

impl Metrics {
    /// The human-readable report: one line per measure.
    pub fn report(&self) -> String {
        let psnr = match self.psnr {
            Some(p) => format!("{p:.2} dB"),
            None => "inf (identical)".to_string(),
        };
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
