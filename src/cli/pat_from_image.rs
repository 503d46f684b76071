//! `pat-from-image`: converts an image to a `.pat` texture pattern by
//! resampling (or cropping) it to SIZE x SIZE and quantizing it to K colours
//! (see [`crate::quantize`] for how and why).

use crate::cli::{eprintln_or_drop, usage_bail};
use crate::color::Rgb8;
use crate::io::{self, display_name, Output};
use crate::pat::{self, Pattern};
use crate::progress::Progress;
use crate::quantize::{self, Dither, Options, DEFAULT_COLORS, MAX_QUANT_COLORS};
use anyhow::{Context, Result};
use clap::Parser;

const EXAMPLES: &str = "\
Examples:
  pat-from-image photo.jpg -o brick.pat
      64x64 texels, 16 colours chosen for the photo, no dithering.
  pat-from-image --size 32 --colors 8 --dither floyd-steinberg photo.jpg > photo.pat
  pat-from-image --crop --size 16 icon.png -o icon16.pat
      The central 16x16 pixels exactly; with 16 colours or fewer the
      conversion is lossless.
  pat-from-image --palette ega.txt --transparent 255,0,255 icon.png -o icon.pat
      Force the colours of ega.txt (lines `r,g,b` or `#rrggbb`, `#` comments,
      or a .pat file); magenta pixels become transparent texels.
  jpegtopnm photo.jpg | pat-from-image --report -o photo.pat
      Any image on standard input: here netpbm's PPM.
  pat-from-image --stripe --angle 90 --length 512 photo.jpg -o furrow.map
      A stripe modulation map: the image's luminance averaged along the
      stripes, varying upwards (90 degrees) across them.
";

/// Convert an image to a .pat texture pattern.
#[derive(Parser, Debug)]
#[command(
    name = "pat-from-image",
    version,
    about = "Convert an image to a .pat texture pattern",
    long_about = "Convert an image (PNG, JPEG, GIF, BMP, TIFF, WebP, PNM/PAM) to a \
canonical .pat texture pattern: resample it to SIZE x SIZE texels, choose a palette \
of K colours (median cut refined by k-means, deterministic) and map every pixel to \
one of them.\n\nA photo is first turned upright by its EXIF orientation (as \
phones store pictures taken sideways). An embedded ICC colour profile, or a \
PNG gAMA chunk other than sRGB's, is not applied: the pixels are taken as sRGB, \
with a warning. Of an animated GIF, \
PNG or WebP only the first frame is used, and of a TIFF of several pages the \
first page, with a warning.\n\nResampling averages in linear light with premultiplied alpha: an \
exact area average (box filter) when shrinking, a Mitchell filter when enlarging. \
A non-square image is cut to its centred largest square first (the left and right, \
or top and bottom, margins are dropped) unless --crop is given. Pixels more \
transparent than --alpha-threshold become transparent texels. The top row of the \
image becomes the last row of the pattern file, whose row 0 is the bottom.",
    after_help = EXAMPLES
)]
pub struct Args {
    /// Input image; `-` reads standard input.
    #[arg(default_value = "-")]
    pub input: String,

    /// Output .pat file; `-` is standard output. Written only if the whole
    /// conversion succeeds.
    #[arg(short, long, default_value = "-", value_name = "FILE")]
    pub output: String,

    /// Side of the pattern in texels (`N` or `NxN`): a multiple of 16 from 16
    /// to 4096.
    #[arg(long, default_value_t = 64, value_name = "N", value_parser = super::parse_pattern_side)]
    pub size: u64,

    /// Number of colours to choose, 1 to 256. An image of this many distinct
    /// colours or fewer keeps exactly its colours if it is not resampled (its
    /// centred square, or the `--crop`, is already SIZE pixels a side);
    /// resampling blends colours.
    #[arg(long, default_value_t = DEFAULT_COLORS as u64, value_name = "K", conflicts_with = "palette")]
    pub colors: u64,

    /// How pixels take palette colours. `none` (the default) keeps texels crisp
    /// and tiles seamlessly, which suits texture patterns best; `floyd-steinberg`
    /// diffuses the error (in linear light) for smooth gradients; `ordered` uses
    /// an 8x8 Bayer matrix, whose regular texture also tiles.
    #[arg(long, value_enum, default_value_t = Dither::None, value_name = "METHOD")]
    pub dither: Dither,

    /// Use these colours instead of choosing them: a .pat file (its palette, in
    /// its order) or a text file with one colour per line as `r,g,b` or `#rrggbb`
    /// (a `#` not followed by a hex digit starts a comment). At most 256 colours.
    #[arg(long, value_name = "FILE")]
    pub palette: Option<String>,

    /// Take the central N x N pixels of the image as they are, without
    /// resampling. The image must be at least N x N.
    #[arg(long)]
    pub crop: bool,

    /// Pixels whose alpha (0-255) is below this become transparent texels;
    /// 0 keeps every pixel.
    #[arg(long, default_value_t = quantize::DEFAULT_ALPHA_THRESHOLD, value_name = "A")]
    pub alpha_threshold: u8,

    /// Pixels of exactly this colour (`r,g,b` or `#rrggbb`, after resampling)
    /// become transparent texels too. Default: none.
    #[arg(long, value_name = "COLOR")]
    pub transparent: Option<Rgb8>,

    /// Print the pattern's size, colours and PSNR against the resampled image
    /// (8-bit sRGB, over coloured texels) to standard error.
    #[arg(long)]
    pub report: bool,

    /// Write a stripe modulation map instead of a pattern: the image's
    /// luminance (linear light, alpha-weighted) averaged along the stripes,
    /// its profile across them resampled to --length entries and encoded to
    /// 0..=255 sRGB.
    #[arg(long, conflicts_with_all = ["size", "colors", "dither", "palette", "crop", "transparent", "alpha_threshold", "report"])]
    pub stripe: bool,

    /// With --stripe: the direction across the stripes, degrees
    /// counter-clockwise from the image's +x axis (0: the map runs left to
    /// right; 90: bottom to top).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "DEG",
        requires = "stripe",
        allow_negative_numbers = true
    )]
    pub angle: f64,

    /// With --stripe: the map's length, a power of two from 1 to 65536.
    #[arg(long, default_value_t = crate::stripe::map::DEFAULT_LEN as u64, value_name = "N", requires = "stripe")]
    pub length: u64,

    #[command(flatten)]
    pub threads: super::ThreadArgs,

    #[command(flatten)]
    pub progress: super::progress::ProgressArgs,
}

pub fn run(args: Args) -> Result<()> {
    args.threads.install(|| run_in_pool(args))?
}

fn run_in_pool(args: Args) -> Result<()> {
    let inputs = [
        ("the picture", Some(args.input.as_str())),
        ("--palette", args.palette.as_deref()),
    ];
    // A usage error first (status 2), then the standard output's.
    super::check_inputs(&inputs)?;
    if args.output == io::STDIO {
        super::check_stdout(super::USE_OUTPUT_FILE)?;
    }
    // Before the work (quantizing a large photo takes a while).
    io::check_output(&args.output, false)?;
    super::refuse_replacing_inputs(&[("-o", Some(args.output.as_str()))], &inputs)?;
    if args.stripe {
        return run_stripe(&args);
    }
    let size = match pat::check_size(args.size) {
        Ok(s) => s,
        Err(e) => usage_bail!("invalid --size `{}`: {e}", args.size),
    };
    if !(1..=MAX_QUANT_COLORS as u64).contains(&args.colors) {
        usage_bail!(
            "invalid --colors `{}`: expected 1 to {MAX_QUANT_COLORS}",
            args.colors
        );
    }
    let palette = match &args.palette {
        Some(file) => {
            let name = display_name(file);
            // Past blank lines, so that their first line tells a pattern
            // from a list of colours however many there are.
            let opened = io::open_input(file, io::InputKind::Text)
                .and_then(io::Opened::past_blank_start)
                .context("reading the --palette file")?;
            if quantize::palette_is_pattern(&opened.start) {
                let p = pat::Pattern::read_from(&mut opened.into_reader(), name)?;
                Some(quantize::pattern_palette(&p, name)?)
            } else {
                let bytes = opened.read_input().context("reading the --palette file")?;
                Some(quantize::parse_palette_file(&bytes, name)?)
            }
        }
        None => None,
    };
    let name = display_name(&args.input);
    let bar = args.progress.bar("pat-from-image");
    bar.phase("reading", 0);
    let img = read_photo(&args.input)?;
    bar.phase("resampling", 0);
    let square = if args.crop {
        quantize::crop_square(&img, size, name)?
    } else {
        quantize::resample_square(&img, size)
    };
    // The decoded picture is not needed again (67 MB at 4096x4096).
    drop(img);
    let opts = Options {
        colors: args.colors as usize,
        dither: args.dither,
        palette,
        alpha_threshold: args.alpha_threshold,
        transparent: args.transparent,
    };
    let pattern = quantize::quantize_with(&square, &opts, &bar)?;
    drop(bar);
    // Never refused at 256 colours of 4096x4096 (1.3 GB), but the bound
    // is every .pat writer's.
    pattern
        .check_canonical_len("give fewer --colors or a smaller --size")
        .with_context(|| name.to_string())?;
    write_pattern(&pattern, &args.output)?;
    if args.report {
        let (_, transparent) = pattern.histogram();
        let psnr = match quantize::psnr(&pattern, &square) {
            Some(p) if p.is_infinite() => "inf (exact)".to_string(),
            Some(p) => format!("{p:.2} dB"),
            None => "n/a (no coloured texels)".to_string(),
        };
        let n = pattern.palette().len();
        eprintln_or_drop!(
            "pat-from-image: {}: {size}x{size}, {n} {}, {transparent} transparent {}, PSNR {psnr}",
            crate::text::one_line(name),
            if n == 1 { "colour" } else { "colours" },
            if transparent == 1 { "texel" } else { "texels" },
        );
    }
    Ok(())
}

/// The input picture, upright as its EXIF orientation says (phone photos
/// store their sensor's rows and a tag); a warning when it carries a colour
/// profile, which is not applied.
fn read_photo(input: &str) -> Result<image::RgbaImage> {
    let name = display_name(input);
    let photo = io::decode_photo(&io::read_input(input, io::InputKind::Image)?, name)?;
    if let Some(n) = photo.frames {
        super::warn(
            "pat-from-image",
            format!("{name}: has {n} frames or pages: only the first is used"),
        );
    }
    if photo.has_icc_profile {
        super::warn(
            "pat-from-image",
            format!(
                "{name}: has an ICC colour profile, which is not applied: its colours are taken \
                 as sRGB (convert it to sRGB first if they look wrong)"
            ),
        );
    }
    if let Some(gamma) = photo.foreign_gamma {
        super::warn(
            "pat-from-image",
            format!(
                "{name}: its gAMA chunk gives gamma {}, which is not applied: its colours are \
                 taken as sRGB (about gamma 2.2; convert it to sRGB first if they look wrong)",
                crate::text::readable(gamma)
            ),
        );
    }
    Ok(photo.image)
}

fn run_stripe(args: &Args) -> Result<()> {
    if let Err(e) = crate::stripe::map::check_len(args.length) {
        usage_bail!("invalid --length `{}`: {e}", args.length);
    }
    if !args.angle.is_finite() {
        usage_bail!(
            "invalid --angle `{}`: expected a finite number of degrees",
            args.angle
        );
    }
    let name = display_name(&args.input);
    let img = read_photo(&args.input)?;
    let map = crate::stripe::from_image::map_from_image(
        &img,
        args.angle,
        args.length,
        crate::stripe::Fade::default(),
    )
    .with_context(|| name.to_string())?;
    let mut out = Output::create(&args.output, false)?;
    map.write_canonical(&mut out).with_context(|| {
        format!(
            "writing {}",
            if args.output == io::STDIO {
                "standard output"
            } else {
                &args.output
            }
        )
    })?;
    Ok(out.commit()?)
}

fn write_pattern(pattern: &Pattern, output: &str) -> Result<()> {
    let mut out = Output::create(output, false)?;
    pattern.write_canonical(&mut out).with_context(|| {
        format!(
            "writing {}",
            if output == io::STDIO {
                "standard output"
            } else {
                output
            }
        )
    })?;
    Ok(out.commit()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn arguments_are_consistent_and_the_man_page_renders() {
        Args::command().debug_assert();
        let man = crate::cli::man_page(Args::command());
        assert!(man.contains("pat\\-from\\-image") && man.contains("alpha\\-threshold"));
        assert!(crate::cli::commands()
            .iter()
            .any(|c| c.get_name() == "pat-from-image"));
    }
}
