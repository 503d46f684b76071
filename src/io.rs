//! Streams and images: `-` for standard input/output, atomic output files,
//! and the image formats the tools write (the README's Conventions): PNG,
//! PPM and PAM in 8- or 16-bit sRGB, and PFM in linear light.

use crate::error::OptionError;
use std::io::{self, BufWriter, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};

mod palette_index;
mod pnm_samples;

/// Checks that `name` can be written, as [`Output::create`] would, and
/// writes nothing: for tools to refuse a missing directory or a terminal
/// before hours of work rather than after.
///
/// A FIFO named as the output is not opened: opening it waits for a
/// reader, and closing it again ends that reader's input before any byte
/// is written (`cat fifo > copy &` got nothing, and the tool then waited
/// for a second reader for ever).
pub fn check_output(name: &str, binary: bool) -> Result<(), IoError> {
    #[cfg(unix)]
    if name != STDIO {
        use std::os::unix::fs::FileTypeExt;
        if std::fs::metadata(name).is_ok_and(|m| m.file_type().is_fifo()) {
            return Ok(());
        }
    }
    Output::create(name, binary).map(drop)
}

/// The name that means standard input or output.
pub const STDIO: &str = "-";

/// How errors name standard input.
pub const STDIN_NAME: &str = "<stdin>";

/// The widest or tallest image any tool will make. 65535 is PNG-safe on every
/// decoder we know of and far beyond any screen.
pub const MAX_IMAGE_SIDE: u32 = 65_535;
/// The most pixels any tool will allocate for one image: 2^28 is 1 GiB of RGBA.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

/// Why an input could not be read or an output written. `Display` says what
/// was being done and to which file; [`std::error::Error::source`] gives the
/// operating system's (or the decoder's) cause, so the tools' `context: cause`
/// chain reads `out.png: cannot create a file in /ro: Permission denied`.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// An input could not be read.
    #[error("{}", if input == STDIO {
        "reading standard input"
    } else if input.is_empty() {
        "an empty input name"
    } else {
        input
    })]
    Read {
        /// The input's name as given; `-` is standard input.
        input: String,
        /// The cause.
        #[source]
        error: io::Error,
    },
    /// Binary output (an image, a pattern) was about to go to a terminal.
    #[error("refusing to write binary output to a terminal: use -o FILE or a pipe")]
    BinaryToTerminal,
    /// The output name is empty (`-o ''`).
    #[error("an empty output name: expected a file name, or - for standard output")]
    EmptyOutputName,
    /// The output name is a directory.
    #[error("{output}: is a directory, expected an output file name")]
    OutputIsDirectory {
        /// The output's name as given.
        output: String,
    },
    /// An output could not be opened, written or moved into place.
    #[error("{}", step.describe(output))]
    Write {
        /// The output's name (`-` is standard output).
        output: String,
        /// Which step failed.
        step: WriteStep,
        /// The cause.
        #[source]
        error: io::Error,
    },
    /// An input is not an image the `image` crate decodes.
    #[error("{input}: not an image this tool can read")]
    NotAnImage {
        /// The input's name, as errors show it.
        input: String,
        /// The decoder's complaint.
        #[source]
        error: image::ImageError,
    },
    /// A JPEG whose data stops before its end-of-image marker: the decoder
    /// would fill the rest with grey and say nothing.
    #[error("{input}: truncated JPEG: the data ends before its end-of-image marker")]
    TruncatedJpeg {
        /// The input's name, as errors show it.
        input: String,
    },
    /// A JPEG whose segments do not walk to a scan: a segment length under
    /// 2, a byte where a marker belongs, or an end-of-image marker before
    /// any scan. Called truncated before, though the data had its end (a
    /// hostile-input review).
    #[error("{input}: malformed JPEG: {what}")]
    MalformedJpeg {
        /// The input's name, as errors show it.
        input: String,
        /// What is wrong, and at which byte.
        what: String,
    },
    /// An input picture larger than any tool makes one ([`Image::check_size`]),
    /// refused from its header, before its pixels are decoded.
    #[error("{input}: {error}")]
    PictureTooLarge {
        /// The input's name, as errors show it.
        input: String,
        /// Which limit it is over.
        error: SizeError,
    },
    /// An input that starts as a PFM but is not a valid one.
    #[error("{input}: not a valid PFM image")]
    BadPfm {
        /// The input's name, as errors show it.
        input: String,
        /// What is wrong, and where.
        #[source]
        error: PfmError,
    },
    /// A netpbm picture with a sample over its header's maxval.
    #[error(
        "{input}: the sample {value} at pixel ({x}, {y}) is over the header's maxval {maxval}"
    )]
    OverMaxval {
        /// The input's name, as errors show it.
        input: String,
        /// The sample.
        value: u64,
        /// The header's maxval.
        maxval: u32,
        /// Its pixel (0-based, row 0 at the top).
        x: u64,
        /// Its row.
        y: u64,
    },
    /// An indexed PNG, GIF or BMP with a pixel whose index is past its palette.
    #[error(
        "{input}: the palette index {index} at pixel ({x}, {y}) is past the palette \
         ({colours} colours)"
    )]
    PastPalette {
        /// The input's name, as errors show it.
        input: String,
        /// The index.
        index: u8,
        /// Entries in the palette (`PLTE`).
        colours: usize,
        /// Its pixel (0-based, row 0 at the top).
        x: u32,
        /// Its row.
        y: u32,
    },
    /// A floating-point picture with a sample that is not a finite number.
    #[error("{input}: the sample {value} at pixel ({x}, {y}) is not a finite number")]
    NotFinite {
        /// The input's name, as errors show it.
        input: String,
        /// Where the first such sample is (0-based, row 0 at the top).
        x: u64,
        /// Its row.
        y: u64,
        /// The sample (NaN or an infinity).
        value: f32,
    },
    /// An image used as a texture has more pixels than a texture may.
    #[error(
        "{input}: image of {width}x{height} pixels is too large for a texture: \
         at most {limit} texels (4096x4096, in any aspect)"
    )]
    TextureTooLarge {
        /// The input's name, as errors show it.
        input: String,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
        /// The most pixels allowed.
        limit: u64,
    },
    /// An animation frame of another size than the animation's.
    #[error(
        "{}: frame of {}x{} with {} channels in an animation of {}x{} with {}",
        display_out(output), frame.0, frame.1, frame.2, animation.0, animation.1, animation.2
    )]
    FrameMismatch {
        /// The output's name.
        output: String,
        /// The frame's width, height and channels.
        frame: (u32, u32, u8),
        /// The animation's width, height and channels.
        animation: (u32, u32, u8),
    },
}

/// The step of writing an output that failed, for [`IoError::Write`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WriteStep {
    /// Opening a device or pipe named as the output.
    Open,
    /// Following a symbolic link to the file it names.
    ResolveLink,
    /// Creating the temporary file, in this directory, that becomes the output.
    CreateIn(PathBuf),
    /// Writing (or flushing) the data.
    Write,
    /// Moving the finished temporary file to the output's name.
    Rename,
}

impl WriteStep {
    fn describe(&self, output: &str) -> String {
        match self {
            WriteStep::Open => format!("{}: cannot open for writing", display_out(output)),
            WriteStep::ResolveLink => format!("{output}: cannot resolve the link"),
            WriteStep::CreateIn(dir) => {
                format!("{output}: cannot create a file in {}", dir.display())
            }
            WriteStep::Write => format!("writing {}", display_out(output)),
            WriteStep::Rename => format!("renaming the output to {output}"),
        }
    }
}

/// An image size that no tool will make: see [`Image::check_size`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SizeError {
    /// A side is 0.
    #[error("image size {0}x{1} is empty: both sides must be at least 1")]
    Empty(u32, u32),
    /// A side is over [`MAX_IMAGE_SIDE`].
    #[error("image size {0}x{1} is too large: each side at most {MAX_IMAGE_SIDE}")]
    SideTooLarge(u32, u32),
    /// The area is over [`MAX_IMAGE_PIXELS`].
    #[error("image size {0}x{1} is too large: at most {MAX_IMAGE_PIXELS} pixels")]
    TooManyPixels(u32, u32),
}

/// [`IoError::Write`] at `step` of writing `output`.
fn write_error(output: impl Into<String>, step: WriteStep) -> impl FnOnce(io::Error) -> IoError {
    let output = output.into();
    move |error| IoError::Write {
        output,
        step,
        error,
    }
}

/// The operating system's error without the temporary file's name, which
/// `tempfile` adds (to a failed creation, and to every failed write of a
/// `NamedTempFile`) and which means nothing to the user (the message names
/// the output and its directory).
fn without_temp_name(e: io::Error) -> io::Error {
    // tempfile's error words it "{cause} at path {temporary file}" and does
    // not give the cause back as a source: keep the words before the path.
    let text = e.to_string();
    match text.find(" at path ") {
        Some(i) => io::Error::new(e.kind(), text[..i].to_string()),
        None => e,
    }
}

/// The PNG encoder's error as the I/O error it carries, or as an I/O error
/// that wraps it, of the kind of the I/O error found among its causes: a
/// closed pipe then reads as `BrokenPipe`, however deep.
fn png_io_error(e: png::EncodingError) -> io::Error {
    match e {
        png::EncodingError::IoError(io) => io,
        other => wrapped_io_error(other),
    }
}

/// `e` as an I/O error of the kind of the first I/O error among its causes.
fn wrapped_io_error<E: std::error::Error + Send + Sync + 'static>(e: E) -> io::Error {
    let mut kind = io::ErrorKind::Other;
    let mut cause = e.source();
    while let Some(c) = cause {
        if let Some(io) = c.downcast_ref::<io::Error>() {
            kind = io.kind();
            break;
        }
        // The PNG encoder's I/O error is not its `source`, but a variant.
        if let Some(png::EncodingError::IoError(io)) = c.downcast_ref::<png::EncodingError>() {
            kind = io.kind();
            break;
        }
        cause = c.source();
    }
    io::Error::new(kind, e)
}

/// The largest file a stream may name (a pattern, a stripe map or table):
/// 256 MiB, far beyond any pattern of the format's 4096x4096 texels in a
/// sensible number of colours, and a bound on what a scene can make a tool
/// read.
pub const MAX_NAMED_FILE_BYTES: u64 = 1 << 28;

/// The largest camera file read: 1 MiB, thousands of times a camera's few
/// numbers with any amount of spacing, and a bound on what `--camera` reads
/// from a device or a pipe that never ends (`--camera /dev/zero` read until
/// memory ran out).
pub const MAX_CAMERA_BYTES: u64 = 1 << 20;

/// Reads a file that an input names (a stream's pattern, stripe map or
/// table): only a regular file (a scene naming `/dev/zero` or a FIFO is
/// refused, not read forever) of at most [`MAX_NAMED_FILE_BYTES`].
pub fn read_path(path: &Path) -> io::Result<Vec<u8>> {
    open_path(path)?.read_all()
}

/// Opens a file that an input names, refusing what [`read_path`] refuses
/// but its size, and reads its first bytes: a caller that finds a `.pat`
/// there reads it as a stream ([`Opened::into_reader`]), bounded by its
/// header rather than by [`MAX_NAMED_FILE_BYTES`].
pub fn open_path(path: &Path) -> io::Result<Opened> {
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(is_a_directory());
    }
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "is not a regular file: a stream names only files",
        ));
    }
    let mut file = std::fs::File::open(path)?;
    let start = read_start(&mut file)?;
    Ok(Opened {
        start,
        rest: Box::new(file),
        limit: MAX_NAMED_FILE_BYTES,
        known_len: Some(meta.len()),
        limit_says: "a named file may have",
        input: path.display().to_string(),
        blank_lines: 0,
    })
}

/// An input opened and its first bytes read (up to `SNIFF_BYTES`), to be
/// read whole, bounded as its kind says ([`Opened::read_all`]), or as a
/// stream whose reader bounds it ([`Opened::into_reader`]).
pub struct Opened {
    /// The first bytes.
    pub start: Vec<u8>,
    rest: Box<dyn Read>,
    /// The most bytes [`Opened::read_all`] reads, and what it is, for its error.
    limit: u64,
    limit_says: &'static str,
    /// A regular file's length, to refuse one too large before reading it.
    known_len: Option<u64>,
    /// The name it was opened by, for [`Opened::read_input`]'s errors.
    input: String,
    /// Newlines of the whitespace before `start` that
    /// [`Opened::past_blank_start`] read past: given back before `start`.
    blank_lines: u64,
}

impl Opened {
    /// When the first bytes are all whitespace, so that they do not say
    /// what the input is, reads on to the first byte that is not: `start`
    /// then begins there. Of the whitespace only its newlines are kept, as
    /// a count, and given back by [`Opened::read_all`] and
    /// [`Opened::into_reader`] before `start`: the text formats' words,
    /// word numbers and lines are the same. Bounded by the input's limit.
    /// (`yes ' ' | pat-info -` was read whole, to 256 MiB, because its
    /// first 4096 bytes could not tell a pattern from a modulation map.)
    pub fn past_blank_start(mut self) -> Result<Opened, IoError> {
        let mut skipped = 0u64;
        let mut step = || -> io::Result<()> {
            // Whether the skipped bytes end in a CR.
            let mut cr = false;
            while !self.start.is_empty() && self.start.iter().all(u8::is_ascii_whitespace) {
                let ends = crate::text::line_ends(&self.start, cr);
                self.blank_lines += ends as u64;
                cr = self.start.last() == Some(&b'\r');
                skipped += self.start.len() as u64;
                if skipped > self.limit {
                    return Err(too_large(self.limit, self.limit_says));
                }
                self.start.clear();
                (&mut self.rest)
                    .take(SNIFF_BYTES as u64)
                    .read_to_end(&mut self.start)?;
            }
            if cr && self.start.first() == Some(&b'\n') {
                // A CR LF split between the skipped bytes and `start`: one
                // line end, which the reader counts at the LF.
                self.blank_lines -= 1;
            }
            Ok(())
        };
        match step() {
            Ok(()) => Ok(self),
            Err(error) => Err(IoError::Read {
                input: self.input,
                error,
            }),
        }
    }

    /// The whole input, refused past its limit.
    pub fn read_all(self) -> io::Result<Vec<u8>> {
        if self.known_len.is_some_and(|n| n > self.limit) {
            return Err(too_large(self.limit, self.limit_says));
        }
        let mut bytes = vec![b'\n'; self.blank_lines as usize];
        bytes.extend_from_slice(&self.start);
        let expected = self.known_len.unwrap_or(0) as usize;
        bytes.reserve(expected.saturating_sub(bytes.len()));
        // Bounded even if the file grows while it is read.
        let rest = self.limit.saturating_sub(bytes.len() as u64);
        let mut rest = self.rest.take(rest.saturating_add(1));
        let mut at_end = false;
        if self.known_len.is_none() && bytes.starts_with(PNG_SIGNATURE) {
            // A PNG from a pipe is read to its end (IEND, or the first
            // chunk that is not one: `png_end`) and no further: a 64x64
            // PNG followed by endless zeros took 2 GiB before the limit
            // refused it (a hostile-input review). A file's size is known,
            // and what follows is read and ignored, as here.
            let mut at = PNG_SIGNATURE.len();
            loop {
                if let Some(end) = png_end(&bytes, &mut at) {
                    bytes.truncate(end);
                    at_end = true;
                    break;
                }
                let read = (&mut rest).take(1 << 16).read_to_end(&mut bytes)?;
                if read == 0 {
                    break;
                }
            }
        }
        if !at_end {
            rest.read_to_end(&mut bytes)?;
        }
        if bytes.len() as u64 > self.limit {
            return Err(too_large(self.limit, self.limit_says));
        }
        Ok(bytes)
    }

    /// [`Opened::read_all`] with [`read_input`]'s errors, which carry the name.
    pub fn read_input(self) -> Result<Vec<u8>, IoError> {
        let input = self.input.clone();
        self.read_all()
            .map_err(|error| IoError::Read { input, error })
    }

    /// The whole input from its first byte as a reader, unbounded: for a
    /// reader that bounds what it reads ([`crate::Pattern::read_from`]).
    pub fn into_reader(self) -> impl Read {
        io::repeat(b'\n')
            .take(self.blank_lines)
            .chain(io::Cursor::new(self.start))
            .chain(self.rest)
    }
}

/// The offset just past a PNG's `IEND` chunk, once `bytes` reach it, or
/// of the first chunk head that is not one (a type not four ASCII
/// letters, or a length past 2^31 - 1: PNG 1.2, section 5.3): what follows
/// that is not PNG, and a PNG cut before its `IEND` and followed by zeros
/// (or any other bytes) was read to the 2 GiB limit from a pipe (a
/// hostile-input review; the decoder reads no further than it does from a
/// file). `at`, the offset of the next chunk to look at, is kept across
/// calls as more bytes come (a chunk is its length, type, data and CRC: 12
/// bytes and its data).
fn png_end(bytes: &[u8], at: &mut usize) -> Option<usize> {
    const MAX_CHUNK_LEN: usize = (1 << 31) - 1;
    while let Some((kind, len)) = png_chunk_head(bytes, *at) {
        if len > MAX_CHUNK_LEN || !kind.iter().all(u8::is_ascii_alphabetic) {
            return Some(*at);
        }
        let end = at.saturating_add(12).saturating_add(len);
        if kind == b"IEND" {
            return (bytes.len() >= end).then_some(end);
        }
        *at = end;
    }
    None
}

/// The type and data length of the PNG chunk at offset `at`, once its
/// 8-byte head (length, type) lies within `bytes`: what [`png_end`] and
/// [`png_header_chunks`] walk by.
fn png_chunk_head(bytes: &[u8], at: usize) -> Option<(&[u8], usize)> {
    let head = bytes.get(at..at.checked_add(8)?)?;
    let len = u32::from_be_bytes([head[0], head[1], head[2], head[3]]) as usize;
    Some((&head[4..8], len))
}

/// The error of an input past its `limit` (`says`: whose limit it is).
fn too_large(limit: u64, says: &str) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("is larger than the {limit} bytes {says}"),
    )
}

/// The first `SNIFF_BYTES` of `r` (fewer if it ends sooner).
fn read_start(r: &mut impl Read) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    r.take(SNIFF_BYTES as u64).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Opens a file to read by name, with a clear error for a directory.
pub fn open_file(name: &str) -> Result<std::fs::File, IoError> {
    open_named(name).map_err(|error| IoError::Read {
        input: name.to_string(),
        error,
    })
}

/// Opens the file an input names (FIFOs and `<(...)` included), with
/// clear errors for an empty name and a directory: what [`open_file`] and
/// [`open_input`] open.
fn open_named(name: &str) -> io::Result<std::fs::File> {
    if name.is_empty() {
        Err(empty_input_name())
    } else if Path::new(name).is_dir() {
        Err(is_a_directory())
    } else {
        std::fs::File::open(name)
    }
}

/// The error for an input named by the empty string (`pat-tile ''`): the
/// operating system's "No such file or directory" named nothing, the name
/// being empty.
fn empty_input_name() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "expected a file name, or - for standard input",
    )
}

/// The error for a directory named as an input file.
fn is_a_directory() -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, "is a directory, not a file")
}

/// The most bytes an image file read from the command line may have: a
/// picture of [`MAX_IMAGE_PIXELS`] at 16 bits a channel, RGBA, uncompressed
/// (PAM), is 2 GiB.
pub const MAX_PICTURE_FILE_BYTES: u64 = MAX_IMAGE_PIXELS * 8 + (1 << 16);

/// The most bytes a PFM read from the command line may have: a picture of
/// [`MAX_IMAGE_PIXELS`] in three f32 a pixel (3 GiB), and its header.
pub const MAX_PFM_FILE_BYTES: u64 = MAX_IMAGE_PIXELS * 12 + (1 << 16);

/// Bytes of an input read before its start is checked ([`InputKind`]).
const SNIFF_BYTES: usize = 4096;

/// What an input read from the command line must start as, which bounds how
/// much of it is read: `pat-info /dev/zero` is refused after its first
/// bytes, not after reading gigabytes (issue 17, item 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// A text format of bounded size (`.pat`, modulation map, palette): no
    /// NUL byte in its first 4096 bytes (`SNIFF_BYTES`), at most
    /// [`MAX_NAMED_FILE_BYTES`].
    Text,
    /// A polygon stream: text, of any size.
    Stream,
    /// A camera file (`--camera`): text, at most [`MAX_CAMERA_BYTES`].
    Camera,
    /// An image file the `image` crate recognises from its first bytes, at
    /// most [`MAX_PICTURE_FILE_BYTES`].
    Image,
    /// A pattern as `.pat` text or as an image (a background pattern).
    TextOrImage,
    /// An image as [`InputKind::Image`], or a PFM (`PF` or `Pf`), at most
    /// [`MAX_PFM_FILE_BYTES`]: an image to measure (`--compare`, `--image`).
    ImageOrPfm,
}

impl InputKind {
    /// Checks the first bytes; returns the size limit of what follows.
    fn check_start(self, start: &[u8]) -> io::Result<u64> {
        let text = || match start.iter().position(|&b| b == 0) {
            None => Ok(()),
            Some(at) => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "byte 0x00 on line {} (offset {at}) is not text (a text format is expected)",
                    1 + crate::text::line_ends(&start[..at], false)
                ),
            )),
        };
        let image = || image::guess_format(start).is_ok();
        if start.is_empty() && matches!(self, InputKind::Image | InputKind::ImageOrPfm) {
            // Said as such: "it does not start as PNG, ..." left the user to
            // find out that it does not start at all (a hostile-input review).
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "empty file: not an image",
            ));
        }
        match self {
            InputKind::Text => text().map(|()| MAX_NAMED_FILE_BYTES),
            InputKind::Stream => text().map(|()| u64::MAX),
            InputKind::Camera => text().map(|()| MAX_CAMERA_BYTES),
            InputKind::Image if image() => Ok(MAX_PICTURE_FILE_BYTES),
            InputKind::Image => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "not an image this tool can read (it does not start as PNG, JPEG, GIF, BMP, \
                 TIFF, WebP or PNM)",
            )),
            InputKind::ImageOrPfm if is_pfm(start) => Ok(MAX_PFM_FILE_BYTES),
            InputKind::ImageOrPfm if image() => Ok(MAX_PICTURE_FILE_BYTES),
            InputKind::ImageOrPfm => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "not an image this tool can read (it does not start as PNG, JPEG, GIF, BMP, \
                 TIFF, WebP, PNM or PFM)",
            )),
            InputKind::TextOrImage if image() => Ok(MAX_PICTURE_FILE_BYTES),
            InputKind::TextOrImage => text().map(|()| MAX_NAMED_FILE_BYTES),
        }
    }
}

/// Reads a file by name, or standard input for `-`, as `kind`: its first
/// bytes are checked before the rest is read, and no more than the kind's
/// limit is read. Errors carry the name.
pub fn read_input(name: &str, kind: InputKind) -> Result<Vec<u8>, IoError> {
    open_input(name, kind)?.read_input()
}

/// Opens a file by name, or standard input for `-`, and checks its first
/// bytes as `kind`: [`read_input`] but for the rest, which the caller reads
/// whole or as a stream (a `.pat` larger than the kind's limit).
pub fn open_input(name: &str, kind: InputKind) -> Result<Opened, IoError> {
    let open = || {
        let mut known_len = None;
        let mut r: Box<dyn Read> = if name == STDIO {
            Box::new(io::stdin().lock())
        } else {
            let f = open_named(name)?;
            // A file's length refuses one past the limit before it is read:
            // a 3 GB picture was read into 2 GB of memory first (a
            // hostile-input review). Pipes and devices have none.
            known_len = f
                .metadata()
                .ok()
                .filter(|m| m.file_type().is_file())
                .map(|m| m.len());
            Box::new(f)
        };
        let start = read_start(&mut r)?;
        let limit = kind.check_start(&start)?;
        Ok(Opened {
            start,
            rest: r,
            limit,
            limit_says: "this input may have",
            known_len,
            input: name.to_string(),
            blank_lines: 0,
        })
    };
    open().map_err(|error| IoError::Read {
        input: name.to_string(),
        error,
    })
}

/// The name to show in errors for an input argument.
pub fn display_name(name: &str) -> &str {
    if name == STDIO {
        STDIN_NAME
    } else {
        name
    }
}

/// The temporary files of outputs being written, which a signal handler
/// must remove: a process that is killed runs no destructors, and a batch
/// scheduler pre-empts with SIGTERM ([`remove_unfinished_outputs`]).
static UNFINISHED: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes the temporary file of every output not yet committed, so that a
/// run stopped by a signal leaves nothing behind; for a signal handler to
/// call just before the process ends. Returns how many were removed.
pub fn remove_unfinished_outputs() -> usize {
    // A poisoned lock still holds the list: removing the files matters more.
    let list = UNFINISHED.lock().unwrap_or_else(|p| p.into_inner());
    list.iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// [`remove_unfinished_outputs`] for a caller that must neither block nor
/// allocate (an allocation failure, where the failing thread may hold the
/// list's lock): skips the removal if the lock is taken. `remove_file`
/// converts paths shorter than a few hundred bytes on the stack.
pub fn remove_unfinished_outputs_now() -> usize {
    let list = match UNFINISHED.try_lock() {
        Ok(list) => list,
        Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner(),
        Err(std::sync::TryLockError::WouldBlock) => return 0,
    };
    list.iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// Notes or forgets an unfinished output's temporary file.
fn unfinished(path: &Path, pending: bool) {
    let mut list = UNFINISHED.lock().unwrap_or_else(|p| p.into_inner());
    if pending {
        list.push(path.to_path_buf());
    } else if let Some(i) = list.iter().position(|p| p == path) {
        list.swap_remove(i);
    }
}

/// An output that is either standard output or a file that appears under its
/// final name only when [`Output::commit`] succeeds: a failed run leaves nothing
/// behind, so `make` never takes a half-written target as up to date.
pub struct Output {
    inner: OutputInner,
    /// The kind of the first write error seen: encoders (PNG's) may hand a
    /// failed write back as an error of another kind, and a closed pipe
    /// (`| head`) must still read as one.
    failed: Option<io::ErrorKind>,
}

enum OutputInner {
    Stdout(BufWriter<io::Stdout>),
    /// A device or pipe named with `-o`, written in place; its name as
    /// given, for the error of the last flush.
    Device {
        w: BufWriter<std::fs::File>,
        name: String,
    },
    File {
        tmp: BufWriter<tempfile::NamedTempFile>,
        path: PathBuf,
        /// Bytes handed to `tmp` so far, and the end of the range already
        /// sent to the disk (see [`WRITE_BEHIND_BYTES`]).
        written: u64,
        started: u64,
    },
}

/// A file output asks the kernel to start writing its pages to the disk
/// every this many bytes (Linux's `sync_file_range`, without waiting),
/// rather than leaving all of them to the rename in [`Output::commit`]:
/// ext4 writes a new file's delayed blocks out when it replaces an existing
/// one, and the 84 MB `.pat` of a 1024x1024 pattern of 256 colours spent
/// 20-45 ms there. Paired runs (median of 7) of the 1024x1024 images of
/// `bench/pat_from_image_large.sh` at K = 256: gradient 0.082 s against
/// 0.098, netscape 0.093 against 0.106, logo 0.125 against 0.140; a step of
/// 1 MiB did as well, 16 MiB less (gradient 0.092 s), 64 MiB (once) as
/// badly as none. Only when the pages start for the disk changes, not what
/// the file holds or how it replaces the old one; outputs smaller than this
/// are untouched.
const WRITE_BEHIND_BYTES: u64 = 4 << 20;

/// Past this many bytes a file output's pages are left to the usual
/// writeback again: a 1.3 GB `.pat` (4096x4096, 256 colours) written behind
/// from start to end took 0.3 s longer in its writes (`strace -c`: 1.59 s
/// against 1.26) than the 0.06 s it saved at the rename; with this limit the
/// whole run took 4.45 s against 4.99 for the build before write-behind
/// (paired, median of 5).
const WRITE_BEHIND_LIMIT: u64 = 256 << 20;

/// Starts the disk writes of `tmp`'s bytes `*started..end`.
#[cfg(all(target_os = "linux", feature = "cli"))]
fn write_behind(tmp: &tempfile::NamedTempFile, started: &mut u64, end: u64) {
    use std::os::fd::AsRawFd;
    // SAFETY: a plain system call on an open descriptor; a failure (a
    // filesystem without it) only leaves the pages to the usual writeback.
    unsafe {
        libc::sync_file_range(
            tmp.as_file().as_raw_fd(),
            *started as libc::off64_t,
            (end - *started) as libc::off64_t,
            libc::SYNC_FILE_RANGE_WRITE,
        )
    };
    *started = end;
}

/// The process's own descriptor that `path` names, duplicated: `/dev/stdout`,
/// `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N` and links to them. Each
/// link of the chain is followed by hand (at most `MAX_LINKS`, the kernel's
/// `MAXSYMLINKS`), and a name is a descriptor when its directory is this
/// process's (or thread's) `fd` directory: following the last link would
/// give the file the descriptor has open, not the descriptor.
#[cfg(target_os = "linux")]
fn open_descriptor(path: &Path) -> Option<io::Result<std::fs::File>> {
    const MAX_LINKS: usize = 40;
    let pid = std::process::id();
    let own_fd_dir = |dir: &Path| {
        let parts: Vec<_> = dir.iter().filter_map(|c| c.to_str()).collect();
        match parts[..] {
            ["/", "proc", p, "fd"] => p == pid.to_string(),
            ["/", "proc", p, "task", _, "fd"] => p == pid.to_string(),
            _ => false,
        }
    };
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if std::fs::canonicalize(dir).is_ok_and(|d| own_fd_dir(&d)) {
            let fd: i32 = p.file_name()?.to_str()?.parse().ok()?;
            // SAFETY: the name exists in this process's fd directory, so the
            // descriptor is open; it is only borrowed to be duplicated.
            let borrowed = unsafe { std::os::fd::BorrowedFd::borrow_raw(fd) };
            return Some(borrowed.try_clone_to_owned().map(std::fs::File::from));
        }
        let target = std::fs::read_link(&p).ok()?;
        p = dir.join(target);
    }
    None
}

/// Where the chain of links from `path` ends, without requiring that the end
/// exist (what [`std::fs::canonicalize`] refuses): a dangling link's target.
/// A chain longer than the kernel's 40 links is an error, as it is to `open`.
fn link_target(path: &Path) -> io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            Ok(target) => {
                let dir = p.parent().map(Path::to_path_buf).unwrap_or_default();
                p = dir.join(target);
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(p),
            // Not a link (EINVAL): the end of the chain.
            Err(_) if std::fs::symlink_metadata(&p).is_ok() => return Ok(p),
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

#[cfg(not(target_os = "linux"))]
fn open_descriptor(_: &Path) -> Option<io::Result<std::fs::File>> {
    None
}

#[cfg(not(all(target_os = "linux", feature = "cli")))]
fn write_behind(_: &tempfile::NamedTempFile, started: &mut u64, end: u64) {
    *started = end;
}

/// The file a written output named `path` replaces: `path`, or where its
/// chain of links ends. The file a link points to is replaced, not the
/// link, and a link to a file not made yet makes it there, as `>` does.
pub fn output_target(path: &Path) -> io::Result<PathBuf> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        return std::fs::canonicalize(path).or_else(|e| match e.kind() {
            io::ErrorKind::NotFound => link_target(path),
            _ => Err(e),
        });
    }
    Ok(path.to_path_buf())
}

impl Output {
    /// Opens `name` (`-` for standard output). `binary` output is refused on a terminal.
    pub fn create(name: &str, binary: bool) -> Result<Output, IoError> {
        if name == STDIO {
            let stdout = io::stdout();
            if binary && stdout.is_terminal() {
                return Err(IoError::BinaryToTerminal);
            }
            return Ok(Output {
                inner: OutputInner::Stdout(BufWriter::with_capacity(1 << 16, stdout)),
                failed: None,
            });
        }
        if name.is_empty() {
            // Refused before any work: `-o ''` failed only at the rename.
            return Err(IoError::EmptyOutputName);
        }
        let mut path = PathBuf::from(name);
        // A name the file system cannot hold (a component over NAME_MAX,
        // as `-o f%0255d.png` makes with its prefix and suffix) is refused
        // now: the temporary file's own short name was made, and only the
        // rename at the end of the work failed.
        if let Err(e) = std::fs::symlink_metadata(&path) {
            if e.kind() == io::ErrorKind::InvalidFilename {
                return Err(write_error(name, WriteStep::Open)(e));
            }
        }
        if path.is_dir() {
            return Err(IoError::OutputIsDirectory {
                output: name.to_string(),
            });
        }
        if let Some(f) = open_descriptor(&path) {
            // `-o /dev/stdout` with standard output appending to a file
            // (`>> log`): opening the name reaches the file itself, and the
            // rename then replaced it, losing what it held (a hostile-input
            // review). Written through the descriptor, as `-` is.
            return Output::device(f.map_err(write_error(name, WriteStep::Open))?, name, binary);
        }
        if let Ok(meta) = std::fs::metadata(&path) {
            if !meta.file_type().is_file() {
                // A device, FIFO or socket (`-o /dev/null`, `-o /dev/stdout`, a
                // named pipe): there is no file to replace atomically, and a
                // rename would replace the device node itself. Write straight to it.
                let f = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&path)
                    .map_err(write_error(name, WriteStep::Open))?;
                return Output::device(f, name, binary);
            }
        }
        path = output_target(&path).map_err(write_error(name, WriteStep::ResolveLink))?;
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let mut builder = tempfile::Builder::new();
        builder.prefix(".patkit-").suffix(".tmp");
        // An ordinary file's mode (0666 less the umask), not the private 0600 a
        // temporary file gets by default: the rename makes it the real output.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let tmp = builder
            .tempfile_in(&dir)
            .map_err(without_temp_name)
            .map_err(write_error(name, WriteStep::CreateIn(dir.clone())))?;
        unfinished(tmp.path(), true);
        // A file replaced keeps its permission bits: a private (0600) output
        // became readable by others (0644) when the rename put a new file in
        // its place. Set with fchmod, which the umask does not touch.
        #[cfg(unix)]
        if let Ok(old) = std::fs::metadata(&path) {
            use std::os::unix::fs::PermissionsExt;
            let mode = old.permissions().mode() & 0o777;
            tmp.as_file()
                .set_permissions(std::fs::Permissions::from_mode(mode))
                .map_err(write_error(name, WriteStep::CreateIn(dir.clone())))?;
        }
        Ok(Output {
            inner: OutputInner::File {
                tmp: BufWriter::with_capacity(1 << 16, tmp),
                path,
                written: 0,
                started: 0,
            },
            failed: None,
        })
    }

    /// Output written straight to `f`, a device, pipe or descriptor named
    /// `name`: `binary` output to a terminal (`-o /dev/stdout` or `-o
    /// /dev/tty` on one) is refused as `-` is, or the picture's bytes would
    /// garble the screen.
    fn device(f: std::fs::File, name: &str, binary: bool) -> Result<Output, IoError> {
        if binary && f.is_terminal() {
            return Err(IoError::BinaryToTerminal);
        }
        Ok(Output {
            inner: OutputInner::Device {
                w: BufWriter::with_capacity(1 << 16, f),
                name: name.to_string(),
            },
            failed: None,
        })
    }

    /// Flushes and, for a file, moves it to its final name.
    pub fn commit(self) -> Result<(), IoError> {
        match self.inner {
            OutputInner::Stdout(mut w) => w.flush().map_err(write_error(STDIO, WriteStep::Write)),
            // Named: a small output (`-o /dev/full`) fails only here.
            OutputInner::Device { mut w, name } => {
                w.flush().map_err(write_error(name, WriteStep::Write))
            }
            OutputInner::File { tmp, path, .. } => {
                let shown = path.display().to_string();
                let tmp_path = tmp.get_ref().path().to_path_buf();
                let tmp = tmp
                    .into_inner()
                    .map_err(|e| without_temp_name(e.into_error()))
                    .map_err(write_error(shown.clone(), WriteStep::Write))?;
                // On the disk before it takes the name: renamed first, a
                // power loss could leave the name on a file of zeros or of
                // nothing (ext4 flushes a file that replaces another at the
                // rename, but not a new one), which `make` then takes for
                // an output made.
                // A filesystem that cannot sync (EINVAL, EOPNOTSUPP: some
                // FUSE and special ones) is no error: the output is as safe
                // there as it can be made; a failed sync (EIO) is one.
                match tmp.as_file().sync_data() {
                    Err(e)
                        if matches!(
                            e.kind(),
                            io::ErrorKind::InvalidInput | io::ErrorKind::Unsupported
                        ) => {}
                    synced => synced.map_err(write_error(shown.clone(), WriteStep::Write))?,
                }
                let persisted = tmp.persist(&path);
                unfinished(&tmp_path, false);
                persisted
                    .map_err(|e| e.error)
                    .map_err(write_error(shown, WriteStep::Rename))?;
                Ok(())
            }
        }
    }
}

impl Output {
    /// `result`, noting the kind of its error.
    fn noted<T>(&mut self, result: io::Result<T>) -> io::Result<T> {
        if let Err(e) = &result {
            self.failed.get_or_insert(e.kind());
        }
        result
    }

    /// An encoder's error, given the kind of the write error that caused
    /// it, if a write failed: a closed pipe reads as `BrokenPipe` however the
    /// encoder words it.
    pub fn cause(&self, e: io::Error) -> io::Error {
        match self.failed {
            Some(kind) if kind != e.kind() => io::Error::new(kind, e),
            _ => e,
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let result = match &mut self.inner {
            OutputInner::Stdout(w) => w.write(buf),
            OutputInner::Device { w, .. } => w.write(buf),
            OutputInner::File {
                tmp,
                written,
                started,
                ..
            } => tmp.write(buf).map_err(without_temp_name).inspect(|&n| {
                *written += n as u64;
                file_written(tmp, *written, started);
            }),
        };
        self.noted(result)
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        let result = match &mut self.inner {
            OutputInner::Stdout(w) => w.write_all(buf),
            OutputInner::Device { w, .. } => w.write_all(buf),
            OutputInner::File {
                tmp,
                written,
                started,
                ..
            } => tmp.write_all(buf).map_err(without_temp_name).inspect(|_| {
                *written += buf.len() as u64;
                file_written(tmp, *written, started);
            }),
        };
        self.noted(result)
    }
    fn flush(&mut self) -> io::Result<()> {
        let result = match &mut self.inner {
            OutputInner::Stdout(w) => w.flush(),
            OutputInner::Device { w, .. } => w.flush(),
            OutputInner::File { tmp, .. } => tmp.flush().map_err(without_temp_name),
        };
        self.noted(result)
    }
}

/// After a write to a file output: once [`WRITE_BEHIND_BYTES`] more have
/// reached the file (not counting what `tmp` still buffers), start their
/// disk writes.
fn file_written(tmp: &BufWriter<tempfile::NamedTempFile>, written: u64, started: &mut u64) {
    let in_file = (written - tmp.buffer().len() as u64).min(WRITE_BEHIND_LIMIT);
    if in_file - *started >= WRITE_BEHIND_BYTES {
        write_behind(tmp.get_ref(), started, in_file);
    }
}

fn display_out(name: &str) -> &str {
    if name == STDIO {
        "standard output"
    } else {
        name
    }
}

/// The image formats every tool writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ImageFormat {
    /// PNG, lossless, with alpha when the image has transparency.
    Png,
    /// Binary PPM (P6); transparency is flattened.
    Ppm,
    /// PAM (P7), RGB or RGB_ALPHA.
    Pam,
    /// PFM (Portable Float Map, `PF`): RGB in linear light, 32-bit floats,
    /// little-endian, rows bottom to top; no alpha.
    Pfm,
}

impl ImageFormat {
    /// The format named by `--format`, else by the output's extension, else PNG.
    pub fn choose(explicit: Option<ImageFormat>, output: &str) -> Result<ImageFormat, OptionError> {
        ImageFormat::choose_in(explicit, output, true)
    }

    /// [`ImageFormat::choose`] for an image of 8-bit colours (a tiled
    /// pattern, a difference image): `.pfm` is refused, and errors list the
    /// 8-bit formats only.
    pub fn choose_8bit(
        explicit: Option<ImageFormat>,
        output: &str,
    ) -> Result<ImageFormat, OptionError> {
        ImageFormat::choose_in(explicit, output, false)
    }

    fn choose_in(
        explicit: Option<ImageFormat>,
        output: &str,
        float: bool,
    ) -> Result<ImageFormat, OptionError> {
        let expected = if float {
            ".png, .ppm, .pam or .pfm"
        } else {
            ".png, .ppm or .pam"
        };
        if let Some(f) = explicit {
            return Ok(f);
        }
        if output == STDIO {
            return Ok(ImageFormat::Png);
        }
        let ext = Path::new(output)
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            // `.pnm` is netpbm's name for any of its three formats: the
            // colour one is written, as netpbm's tools write PPM for colour.
            Some("ppm") | Some("pnm") => Ok(ImageFormat::Ppm),
            Some("pam") => Ok(ImageFormat::Pam),
            Some("pfm") if float => Ok(ImageFormat::Pfm),
            Some("pfm") => Err(OptionError::new(
                format!(
                    "{output}: `.pfm` stores a rendered frame's linear light, and this image has \
                     8-bit colours: expected {expected}, or give "
                ),
                "format",
                "",
            )),
            // Grey and bilevel: the tools write colour, and a silent
            // conversion would lose it.
            Some(grey @ ("pgm" | "pbm")) => Err(OptionError::new(
                format!(
                    "{output}: `.{grey}` is netpbm's {} format and the image is in colour: \
                     write .ppm (or .pnm) and convert with {}, or give ",
                    if grey == "pgm" {
                        "greyscale"
                    } else {
                        "black-and-white"
                    },
                    if grey == "pgm" {
                        "ppmtopgm"
                    } else {
                        "ppmtopgm | pamditherbw"
                    },
                ),
                "format",
                "",
            )),
            Some(other) => Err(OptionError::new(
                format!(
                    "{output}: unknown image extension `.{other}`: expected {expected}, or give "
                ),
                "format",
                "",
            )),
            // `/dev/null`, `out`: PNG, as on standard output.
            None => Ok(ImageFormat::Png),
        }
    }

    /// Whether the format stores an alpha channel: PNG and PAM do, PPM and
    /// PFM do not.
    pub fn supports_alpha(self) -> bool {
        !matches!(self, ImageFormat::Ppm | ImageFormat::Pfm)
    }

    /// What an image in this format at `depth` stores: PFM is linear float
    /// whatever the depth, the others sRGB codes of `depth` bits.
    pub fn encoding(self, depth: Depth) -> Encoding {
        match (self, depth) {
            (ImageFormat::Pfm, _) => Encoding::LinearF32,
            (_, Depth::Eight) => Encoding::Srgb8,
            (_, Depth::Sixteen) => Encoding::Srgb16,
        }
    }
}

/// Bits per channel of the sRGB formats (PNG, PPM, PAM): `--depth`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Depth {
    /// 8 bits, codes 0..=255.
    #[default]
    #[cfg_attr(feature = "cli", value(name = "8"))]
    Eight,
    /// 16 bits, codes 0..=65535 (PNG bit depth 16, netpbm MAXVAL 65535).
    #[cfg_attr(feature = "cli", value(name = "16"))]
    Sixteen,
}

/// How an image's samples stand for light: what [`AnyImage`] holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// 8-bit sRGB codes ([`Image`]).
    Srgb8,
    /// 16-bit sRGB codes ([`Image16`]).
    Srgb16,
    /// Linear light in f32 ([`LinearImage`]).
    LinearF32,
}

impl Encoding {
    /// How reports name it: `8-bit sRGB`, `16-bit sRGB`, `linear float`.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Srgb8 => "8-bit sRGB",
            Encoding::Srgb16 => "16-bit sRGB",
            Encoding::LinearF32 => "linear float",
        }
    }
}

/// How PNG output trades time against size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PngOptions {
    /// The zlib (deflate) level. Default value: zlib's default level.
    pub compression: image::codecs::png::CompressionType,
    /// The PNG row filter applied before deflate. Default value: adaptive
    /// (chosen per row).
    pub filter: image::codecs::png::FilterType,
}

impl Default for PngOptions {
    /// [`PngOptions::GENERAL`].
    fn default() -> Self {
        PngOptions::GENERAL
    }
}

impl PngOptions {
    /// Any image: zlib's default level with per-row adaptive filtering.
    pub const GENERAL: PngOptions = PngOptions {
        compression: image::codecs::png::CompressionType::Default,
        filter: image::codecs::png::FilterType::Adaptive,
    };
    /// Images of flat colour that repeat along each row (tiled patterns):
    /// unfiltered rows let deflate match whole pattern periods. Measured on a
    /// 64x64 pattern tiled to 4096x4096: 0.17 s and 0.23 MiB, against 0.25 s
    /// and 0.40 MiB with GENERAL and 0.10 s but 6.3 MiB with the fast level.
    pub const FLAT_REPEATING: PngOptions = PngOptions {
        compression: image::codecs::png::CompressionType::Default,
        filter: image::codecs::png::FilterType::NoFilter,
    };
}

/// An 8-bit sRGB image, row 0 at the top, 3 or 4 channels interleaved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 3 (RGB) or 4 (RGBA, straight alpha).
    pub channels: u8,
    /// `width * height * channels` bytes: rows top to bottom, pixels left to
    /// right, channels interleaved, sRGB-encoded.
    pub data: Vec<u8>,
}

impl Image {
    /// Checks a requested size against [`MAX_IMAGE_SIDE`] and [`MAX_IMAGE_PIXELS`].
    pub fn check_size(width: u32, height: u32) -> Result<(), SizeError> {
        if width == 0 || height == 0 {
            return Err(SizeError::Empty(width, height));
        }
        if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
            return Err(SizeError::SideTooLarge(width, height));
        }
        if width as u64 * height as u64 > MAX_IMAGE_PIXELS {
            return Err(SizeError::TooManyPixels(width, height));
        }
        Ok(())
    }

    /// Encodes the image in `format`. PPM drops alpha (callers flatten first).
    /// An encoder's own complaint comes back as an [`io::Error`] that wraps it.
    pub fn encode<W: Write>(&self, format: ImageFormat, w: &mut W) -> io::Result<()> {
        self.encode_with(format, PngOptions::GENERAL, w)
    }

    /// [`Image::encode`] with a choice of PNG settings.
    pub fn encode_with<W: Write>(
        &self,
        format: ImageFormat,
        png: PngOptions,
        w: &mut W,
    ) -> io::Result<()> {
        match format {
            // One IDAT chunk of the whole deflate stream, as this image's
            // PNG has always been (rows streamed end it differently,
            // [`PNG_STREAM_CHUNK_BYTES`]).
            ImageFormat::Png => write_png(
                w,
                (self.width, self.height, self.channels),
                png::BitDepth::Eight,
                &self.data,
                png,
            ),
            // PPM, PAM and PFM's refusal: the rows' encoder, the same bytes.
            _ => encode_rows(&mut &*self, format, png, w),
        }
    }

    /// Writes the image to `name` (`-` = standard output) atomically.
    pub fn save(&self, name: &str, format: ImageFormat) -> Result<(), IoError> {
        self.save_with(name, format, PngOptions::GENERAL)
    }

    /// [`Image::save`] with a choice of PNG settings.
    pub fn save_with(
        &self,
        name: &str,
        format: ImageFormat,
        png: PngOptions,
    ) -> Result<(), IoError> {
        save_encoded(name, |out| self.encode_with(format, png, out))
    }
}

/// The `png` crate's settings for `options`, as the `image` crate's
/// `PngEncoder::new_with_quality` sets them (so PNG bytes are what they were
/// before the sRGB chunk, apart from that chunk).
fn png_settings(options: PngOptions) -> (png::Compression, png::Filter) {
    use image::codecs::png::{CompressionType as C, FilterType as F};
    let compression = match options.compression {
        C::Best => png::Compression::High,
        C::Fast => png::Compression::Fast,
        C::Uncompressed | C::Level(0) => png::Compression::NoCompression,
        // `Level(n)` is not used by the tools; image maps it to a level too.
        C::Default | C::Level(_) => png::Compression::Balanced,
        _ => png::Compression::Balanced,
    };
    let filter = match options.filter {
        F::NoFilter => png::Filter::NoFilter,
        F::Sub => png::Filter::Sub,
        F::Up => png::Filter::Up,
        F::Avg => png::Filter::Avg,
        F::Paeth => png::Filter::Paeth,
        _ => png::Filter::Adaptive,
    };
    (compression, filter)
}

/// A PNG encoder for `(width, height, channels)` (3 or 4) at `depth`,
/// marked sRGB: the `sRGB` chunk (rendering intent perceptual; PNG 3rd
/// edition, 11.3.2.5) tells colour-managed viewers what every tool's codes
/// are, instead of leaving them to guess.
fn png_encoder<W: Write>(
    w: W,
    (width, height, channels): (u32, u32, u8),
    depth: png::BitDepth,
    options: PngOptions,
) -> png::Encoder<'static, W> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(if channels == 4 {
        png::ColorType::Rgba
    } else {
        png::ColorType::Rgb
    });
    enc.set_depth(depth);
    let (compression, filter) = png_settings(options);
    enc.set_compression(compression);
    enc.set_filter(filter);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    enc
}

/// Writes one PNG of `data` (samples as PNG stores them: 16-bit ones
/// big-endian).
fn write_png<W: Write>(
    w: &mut W,
    size: (u32, u32, u8),
    depth: png::BitDepth,
    data: &[u8],
    options: PngOptions,
) -> io::Result<()> {
    let mut writer = png_encoder(w, size, depth, options)
        .write_header()
        .map_err(png_io_error)?;
    writer.write_image_data(data).map_err(png_io_error)?;
    writer.finish().map_err(png_io_error)
}

/// The error of an image asked to be written in a format that does not
/// store its encoding (a caller's mistake: the tools choose the encoding
/// from the format).
fn wrong_encoding(encoding: Encoding, format: ImageFormat) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "a {} image cannot be written as {format:?}",
            encoding.name()
        ),
    )
}

/// An 8-bit image made a row at a time, top row first, so that it need never
/// be held whole: [`save_rows`] encodes each row as it comes. A tiled
/// pattern at 16384x16384 was a gigabyte of RGBA held only to be encoded
/// (`texture::TileRows`, `bench/memory.sh`).
pub trait RowSource {
    /// Width and height in pixels, and channels per pixel (3 or 4, RGB or
    /// RGBA with straight alpha), as an [`Image`]'s.
    fn shape(&self) -> (u32, u32, u8);
    /// Row `y` (0 at the top): `width * channels` sRGB codes, laid out as a
    /// row of [`Image::data`]. Asked for once each, in order.
    fn row(&mut self, y: u32) -> &[u8];
}

impl RowSource for &Image {
    fn shape(&self) -> (u32, u32, u8) {
        (self.width, self.height, self.channels)
    }
    fn row(&mut self, y: u32) -> &[u8] {
        let n = self.width as usize * self.channels as usize;
        &self.data[y as usize * n..(y as usize + 1) * n]
    }
}

/// The largest IDAT chunk [`encode_rows`] writes, and so the most
/// compressed bytes it holds. Its PNG has the same pixels as the whole
/// image's ([`Image::encode_with`], one IDAT chunk), not the same bytes: the
/// `png` crate's row writer flushes its deflate stream before ending it
/// (test `rows_give_the_pixels_and_netpbm_bytes_of_the_whole_image`).
pub const PNG_STREAM_CHUNK_BYTES: usize = 8 << 20;

/// Encodes the rows of `rows` in `format` (8-bit PNG, PPM or PAM; PPM drops
/// alpha) as they are made, holding one row and, for PNG, at most
/// [`PNG_STREAM_CHUNK_BYTES`] of compressed data at a time.
pub fn encode_rows<W: Write>(
    rows: &mut dyn RowSource,
    format: ImageFormat,
    png: PngOptions,
    w: &mut W,
) -> io::Result<()> {
    encode_rows_in_chunks(rows, format, png, w, PNG_STREAM_CHUNK_BYTES)
}

/// [`encode_rows`] with IDAT chunks of at most `chunk` bytes.
fn encode_rows_in_chunks<W: Write>(
    rows: &mut dyn RowSource,
    format: ImageFormat,
    png: PngOptions,
    w: &mut W,
    chunk: usize,
) -> io::Result<()> {
    let (wd, ht, channels) = rows.shape();
    match format {
        ImageFormat::Ppm => {
            write!(w, "P6\n{wd} {ht}\n255\n")?;
            let mut rgb = Vec::new();
            for y in 0..ht {
                let row = rows.row(y);
                if channels == 3 {
                    w.write_all(row)?;
                } else {
                    rgb.clear();
                    rgb.extend(row.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]));
                    w.write_all(&rgb)?;
                }
            }
        }
        ImageFormat::Pam => {
            write_pam_header(w, (wd, ht), channels, 255)?;
            for y in 0..ht {
                w.write_all(rows.row(y))?;
            }
        }
        ImageFormat::Png => {
            let mut writer = png_encoder(&mut *w, (wd, ht, channels), png::BitDepth::Eight, png)
                .write_header()
                .map_err(png_io_error)?;
            let mut stream = writer
                .stream_writer_with_size(chunk)
                .map_err(png_io_error)?;
            for y in 0..ht {
                stream.write_all(rows.row(y))?;
            }
            stream.finish().map_err(png_io_error)?;
            writer.finish().map_err(png_io_error)?;
        }
        ImageFormat::Pfm => return Err(wrong_encoding(Encoding::Srgb8, format)),
    }
    Ok(())
}

/// Writes the rows of `rows` to `name` (`-` = standard output) atomically,
/// as [`encode_rows`] makes them.
pub fn save_rows(
    rows: &mut dyn RowSource,
    name: &str,
    format: ImageFormat,
    png: PngOptions,
) -> Result<(), IoError> {
    save_encoded(name, |out| encode_rows(rows, format, png, out))
}

/// A 16-bit sRGB image, row 0 at the top, 3 or 4 channels interleaved: what
/// `--depth 16` writes, each code the nearest to the exact sRGB value
/// ([`crate::color::linear_to_srgb16`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image16 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 3 (RGB) or 4 (RGBA, straight alpha).
    pub channels: u8,
    /// `width * height * channels` codes, laid out as [`Image::data`].
    pub data: Vec<u16>,
}

impl Image16 {
    /// Encodes the image as 16-bit PNG, PPM (MAXVAL 65535; alpha dropped)
    /// or PAM (MAXVAL 65535); PFM is refused (it is written from linear
    /// light, [`LinearImage`]). A PNG takes a big-endian copy of the image
    /// ([`Image16::encode_spent`] takes none); PPM and PAM a row at a time.
    pub fn encode_with<W: Write>(
        &self,
        format: ImageFormat,
        png: PngOptions,
        w: &mut W,
    ) -> io::Result<()> {
        match format {
            ImageFormat::Png => {
                let bytes: Vec<u8> = self.data.iter().flat_map(|v| v.to_be_bytes()).collect();
                self.write_png(&bytes, png, w)
            }
            _ => self.encode_netpbm(format, w),
        }
    }

    /// [`Image16::encode_with`] of an image that is spent by it: a PNG's
    /// samples are turned big-endian where they are, so that writing takes
    /// no second image's worth of memory (8192x8192 RGB: 402 MB). The same
    /// bytes (test `a_spent_16_bit_image_encodes_as_a_kept_one`).
    pub fn encode_spent<W: Write>(
        mut self,
        format: ImageFormat,
        png: PngOptions,
        w: &mut W,
    ) -> io::Result<()> {
        match format {
            ImageFormat::Png => {
                for v in &mut self.data {
                    *v = v.to_be();
                }
                self.write_png(bytemuck::cast_slice(&self.data), png, w)
            }
            _ => self.encode_netpbm(format, w),
        }
    }

    /// The PNG of the image whose samples, big-endian, are `bytes`.
    fn write_png<W: Write>(&self, bytes: &[u8], png: PngOptions, w: &mut W) -> io::Result<()> {
        let size = (self.width, self.height, self.channels);
        write_png(w, size, png::BitDepth::Sixteen, bytes, png)
    }

    /// PPM or PAM, a row at a time (PFM refused).
    fn encode_netpbm(&self, format: ImageFormat, w: &mut dyn Write) -> io::Result<()> {
        let (wd, ht) = (self.width, self.height);
        // Every 16-bit format here stores big-endian samples (PNG 11.2.1,
        // netpbm's PPM and PAM with MAXVAL above 255).
        let keep = match format {
            ImageFormat::Ppm => {
                write!(w, "P6\n{wd} {ht}\n65535\n")?;
                3
            }
            ImageFormat::Pam => {
                write_pam_header(w, (wd, ht), self.channels, 65535)?;
                self.channels as usize
            }
            _ => return Err(wrong_encoding(Encoding::Srgb16, format)),
        };
        let c = self.channels as usize;
        let mut row = Vec::with_capacity(wd as usize * keep * 2);
        // (`max(1)`: an image 0 pixels wide has no rows, and no samples.)
        for line in self.data.chunks_exact((wd as usize * c).max(1)) {
            row.clear();
            for pixel in line.chunks_exact(c) {
                row.extend(pixel[..keep].iter().flat_map(|v| v.to_be_bytes()));
            }
            w.write_all(&row)?;
        }
        Ok(())
    }
}

/// An image in linear light, f32, row 0 at the top, RGB: what PFM stores
/// (`-o x.pfm`), the frame's own values unrounded.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 3` values, laid out as [`Image::data`].
    pub data: Vec<f32>,
}

impl LinearImage {
    /// Encodes the image as PFM (`PF`, scale -1.0: little-endian, rows
    /// bottom to top, as Debevec's format has them); other formats are
    /// refused (they store sRGB codes).
    pub fn encode<W: Write>(&self, format: ImageFormat, w: &mut W) -> io::Result<()> {
        if format != ImageFormat::Pfm {
            return Err(wrong_encoding(Encoding::LinearF32, format));
        }
        let (wd, ht) = (self.width as usize, self.height as usize);
        write!(w, "PF\n{wd} {ht}\n-1.0\n")?;
        let mut row = Vec::with_capacity(wd * 12);
        for r in (0..ht).rev() {
            row.clear();
            row.extend(
                self.data[r * wd * 3..(r + 1) * wd * 3]
                    .iter()
                    .flat_map(|v| v.to_le_bytes()),
            );
            w.write_all(&row)?;
        }
        Ok(())
    }
}

/// An image in any encoding the tools write or measure: 8- or 16-bit sRGB,
/// or linear float.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyImage {
    /// 8-bit sRGB.
    Srgb8(Image),
    /// 16-bit sRGB.
    Srgb16(Image16),
    /// Linear light, f32 (PFM).
    Linear(LinearImage),
}

impl AnyImage {
    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        match self {
            AnyImage::Srgb8(i) => (i.width, i.height),
            AnyImage::Srgb16(i) => (i.width, i.height),
            AnyImage::Linear(i) => (i.width, i.height),
        }
    }

    /// What the samples are.
    pub fn encoding(&self) -> Encoding {
        match self {
            AnyImage::Srgb8(_) => Encoding::Srgb8,
            AnyImage::Srgb16(_) => Encoding::Srgb16,
            AnyImage::Linear(_) => Encoding::LinearF32,
        }
    }

    /// Encodes the image in `format`, which must store its encoding
    /// ([`ImageFormat::encoding`]).
    pub fn encode_with<W: Write>(
        &self,
        format: ImageFormat,
        png: PngOptions,
        w: &mut W,
    ) -> io::Result<()> {
        match self {
            AnyImage::Srgb8(i) => i.encode_with(format, png, w),
            AnyImage::Srgb16(i) => i.encode_with(format, png, w),
            AnyImage::Linear(i) => i.encode(format, w),
        }
    }

    /// [`AnyImage::encode_with`] of an image spent by it: a 16-bit one is
    /// turned big-endian in place rather than copied
    /// ([`Image16::encode_spent`]); the same bytes.
    pub fn encode_spent<W: Write>(
        self,
        format: ImageFormat,
        png: PngOptions,
        w: &mut W,
    ) -> io::Result<()> {
        match self {
            AnyImage::Srgb16(i) => i.encode_spent(format, png, w),
            other => other.encode_with(format, png, w),
        }
    }

    /// Writes the image to `name` (`-` = standard output) atomically.
    pub fn save_with(
        &self,
        name: &str,
        format: ImageFormat,
        png: PngOptions,
    ) -> Result<(), IoError> {
        save_encoded(name, |out| self.encode_with(format, png, out))
    }

    /// [`AnyImage::save_with`], spending the image
    /// ([`AnyImage::encode_spent`]).
    pub fn save_spent(
        self,
        name: &str,
        format: ImageFormat,
        png: PngOptions,
    ) -> Result<(), IoError> {
        save_encoded(name, |out| self.encode_spent(format, png, out))
    }
}

/// Writes `name` (`-` = standard output) atomically with `encode`; a
/// failed write names the output.
fn save_encoded(
    name: &str,
    encode: impl FnOnce(&mut Output) -> io::Result<()>,
) -> Result<(), IoError> {
    let mut out = Output::create(name, true)?;
    encode(&mut out).map_err(|e| write_error(name, WriteStep::Write)(out.cause(e)))?;
    out.commit()
}

/// An animated PNG (APNG) written one frame at a time, so an animation never
/// holds more than one frame in memory. Every frame fills the whole canvas
/// (the default `fcTL` region, dispose none, blend source) and the first frame
/// is also the default image, so a viewer without APNG support shows frame 0.
pub struct ApngWriter {
    writer: Option<png::Writer<SharedOutput>>,
    /// The file, shared with `writer`: `png::Writer::finish` consumes the
    /// writer without giving its stream back, and the output must still be
    /// committed (moved into place) after the last chunk.
    out: std::rc::Rc<std::cell::RefCell<Output>>,
    name: String,
    width: u32,
    height: u32,
    channels: u8,
}

impl ApngWriter {
    /// Starts `name` (`-` = standard output) for `frames` frames of
    /// `width` x `height` with `channels` (3 or 4), each shown for 1/`fps`
    /// seconds, looping forever (`num_plays` 0).
    pub fn create(
        name: &str,
        width: u32,
        height: u32,
        channels: u8,
        frames: u32,
        fps: u16,
    ) -> Result<ApngWriter, IoError> {
        let out = std::rc::Rc::new(std::cell::RefCell::new(Output::create(name, true)?));
        let ctx = |e| write_error(name, WriteStep::Write)(png_io_error(e));
        let mut enc = png::Encoder::new(SharedOutput(out.clone()), width, height);
        enc.set_color(if channels == 4 {
            png::ColorType::Rgba
        } else {
            png::ColorType::Rgb
        });
        enc.set_depth(png::BitDepth::Eight);
        // As every PNG the tools write (`png_encoder`).
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        enc.set_animated(frames, 0).map_err(ctx)?;
        enc.set_frame_delay(1, fps).map_err(ctx)?;
        let writer = enc.write_header().map_err(ctx)?;
        Ok(ApngWriter {
            writer: Some(writer),
            out,
            name: name.to_string(),
            width,
            height,
            channels,
        })
    }

    /// Appends the next frame; it must have the size and channels given to
    /// [`ApngWriter::create`].
    pub fn push(&mut self, img: &Image) -> Result<(), IoError> {
        let frame = (img.width, img.height, img.channels);
        let animation = (self.width, self.height, self.channels);
        if frame != animation {
            return Err(IoError::FrameMismatch {
                output: self.name.clone(),
                frame,
                animation,
            });
        }
        let w = self.writer.as_mut().expect("not finished");
        let out = &self.out;
        w.write_image_data(&img.data).map_err(|e| {
            write_error(&*self.name, WriteStep::Write)(out.borrow().cause(png_io_error(e)))
        })
    }

    /// Ends the file (all frames must have been pushed) and moves it into place.
    pub fn finish(mut self) -> Result<(), IoError> {
        let w = self.writer.take().expect("not finished");
        let out = &self.out;
        w.finish().map_err(|e| {
            write_error(&*self.name, WriteStep::Write)(out.borrow().cause(png_io_error(e)))
        })?;
        // `finish` consumed the writer and with it the only other handle.
        let Ok(out) = std::rc::Rc::try_unwrap(self.out) else {
            unreachable!("the PNG writer, the output's only other owner, is gone")
        };
        out.into_inner().commit()
    }
}

/// [`Output`] behind a shared handle, for [`ApngWriter`].
struct SharedOutput(std::rc::Rc<std::cell::RefCell<Output>>);

impl Write for SharedOutput {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.borrow_mut().write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.borrow_mut().flush()
    }
}

/// A picture as a camera meant it: its pixels turned upright, and what
/// decoding found that the pixels do not say.
#[derive(Clone, Debug)]
pub struct Photo {
    /// The pixels, already turned by `orientation`.
    pub image: image::RgbaImage,
    /// The EXIF orientation the file asked for (a phone held sideways writes
    /// its sensor's rows and an orientation tag), applied to `image`.
    pub orientation: image::metadata::Orientation,
    /// Whether the file embeds an ICC colour profile. It is not applied:
    /// the tools take every pixel as sRGB (and the profile is not kept).
    pub has_icc_profile: bool,
    /// The frames of an animated GIF, PNG (APNG) or WebP, or the pages of a
    /// TIFF, when it has more than one: only the first is decoded
    /// ([`animation_frames`]).
    pub frames: Option<u32>,
    /// The gamma a PNG's `gAMA` chunk gives, when it is not sRGB's (and no
    /// `sRGB` or `iCCP` chunk overrides it), found by `png_foreign_gamma`. It is
    /// not applied either; a linear PNG (gamma 1.0) read as sRGB came out
    /// dark without a word (a hostile-input review).
    pub foreign_gamma: Option<f64>,
}

/// The error of a file that is not an image this tool reads.
fn not_an_image(name: &str) -> impl Fn(image::ImageError) -> IoError + '_ {
    move |error| IoError::NotAnImage {
        input: name.to_string(),
        error: plain_chunk_names(error),
    }
}

/// `error` with each PNG chunk named by its type: the `png` crate writes a
/// chunk's debug form into some messages ("CRC error: ... while decoding
/// ChunkType { type: IDAT, critical: true, private: false, reserved:
/// false, safecopy: false } chunk", a hostile-input review).
fn plain_chunk_names(error: image::ImageError) -> image::ImageError {
    use std::error::Error as _;
    const DEBUG_FORM: &str = "ChunkType { type: ";
    let image::ImageError::Decoding(decoding) = &error else {
        return error;
    };
    let Some(mut rest) = decoding.source().map(|s| s.to_string()) else {
        return error;
    };
    if !rest.contains(DEBUG_FORM) {
        return error;
    }
    let mut text = String::new();
    while let Some(at) = rest.find(DEBUG_FORM) {
        let after = &rest[at + DEBUG_FORM.len()..];
        let (Some(comma), Some(close)) = (after.find(','), after.find('}')) else {
            break;
        };
        text.push_str(&rest[..at]);
        text.push_str(&after[..comma.min(close)]);
        rest = after[close + 1..].to_string();
    }
    text.push_str(&rest);
    image::ImageError::Decoding(image::error::DecodingError::new(
        decoding.format_hint(),
        text,
    ))
}

/// Whether a JPEG's data reaches an end-of-image marker (`FF D9`) after its
/// first scan: `Ok`, or the error saying where it does not. The header
/// segments are walked by their lengths (an EXIF thumbnail inside one has
/// markers of its own); within scan data a `FF` is always followed by a
/// stuffed `00` or a restart marker, so the first `FF D9` after the first
/// start-of-scan is the image's end. The `image` crate's decoder fills a
/// truncated scan with grey without a word (the first 1,000 bytes of a
/// photo made a grey pattern, "PSNR inf").
fn check_jpeg(bytes: &[u8], name: &str) -> Result<(), IoError> {
    let malformed = |what: String| {
        Err(IoError::MalformedJpeg {
            input: name.to_string(),
            what,
        })
    };
    let mut at = 2; // after SOI
    while at + 4 <= bytes.len() {
        if bytes[at] != 0xFF {
            return malformed(format!(
                "byte 0x{:02x} at offset {at}, where a marker (FF) belongs",
                bytes[at]
            ));
        }
        match bytes[at + 1] {
            0xFF => at += 1, // fill byte
            0xDA if memchr::memmem::find(&bytes[at..], &[0xFF, 0xD9]).is_some() => return Ok(()),
            0xDA => break,
            0xD9 => return malformed(format!("it ends (FF D9 at offset {at}) before any scan")),
            0x01 | 0xD0..=0xD7 => at += 2, // markers without a length
            marker => {
                let len = u16::from_be_bytes([bytes[at + 2], bytes[at + 3]]) as usize;
                if len < 2 {
                    return malformed(format!(
                        "the segment FF {marker:02X} at offset {at} has length {len} (it counts \
                         its own 2 bytes)"
                    ));
                }
                at += 2 + len;
            }
        }
    }
    Err(IoError::TruncatedJpeg {
        input: name.to_string(),
    })
}

/// A decoder for `bytes`, its format guessed from the content, before any
/// pixel is decoded (so sizes can be checked first). A JPEG cut short is
/// refused here ([`check_jpeg`]), and so is a netpbm picture with a
/// sample over its maxval (`pnm_samples`).
fn open_decoder<'a>(bytes: &'a [u8], name: &str) -> Result<impl image::ImageDecoder + 'a, IoError> {
    if image::guess_format(bytes).ok() == Some(image::ImageFormat::Jpeg) {
        check_jpeg(bytes, name)?;
    }
    if let Some(o) = pnm_samples::first_over_maxval(bytes) {
        return Err(IoError::OverMaxval {
            input: name.to_string(),
            value: o.value,
            maxval: o.maxval,
            x: o.x,
            y: o.y,
        });
    }
    let mut reader = image::ImageReader::new(io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| not_an_image(name)(image::ImageError::IoError(e)))?;
    if reader.format() == Some(image::ImageFormat::Png) {
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(PNG_METADATA_BYTES);
        reader.limits(limits);
    }
    reader.into_decoder().map_err(|e| {
        // The PNG decoder refuses a header past its own memory limit
        // before our size check can read it ("Memory limit exceeded"
        // for 2^31-1 x 2^31-1, a hostile-input review): the header
        // says what the picture is, and our limits say why not.
        let too_large = matches!(e, image::ImageError::Limits(_))
            .then(|| png_size(bytes))
            .flatten()
            .and_then(|(w, h)| Image::check_size(w, h).err());
        match too_large {
            Some(error) => IoError::PictureTooLarge {
                input: name.to_string(),
                error,
            },
            None => not_an_image(name)(e),
        }
    })
}

/// What the PNG decoder may spend on a picture's metadata (its ICC profile,
/// text, EXIF): the decoder inflates a compressed ICC profile while reading
/// the header, and the `image` crate's default allowance (512 MiB) let a
/// 306 KB file with a 300 MB profile take 619 MB for a 64x64 picture (a
/// hostile-input review). Real profiles are kilobytes; the pixels are
/// allowed for separately, once their size is checked ([`decode_pixels`]).
const PNG_METADATA_BYTES: u64 = 64 << 20;

/// What a decoder may allocate besides the picture itself (strips, tiles and
/// tables of a TIFF): the `image` crate's default allowance for the whole.
const DECODE_WORK_BYTES: u64 = 512 << 20;

/// Decodes the picture `decoder` reads, its size already checked against
/// the caller's limit: the decoder may allocate the picture and
/// [`DECODE_WORK_BYTES`] more (under the `image` crate's default 512 MiB
/// for everything, a 12000x12000 RGBA TIFF, within the tools' limits, was
/// refused as "Memory limit exceeded"). Samples that are not finite
/// numbers (a floating-point TIFF's NaN or infinity) are refused: 8-bit
/// conversion made NaN white; and so is an indexed picture's index past
/// its palette (`bytes`, [`palette_index`]): it was drawn black or clear.
fn decode_pixels(
    mut decoder: impl image::ImageDecoder,
    bytes: &[u8],
    name: &str,
) -> Result<image::DynamicImage, IoError> {
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(decoder.total_bytes().saturating_add(DECODE_WORK_BYTES));
    decoder.set_limits(limits).map_err(not_an_image(name))?;
    let img = image::DynamicImage::from_decoder(decoder).map_err(not_an_image(name))?;
    if let Some(p) = palette_index::first_past_palette(bytes) {
        return Err(IoError::PastPalette {
            input: name.to_string(),
            index: p.index,
            colours: p.colours,
            x: p.x,
            y: p.y,
        });
    }
    let samples: &[f32] = match &img {
        image::DynamicImage::ImageRgb32F(i) => i.as_raw(),
        image::DynamicImage::ImageRgba32F(i) => i.as_raw(),
        _ => &[],
    };
    if let Some(at) = samples.iter().position(|v| !v.is_finite()) {
        let channels = img.color().channel_count() as usize;
        let pixel = (at / channels) as u64;
        let width = u64::from(img.width());
        return Err(IoError::NotFinite {
            input: name.to_string(),
            x: pixel % width,
            y: pixel / width,
            value: samples[at],
        });
    }
    Ok(img)
}

/// The eight bytes every PNG starts with.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// The chunks of a PNG before its pixel data (`IDAT`) or its end, as
/// (type, data), walked without decoding anything; `None` for bytes that
/// do not start as a PNG. A chunk whose length runs past the bytes gives
/// what data there is, and ends the walk.
fn png_header_chunks(bytes: &[u8]) -> Option<impl Iterator<Item = (&[u8], &[u8])>> {
    let mut at = bytes
        .starts_with(PNG_SIGNATURE)
        .then_some(PNG_SIGNATURE.len())?;
    Some(std::iter::from_fn(move || {
        let (kind, len) = png_chunk_head(bytes, at)?;
        if kind == b"IDAT" || kind == b"IEND" {
            return None;
        }
        let data = &bytes[at + 8..bytes.len().min(at.saturating_add(8).saturating_add(len))];
        at = at.saturating_add(12).saturating_add(len);
        Some((kind, data))
    }))
}

/// The image gamma a PNG's `gAMA` chunk states (the exponent that decodes
/// its samples, so the inverse of the chunk's value / 100,000), when it is
/// not sRGB's and no `sRGB`, `iCCP` or `cICP` chunk comes before the pixel
/// data (each overrides `gAMA`: PNG 3rd edition, 11.3.2.5 and 11.3.2.6). sRGB's is taken
/// as the chunk values 45,000 to 46,000 (gamma 2.17 to 2.22): encoders
/// write 45,455 for it, and the sRGB curve is about gamma 2.2.
fn png_foreign_gamma(bytes: &[u8]) -> Option<f64> {
    const SRGB_GAMA: std::ops::RangeInclusive<u32> = 45_000..=46_000;
    let mut gama = None;
    for (kind, data) in png_header_chunks(bytes)? {
        match kind {
            b"sRGB" | b"iCCP" | b"cICP" => return None,
            b"gAMA" => {
                let v = data.get(..4)?;
                gama = Some(u32::from_be_bytes([v[0], v[1], v[2], v[3]]));
            }
            _ => {}
        }
    }
    let gama = gama.filter(|g| *g != 0 && !SRGB_GAMA.contains(g))?;
    Some(100_000.0 / f64::from(gama))
}

/// Whether a PNG has an ICC profile chunk (`iCCP`) before its pixel data,
/// found by walking the chunk list without inflating the profile: the
/// decoder drops a profile past [`PNG_METADATA_BYTES`] without a word.
fn png_has_icc_profile(bytes: &[u8]) -> bool {
    png_header_chunks(bytes).is_some_and(|mut chunks| chunks.any(|(kind, _)| kind == b"iCCP"))
}

/// How many frames an animated GIF, PNG or WebP holds, or pages a TIFF,
/// when more than one; found by walking its blocks, chunks or directories
/// without decoding them. The decoders give the first frame, and the rest
/// were dropped without a word (hostile-input reviews, GIF and APNG first,
/// then WebP and TIFF): the caller warns.
pub fn animation_frames(bytes: &[u8]) -> Option<u32> {
    let frames = match bytes.get(..4)? {
        b"RIFF" => webp_frames(bytes)?,
        b"II*\0" | b"MM\0*" => tiff_pages(bytes)?,
        _ => return gif_or_png_frames(bytes),
    };
    (frames > 1).then_some(frames)
}

/// The `ANMF` (frame) chunks of an animated WebP (RIFF chunks: a four-byte
/// type, a little-endian length, the data padded to an even length).
fn webp_frames(bytes: &[u8]) -> Option<u32> {
    if bytes.get(8..12)? != b"WEBP" {
        return None;
    }
    let (mut at, mut frames) = (12, 0u32);
    while let Some(head) = bytes.get(at..at + 8) {
        let len = u32::from_le_bytes([head[4], head[5], head[6], head[7]]) as usize;
        frames += u32::from(&head[..4] == b"ANMF");
        at = at
            .saturating_add(8)
            .saturating_add(len)
            .saturating_add(len % 2);
    }
    Some(frames)
}

/// The image file directories a TIFF chains from its header (TIFF 6.0,
/// section 2), each a page, wherever in the file they lie; the count ends
/// where the chain loops, leaves the file or passes `MAX_TIFF_PAGES`.
fn tiff_pages(bytes: &[u8]) -> Option<u32> {
    /// Pages counted at most: a warning needs no more.
    const MAX_TIFF_PAGES: u32 = 65_536;
    let big = bytes[0] == b'M';
    let u16_at = |at: usize| {
        let b: [u8; 2] = bytes.get(at..at.checked_add(2)?)?.try_into().ok()?;
        Some(if big {
            u16::from_be_bytes(b)
        } else {
            u16::from_le_bytes(b)
        })
    };
    let u32_at = |at: usize| {
        let b: [u8; 4] = bytes.get(at..at.checked_add(4)?)?.try_into().ok()?;
        Some(if big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        } as usize)
    };
    let mut seen = std::collections::HashSet::new();
    let mut at = u32_at(4)?;
    while at != 0 && (seen.len() as u32) < MAX_TIFF_PAGES && seen.insert(at) {
        // A directory: its entry count, 12 bytes an entry, the next's offset.
        let Some(entries) = u16_at(at) else {
            seen.remove(&at); // Not in the file: no page.
            break;
        };
        match u32_at(at + 2 + 12 * usize::from(entries)) {
            Some(next) => at = next,
            None => break,
        }
    }
    Some(seen.len() as u32)
}

/// [`animation_frames`] of a GIF or an APNG.
fn gif_or_png_frames(bytes: &[u8]) -> Option<u32> {
    let frames = if let Some(mut chunks) = png_header_chunks(bytes) {
        // APNG: an acTL chunk before the pixel data says how many.
        let (_, data) = chunks.find(|(kind, _)| *kind == b"acTL")?;
        let n = data.get(..4)?;
        u32::from_be_bytes([n[0], n[1], n[2], n[3]])
    } else if bytes.starts_with(b"GIF8") && bytes.len() >= 13 {
        // GIF: count the image descriptors, skipping each block's data.
        let colours = |flags: u8| {
            if flags & 0x80 != 0 {
                3usize << ((flags & 7) + 1)
            } else {
                0
            }
        };
        let skip_blocks = |mut at: usize| {
            while let Some(&n) = bytes.get(at) {
                at += 1 + n as usize;
                if n == 0 {
                    break;
                }
            }
            at
        };
        let mut at = 13 + colours(bytes[10]);
        let mut n = 0u32;
        while let Some(&b) = bytes.get(at) {
            match b {
                0x21 => at = skip_blocks(at + 2),
                0x2C => {
                    n += 1;
                    let flags = *bytes.get(at + 9)?;
                    // Descriptor, local colours, LZW code size, data.
                    at = skip_blocks(at + 10 + colours(flags) + 1);
                }
                _ => break,
            }
        }
        n
    } else {
        return None;
    };
    (frames > 1).then_some(frames)
}

/// A PNG's width and height as its header (IHDR, the first chunk) gives
/// them, or `None` for bytes that do not start as one.
fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    let (kind, data) = png_header_chunks(bytes)?.next()?;
    let dims = data.get(..8).filter(|_| kind == b"IHDR")?;
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    Some((be(&dims[..4]), be(&dims[4..8])))
}

/// [`open_decoder`] for a picture to decode whole: refused, from its header,
/// when it is larger than any tool makes one ([`MAX_IMAGE_SIDE`],
/// [`MAX_IMAGE_PIXELS`]), so that a small file declaring a huge picture (a
/// 389 KB PNG of 20000x20000 took 2 GB) costs nothing.
fn open_picture<'a>(bytes: &'a [u8], name: &str) -> Result<impl image::ImageDecoder + 'a, IoError> {
    use image::ImageDecoder as _;
    let decoder = open_decoder(bytes, name)?;
    let (width, height) = decoder.dimensions();
    Image::check_size(width, height).map_err(|error| IoError::PictureTooLarge {
        input: name.to_string(),
        error,
    })?;
    Ok(decoder)
}

/// [`decode_image`] for pictures from cameras and phones: the EXIF
/// orientation (JPEG, PNG's `eXIf`, TIFF, WebP) is applied, and an ICC
/// profile is reported so the caller can warn that it is not.
pub fn decode_photo(bytes: &[u8], name: &str) -> Result<Photo, IoError> {
    use image::ImageDecoder as _;
    let mut decoder = open_picture(bytes, name)?;
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let has_icc_profile = if image::guess_format(bytes).ok() == Some(image::ImageFormat::Png) {
        png_has_icc_profile(bytes)
    } else {
        decoder.icc_profile().ok().flatten().is_some()
    };
    let mut img = decode_pixels(decoder, bytes, name)?;
    img.apply_orientation(orientation);
    Ok(Photo {
        image: img.into_rgba8(),
        orientation,
        has_icc_profile,
        frames: animation_frames(bytes),
        foreign_gamma: png_foreign_gamma(bytes),
    })
}

/// An image's pixels as decoded for a texture: straight RGBA, row 0 at the
/// TOP, 8 bits a channel or, where the file has more, 16.
#[derive(Clone, Debug, PartialEq)]
pub enum RgbaPixels {
    /// 8 bits a channel, 4 per pixel.
    Rgba8(Vec<u8>),
    /// 16 bits a channel, 4 per pixel.
    Rgba16(Vec<u16>),
}

/// Whether `bytes` start like an image file the `image` crate reads (by
/// content, not by name): what tells an image texture from a `.pat`.
pub fn is_image(bytes: &[u8]) -> bool {
    image::guess_format(bytes).is_ok()
}

/// The width and height [`decode_texture`] gives `bytes`, read from the
/// header alone (a quarter turn by the EXIF orientation swaps them): what a
/// texture's texel coordinates are scaled by before it is decoded.
pub fn texture_size(bytes: &[u8], name: &str) -> Result<(u32, u32), IoError> {
    use image::metadata::Orientation as O;
    use image::ImageDecoder as _;
    let mut decoder = open_decoder(bytes, name)?;
    let (w, h) = decoder.dimensions();
    Ok(match decoder.orientation().unwrap_or(O::NoTransforms) {
        O::Rotate90 | O::Rotate270 | O::Rotate90FlipH | O::Rotate270FlipH => (h, w),
        _ => (w, h),
    })
}

/// [`decode_photo`] for a texture: the EXIF orientation applied, 16-bit
/// channels kept (PNG, TIFF, PNM with 16 bits), anything else as 8-bit
/// RGBA; refused before decoding if the image has more than `max_pixels`
/// pixels. Returns (width, height, pixels).
pub fn decode_texture(
    bytes: &[u8],
    name: &str,
    max_pixels: u64,
) -> Result<(u32, u32, RgbaPixels), IoError> {
    use image::ImageDecoder as _;
    let mut decoder = open_decoder(bytes, name)?;
    let (width, height) = decoder.dimensions();
    if width as u64 * height as u64 > max_pixels {
        return Err(IoError::TextureTooLarge {
            input: name.to_string(),
            width,
            height,
            limit: max_pixels,
        });
    }
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let mut img = decode_pixels(decoder, bytes, name)?;
    img.apply_orientation(orientation);
    let (width, height) = (img.width(), img.height());
    let deep = img.color().bytes_per_pixel() / img.color().channel_count() > 1;
    let pixels = if deep {
        RgbaPixels::Rgba16(img.into_rgba16().into_raw())
    } else {
        RgbaPixels::Rgba8(img.into_rgba8().into_raw())
    };
    Ok((width, height, pixels))
}

/// Whether `bytes` start as a PFM: `PF` (colour) or `Pf` (grey) and
/// whitespace.
pub fn is_pfm(bytes: &[u8]) -> bool {
    matches!(bytes, [b'P', b'F' | b'f', ws, ..] if ws.is_ascii_whitespace())
}

/// What is wrong with a PFM ([`IoError::BadPfm`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PfmError {
    /// The first two bytes are not `PF` or `Pf`.
    #[error("it does not start with `PF` or `Pf`")]
    Magic,
    /// A header field is missing or not a number.
    #[error("header: the {field} is `{found}`: expected {expected}")]
    Header {
        /// Which field: width, height or scale.
        field: &'static str,
        /// What the file has there (shortened), or `end of file`.
        found: String,
        /// What it should be.
        expected: &'static str,
    },
    /// The size is empty or beyond the tools' limits.
    #[error("header: {0}")]
    Size(#[from] SizeError),
    /// Fewer bytes of pixels than the header's size needs.
    #[error("truncated: {width}x{height} pixels of {channels} f32 need {needed} bytes after the header, the file has {found}")]
    Truncated {
        /// Width from the header.
        width: u32,
        /// Height from the header.
        height: u32,
        /// 3 (`PF`) or 1 (`Pf`).
        channels: u8,
        /// Bytes the pixels need.
        needed: u64,
        /// Bytes there are.
        found: u64,
    },
    /// More bytes than the header's size needs.
    #[error("{extra} byte(s) after the {width}x{height} pixels the header gives")]
    Trailing {
        /// Width from the header.
        width: u32,
        /// Height from the header.
        height: u32,
        /// Bytes beyond the pixels.
        extra: u64,
    },
    /// A sample is NaN or infinite.
    #[error("pixel ({x}, {y}) from the top-left, channel {channel}, is {value}: expected a finite number")]
    NotFinite {
        /// Column from the left.
        x: u32,
        /// Row from the top.
        y: u32,
        /// 0, 1, 2 for R, G, B.
        channel: u8,
        /// The value, as Rust prints it (`NaN`, `inf`, `-inf`).
        value: f32,
    },
}

/// What a PFM's header says ([`decode_pfm`]).
struct PfmHeader {
    /// 3 (`PF`) or 1 (`Pf`).
    channels: u8,
    width: u32,
    height: u32,
    /// A negative scale: the samples are little-endian.
    little: bool,
    /// Where the samples start.
    data_at: usize,
}

/// Reads a PFM's header ([`decode_pfm`]), its size checked against the
/// tools' limits.
fn pfm_header(bytes: &[u8]) -> Result<PfmHeader, PfmError> {
    if !is_pfm(bytes) {
        return Err(PfmError::Magic);
    }
    let channels: u8 = if bytes[1] == b'F' { 3 } else { 1 };
    let mut at = 2;
    // A header token: whitespace, then the bytes up to the next whitespace
    // (at most 64 of them: no number in a header is longer).
    let mut token = |field: &'static str, expected: &'static str| {
        while bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() && at - start < 64 {
            at += 1;
        }
        let text = String::from_utf8_lossy(&bytes[start..at]).into_owned();
        let found = if text.is_empty() {
            "end of file".to_string()
        } else {
            text.clone()
        };
        (text, move || PfmError::Header {
            field,
            found: found.clone(),
            expected,
        })
    };
    let (w, bad) = token("width", "a whole number of pixels");
    let width: u32 = w.parse().map_err(|_| bad())?;
    let (h, bad) = token("height", "a whole number of pixels");
    let height: u32 = h.parse().map_err(|_| bad())?;
    Image::check_size(width, height)?;
    let (sc, bad) = token(
        "scale",
        "a finite non-zero number (negative: little-endian)",
    );
    let scale: f32 = sc.parse().map_err(|_| bad())?;
    if !scale.is_finite() || scale == 0.0 {
        return Err(bad());
    }
    // Exactly one whitespace byte ends the header.
    if !bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
        return Err(bad());
    }
    Ok(PfmHeader {
        channels,
        width,
        height,
        little: scale < 0.0,
        data_at: at + 1,
    })
}

/// Reads a PFM (Portable Float Map, Debevec's format as netpbm's `pfmtopam`
/// reads it): `PF` (RGB) or `Pf` (grey, read as R = G = B), whitespace, the
/// width and height in decimal, the scale (negative: little-endian,
/// positive: big-endian; its magnitude is not applied, as a rendering's
/// values are linear light as they stand), one whitespace byte, then
/// `width * height` pixels of f32, rows from the bottom. The size is checked
/// against the tools' limits ([`Image::check_size`]) before anything is
/// allocated, and every sample must be finite.
pub fn decode_pfm(bytes: &[u8]) -> Result<LinearImage, PfmError> {
    let PfmHeader {
        channels,
        width,
        height,
        little,
        data_at,
    } = pfm_header(bytes)?;
    let data = &bytes[data_at..];
    let (wd, ht) = (width as usize, height as usize);
    let needed = wd as u64 * ht as u64 * channels as u64 * 4;
    if (data.len() as u64) < needed {
        return Err(PfmError::Truncated {
            width,
            height,
            channels,
            needed,
            found: data.len() as u64,
        });
    }
    if data.len() as u64 > needed {
        return Err(PfmError::Trailing {
            width,
            height,
            extra: data.len() as u64 - needed,
        });
    }
    let mut out = vec![0f32; wd * ht * 3];
    for (i, b) in data.chunks_exact(4).enumerate() {
        let b = [b[0], b[1], b[2], b[3]];
        let v = if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        };
        let px = i / channels as usize;
        let (x, y) = (px % wd, ht - 1 - px / wd);
        if !v.is_finite() {
            return Err(PfmError::NotFinite {
                x: x as u32,
                y: y as u32,
                channel: (i % channels as usize) as u8,
                value: v,
            });
        }
        let o = (y * wd + x) * 3;
        if channels == 3 {
            out[o + i % 3] = v;
        } else {
            out[o..o + 3].fill(v);
        }
    }
    Ok(LinearImage {
        width,
        height,
        data: out,
    })
}

/// Decodes an image to measure, at the depth it has: a PFM as linear
/// light, a 16-bit PNG or PNM (MAXVAL above 255) as 16-bit sRGB RGBA, any
/// other image the `image` crate reads as 8-bit sRGB RGBA (no EXIF
/// orientation, as [`decode_image`]).
pub fn decode_any(bytes: &[u8], name: &str) -> Result<AnyImage, IoError> {
    if is_pfm(bytes) {
        return decode_pfm(bytes)
            .map(AnyImage::Linear)
            .map_err(|error| IoError::BadPfm {
                input: name.to_string(),
                error,
            });
    }
    let img = decode_pixels(open_picture(bytes, name)?, bytes, name)?;
    let (width, height) = (img.width(), img.height());
    let deep = img.color().bytes_per_pixel() / img.color().channel_count() > 1;
    Ok(if deep {
        AnyImage::Srgb16(Image16 {
            width,
            height,
            channels: 4,
            data: img.into_rgba16().into_raw(),
        })
    } else {
        AnyImage::Srgb8(Image {
            width,
            height,
            channels: 4,
            data: img.into_rgba8().into_raw(),
        })
    })
}

/// The width and height a picture's header gives (a PFM's too), read
/// before its pixels are decoded: a compressed file of a few kilobytes may
/// decode to gigabytes.
pub fn picture_size(bytes: &[u8], name: &str) -> Result<(u32, u32), IoError> {
    use image::ImageDecoder as _;
    if is_pfm(bytes) {
        let h = pfm_header(bytes).map_err(|error| IoError::BadPfm {
            input: name.to_string(),
            error,
        })?;
        return Ok((h.width, h.height));
    }
    Ok(open_picture(bytes, name)?.dimensions())
}

/// Decodes any image the `image` crate reads (PNG, JPEG, GIF, BMP, TIFF, WebP,
/// PNM/PAM) into RGBA8, as stored (no EXIF orientation: see [`decode_photo`]).
pub fn decode_image(bytes: &[u8], name: &str) -> Result<image::RgbaImage, IoError> {
    let img = decode_pixels(open_picture(bytes, name)?, bytes, name)?;
    Ok(img.into_rgba8())
}

/// A PAM header (netpbm's `pam(5)`): RGB, or RGB_ALPHA for 4 channels,
/// samples up to `maxval`.
fn write_pam_header(
    w: &mut dyn Write,
    (width, height): (u32, u32),
    channels: u8,
    maxval: u32,
) -> std::io::Result<()> {
    let (depth, tupltype) = if channels == 4 {
        (4, "RGB_ALPHA")
    } else {
        (3, "RGB")
    };
    write!(
        w,
        "P7\nWIDTH {width}\nHEIGHT {height}\nDEPTH {depth}\nMAXVAL {maxval}\nTUPLTYPE {tupltype}\nENDHDR\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_float_picture_with_a_sample_not_finite_is_refused() {
        // 8-bit conversion made NaN white, and `--report` said "PSNR inf".
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let mut img = image::Rgb32FImage::from_pixel(3, 2, image::Rgb([0.25, 0.5, 1.0]));
            img.put_pixel(1, 1, image::Rgb([0.0, bad, 0.0]));
            let mut tiff = io::Cursor::new(Vec::new());
            image::DynamicImage::ImageRgb32F(img)
                .write_to(&mut tiff, image::ImageFormat::Tiff)
                .unwrap();
            let err = decode_image(tiff.get_ref(), "f.tif").unwrap_err();
            assert_eq!(
                err.to_string(),
                format!("f.tif: the sample {bad} at pixel (1, 1) is not a finite number")
            );
        }
        // Finite ones decode.
        let img = image::Rgb32FImage::from_pixel(3, 2, image::Rgb([0.25, 0.5, 1.0]));
        let mut tiff = io::Cursor::new(Vec::new());
        image::DynamicImage::ImageRgb32F(img)
            .write_to(&mut tiff, image::ImageFormat::Tiff)
            .unwrap();
        assert_eq!(
            decode_image(tiff.get_ref(), "f.tif").unwrap().dimensions(),
            (3, 2)
        );
    }

    /// A 2x2 PNG with an ICC profile of `profile` bytes (zeros: it
    /// compresses to a thousandth of that).
    fn png_with_profile(profile: usize) -> Vec<u8> {
        use image::ImageEncoder as _;
        let mut png = Vec::new();
        let mut enc = image::codecs::png::PngEncoder::new(&mut png);
        enc.set_icc_profile(vec![0; profile]).unwrap();
        enc.write_image(&[9; 12], 2, 2, image::ExtendedColorType::Rgb8)
            .unwrap();
        png
    }

    /// A PNG chunk is named by its type in a decoder's message, not by
    /// the `png` crate's debug form.
    #[test]
    fn a_png_chunk_is_named_by_its_type() {
        let mut png = Vec::new();
        let mut e = png::Encoder::new(&mut png, 1, 1);
        e.set_color(png::ColorType::Rgb);
        e.write_header().unwrap().write_image_data(&[9; 3]).unwrap();
        // The IDAT chunk's CRC, 12 bytes before the end (IEND's 12 bytes).
        let at = png.len() - 13;
        png[at] ^= 1;
        // The error and its sources, as the tools print them.
        let err = decode_image(&png, "crc.png").unwrap_err();
        let mut said = err.to_string();
        let mut source = std::error::Error::source(&err);
        while let Some(s) = source {
            said.push_str(&format!(": {s}"));
            source = s.source();
        }
        assert!(said.contains("while decoding IDAT chunk"), "{said}");
        assert!(!said.contains("ChunkType"), "{said}");
    }

    /// A PNG's gAMA other than sRGB's is reported (to be warned of), with
    /// the gamma it decodes by; sRGB's, or one an sRGB chunk overrides, is
    /// not.
    #[test]
    fn a_png_gamma_other_than_srgbs_is_reported() {
        let png = |gama: Option<u32>, srgb: bool| {
            let mut out = Vec::new();
            let mut e = png::Encoder::new(&mut out, 1, 1);
            e.set_color(png::ColorType::Rgb);
            if let Some(g) = gama {
                e.set_source_gamma(png::ScaledFloat::from_scaled(g));
            }
            if srgb {
                e.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            }
            e.write_header().unwrap().write_image_data(&[9; 3]).unwrap();
            out
        };
        let gamma = |bytes: &[u8]| decode_photo(bytes, "g.png").unwrap().foreign_gamma;
        assert_eq!(gamma(&png(Some(100_000), false)), Some(1.0));
        assert_eq!(gamma(&png(Some(50_000), false)), Some(2.0));
        assert_eq!(gamma(&png(Some(45_455), false)), None);
        assert_eq!(gamma(&png(None, false)), None);
        assert_eq!(gamma(&png(None, true)), None);
        // A cICP chunk overrides gAMA too (its CRC is not read here).
        let mut cicp = png(Some(100_000), false);
        let ihdr_end = 8 + 12 + 13;
        let chunk = [&[0, 0, 0, 4][..], b"cICP", &[1, 13, 0, 1], &[0; 4]].concat();
        cicp.splice(ihdr_end..ihdr_end, chunk);
        assert_eq!(png_foreign_gamma(&cicp), None);
        assert_eq!(png_foreign_gamma(&png(Some(100_000), false)), Some(1.0));
    }

    #[test]
    fn animated_gifs_pngs_webps_and_tiff_pages_are_counted_without_decoding() {
        let frame = |v: u8| {
            image::Frame::new(image::RgbaImage::from_pixel(
                4,
                4,
                image::Rgba([v, 0, 0, 255]),
            ))
        };
        // A GIF of three frames, and one of one.
        let gif = |n: u8| {
            let mut out = Vec::new();
            let mut enc = image::codecs::gif::GifEncoder::new(&mut out);
            enc.encode_frames((0..n).map(|i| frame(i * 80))).unwrap();
            drop(enc);
            out
        };
        assert_eq!(animation_frames(&gif(3)), Some(3));
        assert_eq!(animation_frames(&gif(1)), None);
        let three = decode_photo(&gif(3), "a.gif").unwrap();
        assert_eq!(three.frames, Some(3));
        assert_eq!(three.image.get_pixel(0, 0).0[0], 0, "the first frame");
        // An APNG of two frames; a plain PNG; a PNG whose chunks lie.
        let mut apng = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut apng, 2, 2);
            enc.set_color(png::ColorType::Rgb);
            enc.set_animated(2, 0).unwrap();
            let mut w = enc.write_header().unwrap();
            w.write_image_data(&[1; 12]).unwrap();
            w.write_image_data(&[2; 12]).unwrap();
            w.finish().unwrap();
        }
        assert_eq!(animation_frames(&apng), Some(2));
        let plain = png_with_profile(10);
        assert_eq!(animation_frames(&plain), None);
        let mut lying = plain.clone();
        lying[8..12].copy_from_slice(&u32::MAX.to_be_bytes());
        assert_eq!(animation_frames(&lying), None);
        assert_eq!(animation_frames(&gif(3)[..20]), None);
        // An animated WebP's frame chunks, after others (one of odd length,
        // padded), laid out by hand.
        let chunk = |kind: &[u8], len: u32| {
            let mut c = kind.to_vec();
            c.extend(len.to_le_bytes());
            c.extend(vec![0; (len + len % 2) as usize]);
            c
        };
        let mut webp = b"RIFF\0\0\0\0WEBP".to_vec();
        webp.extend(chunk(b"VP8X", 10));
        webp.extend(chunk(b"ANIM", 5));
        for _ in 0..3 {
            webp.extend(chunk(b"ANMF", 16));
        }
        assert_eq!(animation_frames(&webp), Some(3));
        assert_eq!(animation_frames(&webp[..webp.len() - 40]), Some(2));
        // A TIFF's directories, big- and little-endian, each with no entry;
        // a chain pointing back ends there.
        let tiff = |big: bool, next: [u32; 2]| {
            let u32b = |v: u32| {
                if big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                }
            };
            let mut t = if big {
                b"MM\0*".to_vec()
            } else {
                b"II*\0".to_vec()
            };
            t.extend(u32b(8));
            for n in next {
                t.extend([0, 0]);
                t.extend(u32b(n));
            }
            t
        };
        assert_eq!(animation_frames(&tiff(false, [14, 0])), Some(2));
        assert_eq!(animation_frames(&tiff(true, [14, 0])), Some(2));
        assert_eq!(animation_frames(&tiff(false, [14, 8])), Some(2));
        assert_eq!(animation_frames(&tiff(false, [0, 0])), None);
        // Directories out of order, and a chain whose last link leaves the
        // file: two pages each (a review).
        let mut reordered = tiff(false, [0, 8]);
        reordered[4] = 14;
        assert_eq!(animation_frames(&reordered), Some(2));
        assert_eq!(animation_frames(&tiff(false, [14, 1000])), Some(2));
    }

    #[test]
    fn an_icc_profile_is_reported_without_inflating_it() {
        // The decoder inflated a 300 MB profile (619 MB peak for a 64x64
        // picture) and dropped one past its allowance without a word; the
        // chunk is now found by walking the chunk list, and the decoder
        // stops at PNG_METADATA_BYTES.
        let small = png_with_profile(3000);
        assert!(png_has_icc_profile(&small));
        assert!(decode_photo(&small, "p.png").unwrap().has_icc_profile);
        let past = png_with_profile(PNG_METADATA_BYTES as usize + 1000);
        assert!(past.len() < 1 << 20);
        let photo = decode_photo(&past, "p.png").unwrap();
        assert!(photo.has_icc_profile);
        assert_eq!(photo.image.get_pixel(1, 1).0, [9, 9, 9, 255]);
        use image::ImageEncoder as _;
        let mut plain = Vec::new();
        image::codecs::png::PngEncoder::new(&mut plain)
            .write_image(&[9; 12], 2, 2, image::ExtendedColorType::Rgb8)
            .unwrap();
        assert!(!png_has_icc_profile(&plain));
        assert!(!decode_photo(&plain, "p.png").unwrap().has_icc_profile);
        // A chunk list cut short, or lying about a length, is no profile.
        assert!(!png_has_icc_profile(&small[..20]));
        let mut lying = plain.clone();
        lying[8..12].copy_from_slice(&u32::MAX.to_be_bytes());
        assert!(!png_has_icc_profile(&lying));
    }

    #[test]
    fn an_opened_file_reads_back_whole_from_its_first_byte() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.pat");
        let bytes: Vec<u8> = (0..3 * SNIFF_BYTES + 5)
            .map(|i| b'0' + (i % 7) as u8)
            .collect();
        std::fs::write(&path, &bytes).unwrap();
        let opened = open_path(&path).unwrap();
        assert_eq!(opened.start, bytes[..SNIFF_BYTES]);
        let mut back = Vec::new();
        opened.into_reader().read_to_end(&mut back).unwrap();
        assert_eq!(back, bytes);
        assert_eq!(open_path(&path).unwrap().read_all().unwrap(), bytes);
        let name = path.to_str().unwrap();
        let opened = open_input(name, InputKind::Text).unwrap();
        assert_eq!(opened.read_input().unwrap(), bytes);
        // What read_path refuses, open_path refuses: a directory, a device.
        assert!(open_path(dir.path()).is_err());
        assert!(open_path(Path::new("/dev/zero")).is_err());
    }

    #[test]
    fn past_a_blank_start_keeps_its_newlines_and_what_follows() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.pat");
        // Four sniffs' worth of blank lines (spaces, tabs, CRLF), then text.
        let blank = " \t\r\n".repeat(SNIFF_BYTES);
        let text = "  16 1\n1 2 3\n";
        std::fs::write(&path, format!("{blank}{text}")).unwrap();
        let lines = "\n".repeat(SNIFF_BYTES);
        let name = path.to_str().unwrap();
        let past = || {
            open_input(name, InputKind::Text)
                .unwrap()
                .past_blank_start()
                .unwrap()
        };
        let opened = past();
        assert_eq!(opened.start, text.as_bytes());
        // Of the whitespace read past, its newlines come back first.
        let mut back = Vec::new();
        opened.into_reader().read_to_end(&mut back).unwrap();
        assert_eq!(back, format!("{lines}{text}").into_bytes());
        assert_eq!(past().read_all().unwrap(), back);
        // A start that is not blank is left as it is; a blank file is empty.
        std::fs::write(&path, format!("{text}{blank}")).unwrap();
        assert_eq!(
            past().start,
            format!("{text}{blank}").as_bytes()[..SNIFF_BYTES]
        );
        std::fs::write(&path, &blank).unwrap();
        let opened = past();
        assert!(opened.start.is_empty());
        assert_eq!(opened.read_all().unwrap(), lines.as_bytes());
    }

    /// `n` pseudo-random words from `seed` (a linear congruential
    /// generator, Numerical Recipes' constants): test images' samples.
    fn noise(seed: u32, n: usize) -> impl Iterator<Item = u32> {
        let step = |s: u32| s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        std::iter::successors(Some(step(seed)), move |&s| Some(step(s))).take(n)
    }

    /// The rows of an image, encoded as they come, give netpbm's bytes
    /// (written out here by hand) and the image's PNG pixels (decoded by the
    /// `image` crate, not by the encoder's own crate), with one IDAT chunk
    /// or, cut small, many.
    #[test]
    fn rows_give_the_pixels_and_netpbm_bytes_of_the_whole_image() {
        for channels in [3u8, 4] {
            let (width, height) = (37, 23);
            let n = (width * height * channels as u32) as usize;
            let data = noise(7, n).map(|v| (v >> 24) as u8).collect();
            let img = Image {
                width,
                height,
                channels,
                data,
            };
            // netpbm's files written out by hand (ppm(5), pam(5)): PPM
            // without alpha, PAM with it when there is one.
            let rgb: Vec<u8> = img
                .data
                .chunks(channels as usize)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            let tupltype = if channels == 4 { "RGB_ALPHA" } else { "RGB" };
            let ppm = [format!("P6\n{width} {height}\n255\n").as_bytes(), &rgb].concat();
            let pam = [
                format!("P7\nWIDTH {width}\nHEIGHT {height}\nDEPTH {channels}\nMAXVAL 255\nTUPLTYPE {tupltype}\nENDHDR\n").as_bytes(),
                &img.data,
            ]
            .concat();
            for (format, want) in [(ImageFormat::Ppm, ppm), (ImageFormat::Pam, pam)] {
                let (mut whole, mut rows) = (Vec::new(), Vec::new());
                img.encode(format, &mut whole).unwrap();
                encode_rows(&mut &img, format, PngOptions::GENERAL, &mut rows).unwrap();
                assert!(rows == want && whole == want, "{format:?} {channels}");
            }
            for (options, chunk) in [
                (PngOptions::GENERAL, PNG_STREAM_CHUNK_BYTES),
                (PngOptions::FLAT_REPEATING, 100),
            ] {
                let mut png = Vec::new();
                encode_rows_in_chunks(&mut &img, ImageFormat::Png, options, &mut png, chunk)
                    .unwrap();
                // The chunks' lengths and types, after the 8-byte signature.
                let (mut at, mut idat_chunks) = (8, 0);
                while at < png.len() {
                    let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
                    idat_chunks += usize::from(&png[at + 4..at + 8] == b"IDAT");
                    assert!(chunk == PNG_STREAM_CHUNK_BYTES || len <= chunk);
                    at += 12 + len;
                }
                assert!(
                    idat_chunks > 4 || chunk == PNG_STREAM_CHUNK_BYTES,
                    "{idat_chunks}"
                );
                let back = decode_image(&png, "rows.png").unwrap();
                let rgba: Vec<u8> = if channels == 4 {
                    img.data.clone()
                } else {
                    img.data
                        .chunks(3)
                        .flat_map(|p| [p[0], p[1], p[2], 255])
                        .collect()
                };
                assert_eq!(back.dimensions(), (width, height));
                assert_eq!(back.into_raw(), rgba, "{channels} {chunk}");
            }
            let pfm = encode_rows(
                &mut &img,
                ImageFormat::Pfm,
                PngOptions::GENERAL,
                &mut Vec::new(),
            );
            assert_eq!(pfm.unwrap_err().kind(), io::ErrorKind::InvalidInput);
        }
    }

    /// A JPEG cut anywhere after its first scan starts is refused, by name,
    /// even with an end-of-image marker inside a header segment (an EXIF
    /// thumbnail's); whole, it decodes.
    #[test]
    fn a_truncated_jpeg_is_refused() {
        let fixture = |name: &str| {
            std::fs::read(
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("fixtures/images")
                    .join(name),
            )
            .unwrap()
        };
        let earth = fixture("earth-nasa.jpg");
        // An APP1 segment holding a thumbnail's SOS and EOI markers.
        let thumb: &[u8] = b"Exif\0\0\xff\xd8\xff\xda\x00\x02\xff\xd9";
        let mut exif = earth[..2].to_vec();
        exif.extend_from_slice(&[0xFF, 0xE1, 0, 2 + thumb.len() as u8]);
        exif.extend_from_slice(thumb);
        exif.extend_from_slice(&earth[2..]);
        for whole in [&earth, &exif] {
            assert!(decode_image(whole, "earth.jpg").is_ok());
            for cut in [1_000, whole.len() / 2, whole.len() - 2] {
                let err = decode_image(&whole[..cut], "earth.jpg").unwrap_err();
                assert_eq!(
                    err.to_string(),
                    "earth.jpg: truncated JPEG: the data ends before its end-of-image marker",
                    "cut at {cut}"
                );
            }
        }
        assert!(check_jpeg(&fixture("moon-usgs.jpg"), "moon.jpg").is_ok());
        // Ends that are there, around faults that are not truncation: a
        // segment of length 0, an end before any scan, a stray byte.
        let mut zero = earth[..2].to_vec();
        zero.extend_from_slice(&[0xFF, 0xE2, 0, 0]);
        zero.extend_from_slice(&earth[2..]);
        let mut stray = earth[..2].to_vec();
        stray.extend_from_slice(&[0xFF, 0xE0, 0, 4, 0, 0, 0x42]);
        stray.extend_from_slice(&earth[2..]);
        for (bytes, said) in [
            (
                &zero[..],
                "the segment FF E2 at offset 2 has length 0 (it counts its own 2 bytes)",
            ),
            (
                b"\xff\xd8\xff\xd9\0\0",
                "it ends (FF D9 at offset 2) before any scan",
            ),
            (&stray, "byte 0x42 at offset 8, where a marker (FF) belongs"),
        ] {
            let err = decode_image(bytes, "bad.jpg").unwrap_err();
            assert_eq!(err.to_string(), format!("bad.jpg: malformed JPEG: {said}"));
        }
    }

    /// A picture's header that declares more than any tool makes is refused
    /// before a pixel is decoded: these headers have no pixels at all.
    #[test]
    fn pictures_over_the_size_limits_are_refused_from_their_header() {
        for (header, want) in [
            (
                &b"P5\n20000 20000\n255\n"[..],
                "20000x20000 is too large: at most 268435456 pixels",
            ),
            (
                &b"P6\n70000 16\n255\n"[..],
                "70000x16 is too large: each side at most 65535",
            ),
        ] {
            let text = |e: IoError| e.to_string();
            for got in [
                decode_image(header, "bomb.pnm").map(|_| ()).map_err(text),
                decode_photo(header, "bomb.pnm").map(|_| ()).map_err(text),
                decode_any(header, "bomb.pnm").map(|_| ()).map_err(text),
            ] {
                assert_eq!(got, Err(format!("bomb.pnm: image size {want}")));
            }
        }
        // At the limit, the header passes and the missing pixels are the error.
        let at_limit = decode_image(b"P5\n16384 16384\n255\n", "short.pgm").unwrap_err();
        assert!(matches!(at_limit, IoError::NotAnImage { .. }), "{at_limit}");
        // A PNG header past the PNG decoder's own memory limit: it said
        // "Memory limit exceeded" before our check could read the header.
        let crc32 = |data: &[u8]| {
            let mut c = !0u32;
            for &b in data {
                c ^= b as u32;
                for _ in 0..8 {
                    c = if c & 1 == 1 {
                        (c >> 1) ^ 0xEDB8_8320
                    } else {
                        c >> 1
                    };
                }
            }
            !c
        };
        let side = 0x7FFF_FFFFu32;
        let mut ihdr = b"IHDR".to_vec();
        ihdr.extend_from_slice(&side.to_be_bytes());
        ihdr.extend_from_slice(&side.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        png.extend_from_slice(&13u32.to_be_bytes());
        png.extend_from_slice(&ihdr);
        png.extend_from_slice(&crc32(&ihdr).to_be_bytes());
        assert_eq!(png_size(&png), Some((side, side)));
        let e = decode_image(&png, "bomb.png").unwrap_err().to_string();
        assert_eq!(
            e,
            "bomb.png: image size 2147483647x2147483647 is too large: each side at most 65535"
        );
    }

    #[test]
    fn failed_output_leaves_no_file_behind() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        {
            let mut out = Output::create(path.to_str().unwrap(), true).unwrap();
            out.write_all(b"partial").unwrap();
            // dropped without commit, as on an error
        }
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        let out = Output::create(path.to_str().unwrap(), true).unwrap();
        out.commit().unwrap();
        assert!(path.exists());
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_ne!(
                mode & 0o044,
                0,
                "output is readable by others as usual: {mode:o}"
            );
        }
    }

    #[test]
    fn a_file_output_larger_than_the_write_behind_step_keeps_every_byte() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.pat");
        let bytes: Vec<u8> = (0..3 * WRITE_BEHIND_BYTES as usize + 12_345)
            .map(|i| (i * 7 % 251) as u8)
            .collect();
        // An old file replaced, as a benchmark's rerun does.
        std::fs::write(&path, b"old").unwrap();
        let mut out = Output::create(path.to_str().unwrap(), false).unwrap();
        // Small writes (buffered), one larger than the step, partial writes.
        let (head, rest) = bytes.split_at(1000);
        for b in head.chunks(10) {
            out.write_all(b).unwrap();
        }
        let (big, mut rest) = rest.split_at(WRITE_BEHIND_BYTES as usize + 1);
        out.write_all(big).unwrap();
        while !rest.is_empty() {
            let n = out.write(&rest[..rest.len().min(1 << 20)]).unwrap();
            rest = &rest[n..];
        }
        out.commit().unwrap();
        assert!(std::fs::read(&path).unwrap() == bytes);
    }

    /// A device named as the output whose writes fail only when the last
    /// bytes are flushed (an output smaller than the buffer, to a full
    /// device) is named in the error, as a larger output's is.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_device_that_fails_at_the_last_flush_is_named() {
        if !Path::new("/dev/full").exists() {
            return;
        }
        let mut out = Output::create("/dev/full", false).unwrap();
        out.write_all(b"P6\n1 1\n255\n\0\0\0").unwrap();
        let err = out.commit().unwrap_err();
        assert_eq!(
            err.to_string(),
            "writing /dev/full",
            "{:?}",
            std::error::Error::source(&err)
        );
    }

    /// A file name longer than the file system holds is refused when the
    /// output is opened (and so by `check_output`, before any work), not
    /// only by the rename at the end.
    #[test]
    fn a_file_name_too_long_is_refused_when_opened() {
        let dir = tempfile::tempdir().unwrap();
        let name = dir.path().join(format!("f{}.png", "0".repeat(300)));
        let name = name.to_str().unwrap();
        let err = check_output(name, false).unwrap_err();
        assert!(err.to_string().starts_with(name), "{err}");
        let IoError::Write { error, .. } = err else {
            panic!("{err:?}")
        };
        assert_eq!(error.kind(), io::ErrorKind::InvalidFilename);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        // At the limit (255 bytes on Linux's file systems) it is written.
        let name = dir.path().join(format!("f{}.png", "0".repeat(250)));
        let mut out = Output::create(name.to_str().unwrap(), false).unwrap();
        out.write_all(b"x").unwrap();
        out.commit().unwrap();
        assert_eq!(std::fs::read(&name).unwrap(), b"x");
    }

    #[test]
    fn an_empty_output_name_is_refused_before_anything_is_written() {
        let err = Output::create("", true).map(drop).unwrap_err();
        assert_eq!(
            err.to_string(),
            "an empty output name: expected a file name, or - for standard output"
        );
    }

    #[test]
    #[cfg(unix)]
    fn a_replaced_output_keeps_its_permission_bits() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("private.png");
        for mode in [0o600, 0o640, 0o755] {
            std::fs::write(&path, b"old").unwrap();
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(mode)).unwrap();
            let mut out = Output::create(path.to_str().unwrap(), true).unwrap();
            out.write_all(b"new").unwrap();
            out.commit().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), b"new");
            let now = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
            assert_eq!(now, mode, "{now:o} against {mode:o}");
        }
    }

    #[test]
    #[cfg(unix)]
    fn a_device_is_written_in_place_and_a_link_keeps_pointing() {
        use std::os::unix::fs::FileTypeExt;
        let mut out = Output::create("/dev/null", true).unwrap();
        out.write_all(b"discarded").unwrap();
        out.commit().unwrap();
        let meta = std::fs::metadata("/dev/null").unwrap();
        assert!(
            meta.file_type().is_char_device(),
            "/dev/null is still a device"
        );

        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("real.txt");
        std::fs::write(&target, b"old").unwrap();
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let mut out = Output::create(link.to_str().unwrap(), false).unwrap();
        out.write_all(b"new").unwrap();
        out.commit().unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
    }

    #[test]
    fn format_follows_flag_then_extension() {
        assert_eq!(
            ImageFormat::choose(None, "a.PPM").unwrap(),
            ImageFormat::Ppm
        );
        assert_eq!(
            ImageFormat::choose(None, "a.pam").unwrap(),
            ImageFormat::Pam
        );
        assert_eq!(ImageFormat::choose(None, "-").unwrap(), ImageFormat::Png);
        assert_eq!(
            ImageFormat::choose(Some(ImageFormat::Pam), "a.png").unwrap(),
            ImageFormat::Pam
        );
        let e = ImageFormat::choose(None, "a.jpg").unwrap_err().to_string();
        assert!(e.contains("a.jpg") && e.contains(".jpg"), "{e}");
    }

    #[test]
    fn absurd_sizes_are_refused() {
        assert!(Image::check_size(0, 5).is_err());
        assert!(Image::check_size(70_000, 1).is_err());
        assert!(Image::check_size(60_000, 60_000).is_err());
        assert!(Image::check_size(4096, 4096).is_ok());
    }

    fn pfm(header: &str, values: &[f32]) -> Vec<u8> {
        let mut b = header.as_bytes().to_vec();
        b.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        b
    }

    #[test]
    fn pfm_round_trips_bit_for_bit_with_rows_bottom_to_top() {
        let img = LinearImage {
            width: 2,
            height: 2,
            data: vec![
                0.0, 0.25, 0.5, 1.0, 1e-7, 0.75, 0.1, 0.2, 0.3, 2.5, -0.0, 0.9,
            ],
        };
        let mut buf = Vec::new();
        img.encode(ImageFormat::Pfm, &mut buf).unwrap();
        assert!(buf.starts_with(b"PF\n2 2\n-1.0\n"));
        // The file's first pixel is the bottom-left one.
        let first = f32::from_le_bytes(buf[12..16].try_into().unwrap());
        assert_eq!(first, 0.1);
        let back = decode_pfm(&buf).unwrap();
        assert_eq!(back, img);
        // Big-endian (positive scale) and grey (`Pf`) are read too.
        let mut be = b"PF 1 1 1.0\n".to_vec();
        be.extend([0.5f32, 0.25, 1.0].iter().flat_map(|v| v.to_be_bytes()));
        assert_eq!(decode_pfm(&be).unwrap().data, vec![0.5, 0.25, 1.0]);
        assert_eq!(
            decode_pfm(&pfm("Pf\n1 1\n-1\n", &[0.5])).unwrap().data,
            vec![0.5; 3]
        );
    }

    #[test]
    fn malformed_pfm_is_refused_with_what_is_wrong() {
        let cases: [(Vec<u8>, &str); 11] = [
            (b"P6\n1 1\n255\n".to_vec(), "does not start with `PF`"),
            (pfm("PF\nabc 1\n-1.0\n", &[0.0; 3]), "the width is `abc`"),
            (pfm("PF\n1 1\n", &[]), "the scale is `end of file`"),
            (pfm("PF\n1 -2\n-1.0\n", &[]), "the height is `-2`"),
            (pfm("PF\n0 1\n-1.0\n", &[]), "is empty"),
            (pfm("PF\n70000 1\n-1.0\n", &[]), "each side at most 65535"),
            (
                pfm("PF\n60000 60000\n-1.0\n", &[]),
                "at most 268435456 pixels",
            ),
            (pfm("PF\n1 1\nnan\n", &[0.0; 3]), "the scale is `nan`"),
            (
                pfm("PF\n2 1\n-1.0\n", &[0.0; 5]),
                "need 24 bytes after the header, the file has 20",
            ),
            (
                pfm("PF\n1 1\n-1.0\n", &[0.0; 4]),
                "4 byte(s) after the 1x1 pixels",
            ),
            (
                pfm(
                    "PF\n2 2\n-1.0\n",
                    &[
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                        f32::NAN,
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                    ],
                ),
                "pixel (1, 1) from the top-left, channel 1, is NaN",
            ),
        ];
        for (bytes, want) in cases {
            let e = decode_pfm(&bytes).unwrap_err().to_string();
            assert!(e.contains(want), "{want:?} not in {e:?}");
        }
        let e =
            decode_any(&pfm("PF\n1 1\n-1.0\n", &[f32::INFINITY, 0.0, 0.0]), "x.pfm").unwrap_err();
        assert_eq!(e.to_string(), "x.pfm: not a valid PFM image");
        assert!(std::error::Error::source(&e)
            .unwrap()
            .to_string()
            .contains("is inf"));
    }

    #[test]
    fn a_spent_16_bit_image_encodes_as_a_kept_one() {
        // PNG, PPM and PAM bytes of an image encoded borrowed, spent (its
        // samples turned big-endian in place), and, for the netpbm formats
        // (now written a row at a time), built whole as before: a header and
        // every kept sample big-endian.
        for channels in [3u8, 4] {
            let (width, height) = (37, 5);
            let n = (width * height * channels as u32) as usize;
            let data = noise(12345, n).map(|v| (v >> 16) as u16).collect();
            let img = Image16 {
                width,
                height,
                channels,
                data,
            };
            for f in [ImageFormat::Png, ImageFormat::Ppm, ImageFormat::Pam] {
                let mut kept = Vec::new();
                img.encode_with(f, PngOptions::GENERAL, &mut kept).unwrap();
                let mut spent = Vec::new();
                let any = AnyImage::Srgb16(img.clone());
                any.encode_spent(f, PngOptions::GENERAL, &mut spent)
                    .unwrap();
                assert!(kept == spent, "{f:?}, {channels} channels");
                let keep = if f == ImageFormat::Ppm {
                    3
                } else {
                    channels as usize
                };
                let whole: Vec<u8> = img
                    .data
                    .chunks_exact(channels as usize)
                    .flat_map(|p| p[..keep].iter().flat_map(|v| v.to_be_bytes()))
                    .collect();
                let mut want = Vec::new();
                match f {
                    ImageFormat::Ppm => write!(want, "P6\n{width} {height}\n65535\n").unwrap(),
                    ImageFormat::Pam => {
                        write_pam_header(&mut want, (width, height), channels, 65535).unwrap()
                    }
                    _ => continue,
                }
                want.extend(whole);
                assert!(kept == want, "{f:?}, {channels} channels");
            }
        }
    }

    #[test]
    fn an_empty_16_bit_image_is_a_header_alone() {
        // No rows to write a row at a time (the row length is 0).
        let img = Image16 {
            width: 0,
            height: 0,
            channels: 3,
            data: Vec::new(),
        };
        let mut ppm = Vec::new();
        img.encode_with(ImageFormat::Ppm, PngOptions::GENERAL, &mut ppm)
            .unwrap();
        assert_eq!(ppm, b"P6\n0 0\n65535\n");
    }

    #[test]
    fn sixteen_bit_formats_round_trip_and_pngs_say_srgb() {
        let img = Image16 {
            width: 2,
            height: 1,
            channels: 4,
            data: vec![1, 258, 65534, 65535, 40000, 3, 0, 12345],
        };
        for f in [ImageFormat::Ppm, ImageFormat::Pam, ImageFormat::Png] {
            let mut buf = Vec::new();
            img.encode_with(f, PngOptions::GENERAL, &mut buf).unwrap();
            let AnyImage::Srgb16(back) = decode_any(&buf, "x").unwrap() else {
                panic!("{f:?} not read back as 16-bit");
            };
            let alpha = if f == ImageFormat::Ppm {
                [65535, 65535]
            } else {
                [65535, 12345]
            };
            assert_eq!(
                back.data,
                vec![1, 258, 65534, alpha[0], 40000, 3, 0, alpha[1]],
                "{f:?}"
            );
            if f == ImageFormat::Png {
                let info = png::Decoder::new(io::Cursor::new(&buf))
                    .read_info()
                    .unwrap();
                let info = info.info();
                assert_eq!(info.bit_depth, png::BitDepth::Sixteen);
                assert_eq!(info.srgb, Some(png::SrgbRenderingIntent::Perceptual));
            }
        }
        let eight = Image {
            width: 1,
            height: 1,
            channels: 3,
            data: vec![1, 2, 3],
        };
        let mut buf = Vec::new();
        eight.encode(ImageFormat::Png, &mut buf).unwrap();
        let info = png::Decoder::new(io::Cursor::new(&buf))
            .read_info()
            .unwrap();
        assert_eq!(info.info().srgb, Some(png::SrgbRenderingIntent::Perceptual));
        assert!(eight.encode(ImageFormat::Pfm, &mut Vec::new()).is_err());
        assert_eq!(
            ImageFormat::choose(None, "a.PFM").unwrap(),
            ImageFormat::Pfm
        );
    }

    #[test]
    fn pnm_and_pam_round_trip_through_the_image_crate() {
        let img = Image {
            width: 2,
            height: 1,
            channels: 3,
            data: vec![1, 2, 3, 250, 251, 252],
        };
        for f in [ImageFormat::Ppm, ImageFormat::Pam, ImageFormat::Png] {
            let mut buf = Vec::new();
            img.encode(f, &mut buf).unwrap();
            let back = decode_image(&buf, "x").unwrap();
            assert_eq!(back.get_pixel(1, 0).0, [250, 251, 252, 255], "{f:?}");
        }
    }
}
