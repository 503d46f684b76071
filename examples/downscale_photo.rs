//! Downscales a photograph by an integer factor, averaging each
//! `factor x factor` block in linear light, and writes it as JPEG (quality
//! 90) or PNG by the output's extension: how `fixtures/images/earth-nasa.jpg`
//! was made from xplanet's NASA map (fixtures/images/ATTRIBUTION.md).
//!
//! Usage: `cargo run --release --example downscale_photo -- IN FACTOR OUT`

use patkit::color::{linear_to_srgb_f64, srgb_to_linear_f64};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, factor, output] = args.as_slice() else {
        return Err("usage: downscale_photo IN FACTOR OUT".into());
    };
    let f: u32 = factor.parse()?;
    let img = image::open(input)?.into_rgb8();
    let (w, h) = (img.width() / f, img.height() / f);
    let out = image::RgbImage::from_fn(w, h, |x, y| {
        let mut acc = [0.0f64; 3];
        for dy in 0..f {
            for dx in 0..f {
                let p = img.get_pixel(x * f + dx, y * f + dy).0;
                for ch in 0..3 {
                    acc[ch] += srgb_to_linear_f64(p[ch] as f64 / 255.0);
                }
            }
        }
        let n = (f * f) as f64;
        image::Rgb(acc.map(|a| (linear_to_srgb_f64(a / n) * 255.0).round() as u8))
    });
    if output.ends_with(".jpg") || output.ends_with(".jpeg") {
        let file = std::io::BufWriter::new(std::fs::File::create(output)?);
        image::codecs::jpeg::JpegEncoder::new_with_quality(file, 90).encode_image(&out)?;
    } else {
        out.save(output)?;
    }
    Ok(())
}
