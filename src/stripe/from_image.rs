//! A modulation map from an image (`pat-from-image --stripe`): the seed's maps
//! are "amplitude waveforms" across a set of parallel stripes, so an image of
//! such a surface (a ploughed field, a runway's markings) gives one by
//! averaging it *along* the stripes and keeping the variation *across* them.
//!
//! The direction across the stripes is `angle` degrees counter-clockwise from
//! the image's +x axis (with y up, as on the screen). Each pixel's luminance in
//! linear light (Rec. 709 / sRGB primaries), weighted by its alpha, goes to the
//! one-pixel-wide bin of its centre's position along that direction; the bins'
//! profile is then resampled to the map's length (box average when shrinking,
//! linear interpolation when stretching) and encoded to 8-bit sRGB. Empty bins
//! (fully transparent pixels) take the linear interpolation of their
//! neighbours.

use super::map::InvalidMap;
use super::map::{check_len, Fade, ModulationMap};
use crate::color::{linear_to_srgb, srgb_to_linear};
use crate::math;

/// Why an image gives no stripe map.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FromImageError {
    /// The map length asked for is not a power of two in range.
    #[error(transparent)]
    Map(#[from] InvalidMap),
    /// The stripes' angle is NaN or infinite.
    #[error("the stripe angle {0} is not a finite number")]
    Angle(f64),
    /// Every pixel has alpha 0.
    #[error("the image is fully transparent: there is nothing to average")]
    Transparent,
}

/// Rec. 709 luminance weights of linear R, G, B.
const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The map of `img` across stripes at `angle` degrees, with `len` entries.
pub fn map_from_image(
    img: &image::RgbaImage,
    angle: f64,
    len: u64,
    fade: Fade,
) -> Result<ModulationMap, FromImageError> {
    let len = check_len(len)?;
    if !angle.is_finite() {
        return Err(FromImageError::Angle(angle));
    }
    // Reduced to a turn first (math::sin_cos_degrees): the radians of a
    // huge angle (1e20 degrees, exactly 280 mod 360) carry no fraction of a
    // turn, so its map was not the map of its residue.
    let (w, h) = img.dimensions();
    let (s, c) = math::sin_cos_degrees(angle);
    let (cx, cy) = (w as f64 / 2.0, h as f64 / 2.0);
    // Position across the stripes of a pixel centre; the image rows go down.
    let t = |x: u32, y: u32| (x as f64 + 0.5 - cx) * c + (cy - (y as f64 + 0.5)) * s;
    let corners = [t(0, 0), t(w - 1, 0), t(0, h - 1), t(w - 1, h - 1)];
    let tmin = corners.iter().copied().fold(f64::INFINITY, f64::min);
    let tmax = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Bins are one pixel wide and centred on whole steps from `tmin`, so the
    // axis-aligned cases put each row or column in its own bin despite the
    // round-off of sin/cos.
    let bins = (tmax - tmin).round() as usize + 1;
    let mut sum = vec![0.0f64; bins];
    let mut weight = vec![0.0f64; bins];
    for (x, y, p) in img.enumerate_pixels() {
        let a = p.0[3] as f64 / 255.0;
        if a == 0.0 {
            continue;
        }
        let lum: f64 = (0..3)
            .map(|i| LUMA[i] * srgb_to_linear(p.0[i]) as f64)
            .sum();
        let b = ((t(x, y) - tmin).round() as usize).min(bins - 1);
        sum[b] += a * lum;
        weight[b] += a;
    }
    if weight.iter().all(|&wt| wt == 0.0) {
        return Err(FromImageError::Transparent);
    }
    let mut profile: Vec<Option<f64>> = sum
        .iter()
        .zip(&weight)
        .map(|(s, &wt)| (wt > 0.0).then(|| s / wt))
        .collect();
    fill_gaps(&mut profile);
    let profile: Vec<f64> = profile.into_iter().map(|v| v.expect("filled")).collect();
    let values = resample(&profile, len)
        .into_iter()
        .map(|l| linear_to_srgb(l as f32))
        .collect();
    Ok(ModulationMap::new(values, fade)?)
}

/// Replaces empty bins by the linear interpolation of the nearest full ones
/// (or the nearest full one at the ends). At least one bin is full.
fn fill_gaps(p: &mut [Option<f64>]) {
    let full: Vec<usize> = (0..p.len()).filter(|&i| p[i].is_some()).collect();
    for i in 0..p.len() {
        if p[i].is_some() {
            continue;
        }
        let after = full.partition_point(|&j| j < i);
        let v = match (after.checked_sub(1).map(|k| full[k]), full.get(after)) {
            (Some(a), Some(&b)) => {
                let (va, vb) = (p[a].expect("full"), p[b].expect("full"));
                va + (vb - va) * (i - a) as f64 / (b - a) as f64
            }
            (Some(a), None) => p[a].expect("full"),
            (None, Some(&b)) => p[b].expect("full"),
            (None, None) => unreachable!("at least one bin is full"),
        };
        p[i] = Some(v);
    }
}

/// Resamples a profile to `n` entries: each entry covers `len/n` bins; the
/// box average of those when that is at least one bin, else the linear
/// interpolation at the entry's centre.
fn resample(p: &[f64], n: usize) -> Vec<f64> {
    let k = p.len() as f64;
    let step = k / n as f64;
    (0..n)
        .map(|i| {
            let (a, b) = (i as f64 * step, (i + 1) as f64 * step);
            if step >= 1.0 {
                let mut total = 0.0;
                let mut j = a.floor() as usize;
                while (j as f64) < b && j < p.len() {
                    let overlap = (b.min(j as f64 + 1.0) - a.max(j as f64)).max(0.0);
                    total += overlap * p[j];
                    j += 1;
                }
                total / step
            } else {
                let centre = (a + b) / 2.0 - 0.5;
                let j = centre.floor().clamp(0.0, k - 1.0) as usize;
                let f = (centre - j as f64).clamp(0.0, 1.0);
                let next = p[(j + 1).min(p.len() - 1)];
                p[j] + (next - p[j]) * f
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{Rgba, RgbaImage};

    #[test]
    fn vertical_bars_give_their_profile_at_angle_0() {
        // Four columns: black, white, black, white; 4 rows.
        let img = RgbaImage::from_fn(4, 4, |x, _| {
            let v = if x % 2 == 0 { 0 } else { 255 };
            Rgba([v, v, v, 255])
        });
        let m = map_from_image(&img, 0.0, 4, Fade::None).unwrap();
        assert_eq!(m.values(), &[0, 255, 0, 255]);
        // Shrinking to 2 entries averages in linear light: half is code 188.
        let m2 = map_from_image(&img, 0.0, 2, Fade::None).unwrap();
        assert_eq!(m2.values(), &[188, 188]);
        // Across at 90 degrees every row is the same grey.
        let m3 = map_from_image(&img, 90.0, 4, Fade::None).unwrap();
        assert!(m3.values().iter().all(|&v| v == 188), "{:?}", m3.values());
    }

    #[test]
    fn horizontal_bands_read_bottom_to_top_at_90_degrees() {
        // Row 0 (top) white, the rest black: at 90 degrees (up) it comes last.
        let img = RgbaImage::from_fn(2, 4, |_, y| {
            let v = if y == 0 { 255 } else { 0 };
            Rgba([v, v, v, 255])
        });
        let m = map_from_image(&img, 90.0, 4, Fade::None).unwrap();
        assert_eq!(m.values(), &[0, 0, 0, 255]);
    }

    /// An angle of a turn or more gives the map of its residue modulo 360
    /// (exact in floating point): 1e20 degrees, exactly 280 mod 360, gave
    /// another map, its radians having lost the fraction of a turn.
    #[test]
    fn a_huge_angle_gives_the_map_of_its_residue() {
        let img = RgbaImage::from_fn(16, 12, |x, y| {
            let v = ((x * 13 + y * 29) % 256) as u8;
            Rgba([v, 255 - v, v / 2, 255])
        });
        let map = |angle| map_from_image(&img, angle, 16, Fade::None).unwrap();
        for (huge, residue) in [(1e20, 280.0), (-1e20, 80.0), (360.0 * 1e6 + 30.0, 30.0)] {
            assert_eq!(map(huge), map(residue), "{huge}");
        }
        assert_ne!(map(280.0), map(80.0), "the image tells the angles apart");
    }

    #[test]
    fn stretching_interpolates_and_transparency_is_skipped() {
        let img = RgbaImage::from_fn(2, 1, |x, _| {
            if x == 0 {
                Rgba([0, 0, 0, 255])
            } else {
                Rgba([255, 255, 255, 255])
            }
        });
        let m = map_from_image(&img, 0.0, 8, Fade::None).unwrap();
        assert_eq!(m.values()[0], 0);
        assert_eq!(m.values()[7], 255);
        assert!(m.values().windows(2).all(|w| w[0] <= w[1]));
        let clear = RgbaImage::from_pixel(3, 3, Rgba([9, 9, 9, 0]));
        assert!(map_from_image(&clear, 0.0, 4, Fade::None)
            .unwrap_err()
            .to_string()
            .contains("fully transparent"));
        assert!(map_from_image(&img, 0.0, 1000, Fade::None)
            .unwrap_err()
            .to_string()
            .contains("not a power of two"));
    }
}
