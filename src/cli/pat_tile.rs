//! `pat-tile`: fill an image with a repeated pattern (texted's VIEW option and
//! the IRIS `colorclear`), or write a larger tiled `.pat`.

use super::{warn, IntPair, Size};
use crate::cli::usage_bail;
use crate::color::Rgb8;
use crate::io::{display_name, open_input, save_rows, ImageFormat, Output, PngOptions};
use crate::texture::{ScreenTiling, TileRows};
use anyhow::{Context, Result};
use clap::Parser;

const EXAMPLES: &str = "\
Examples:
  pat-tile --size 1024x768 -o wall.png fixtures/patterns/brick.pat
  pat-tile --size 256x256 --scale 4 --background 255,255,255 brick.pat > big.png
  pat-tile --size 640x480 --format ppm brick.pat | pnmtopng > view.png
  pat-tile --pat --size 256x256 brick.pat -o brick256.pat";

/// The image size without --size (an image's: --pat has no default).
const DEFAULT_SIZE: Size = Size {
    width: 1024,
    height: 768,
};

/// Fill a WxH image with a repeated pattern, one texel per pixel or scaled up;
/// row 0 of the pattern is at the bottom (IRIS GL). With --pat, write a larger
/// tiled pattern instead of an image.
#[derive(Parser, Debug)]
#[command(name = "pat-tile", version, after_help = EXAMPLES)]
pub struct Args {
    /// The pattern; `-` reads standard input.
    #[arg(default_value = "-")]
    pub input: String,

    /// Output file; `-` is standard output (binary output to a terminal is refused).
    #[arg(short, long, default_value = "-")]
    pub output: String,

    /// Image size (WxH); default 1024x768. With --pat the new pattern's
    /// size, NxN (square, a multiple of 16 up to 4096), which --pat needs:
    /// the default is not square.
    #[arg(long, value_name = "SIZE")]
    pub size: Option<Size>,

    /// Each texel becomes an N x N block of pixels.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=65535))]
    pub scale: u32,

    /// The texel shown at the lower-left pixel (COL,ROW); negative values allowed.
    #[arg(
        long,
        value_name = "COL,ROW",
        default_value = "0,0",
        allow_hyphen_values = true
    )]
    pub offset: IntPair,

    /// Colour for transparent texels (`r,g,b` or `#rrggbb`). Without it, PNG and
    /// PAM keep transparency as alpha and PPM shows black with a warning.
    #[arg(long, value_name = "COLOR")]
    pub background: Option<Rgb8>,

    /// Image format; by default from the output's extension, PNG on standard
    /// output. Always 8-bit sRGB: a pattern's colours are 8-bit codes, which
    /// more bits or PFM's floats would only repeat.
    #[arg(long, value_parser = eight_bit_formats())]
    pub format: Option<ImageFormat>,

    /// Write a tiled .pat of --size instead of an image.
    #[arg(long, conflicts_with = "format")]
    pub pat: bool,
}

/// Runs `pat-tile`.
pub fn run(args: Args) -> Result<()> {
    let inputs = [("the pattern", Some(args.input.as_str()))];
    // A usage error first (status 2), then the standard output's.
    super::check_inputs(&inputs)?;
    if args.output == crate::io::STDIO {
        super::check_stdout(super::USE_OUTPUT_FILE)?;
    }
    super::refuse_replacing_inputs(&[("-o", Some(args.output.as_str()))], &inputs)?;
    let tiling = ScreenTiling {
        scale: args.scale,
        offset: (args.offset.0, args.offset.1),
    };
    if args.pat {
        // The default is an image's: `--pat` alone was refused as
        // `--size 1024x768: a pattern must be square`, a value never typed.
        let Some(size) = args.size else {
            usage_bail!(
                "--pat needs --size NxN (square, a multiple of 16 up to {}): the default size, \
                 {DEFAULT_SIZE}, is not square",
                crate::pat::MAX_SIZE
            );
        };
        let Size { width, height } = size;
        if width != height || width % 16 != 0 || width > crate::pat::MAX_SIZE {
            usage_bail!(
                "--size {size}: a pattern must be square with a side that is a multiple of 16 up to {}",
                crate::pat::MAX_SIZE
            );
        }
    }
    let size = args.size.unwrap_or(DEFAULT_SIZE);
    let format = if args.pat {
        None
    } else {
        // A pattern's colours are 8-bit codes: PFM's floats would only
        // repeat them (scene-render writes PFM, from linear light).
        Some(super::output_format_8bit(args.format, &args.output)?)
    };
    let name = display_name(&args.input);
    let opened = open_input(&args.input, crate::io::InputKind::Text)?;
    let pattern = super::read_pattern(opened, name)?;

    let Some(format) = format else {
        let mut tiled = pattern
            .tiled(size.width, args.scale, tiling.offset)
            .context("tiling the pattern")?;
        if let Some(bg) = args.background {
            // Named: the error line is `pat-tile: error: NAME: ...`.
            tiled = tiled
                .with_background(bg)
                .with_context(|| name.to_string())?;
        }
        // Before the output is created: 65,535 colours tiled to 4096x4096
        // are 344 GB of text.
        tiled
            .check_canonical_len("give a smaller --size, or tile a pattern of fewer colours")
            .with_context(|| name.to_string())?;
        let mut out = Output::create(&args.output, false)?;
        tiled
            .write_canonical(&mut out)
            .with_context(|| format!("writing {}", args.output))?;
        return Ok(out.commit()?);
    };

    let mut background = args.background;
    if background.is_none() && !format.supports_alpha() && pattern.histogram().1 > 0 {
        warn(
            "pat-tile",
            format!("{name} has transparent texels and PPM has no alpha: they are black (give --background)"),
        );
        background = Some(Rgb8::BLACK);
    }
    // Made and written a row at a time: the image is never held whole.
    let mut rows = TileRows::new(&pattern, size.width, size.height, tiling, background);
    Ok(save_rows(
        &mut rows,
        &args.output,
        format,
        PngOptions::FLAT_REPEATING,
    )?)
}

/// `--format`'s values: the 8-bit formats, not PFM (scene-render's).
fn eight_bit_formats() -> impl clap::builder::TypedValueParser<Value = ImageFormat> {
    use clap::builder::TypedValueParser as _;
    use clap::ValueEnum as _;
    let eight_bit = ImageFormat::value_variants()
        .iter()
        .filter(|f| **f != ImageFormat::Pfm)
        .filter_map(ImageFormat::to_possible_value);
    clap::builder::PossibleValuesParser::new(eight_bit)
        .map(|s| ImageFormat::from_str(&s, false).expect("a listed format"))
}
