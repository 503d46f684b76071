//! Streams and images: `-` for standard input/output, atomic output files,
//! and the three image formats every tool writes (the README's Conventions).

use crate::error::OptionError;
use std::io::{self, BufWriter, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};

/// Checks that `name` can be written, as [`Output::create`] would, and
/// writes nothing: for tools to refuse a missing directory or a terminal
/// before hours of work rather than after.
pub fn check_output(name: &str, binary: bool) -> Result<(), IoError> {
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
    #[error("{}", if input == STDIO { "reading standard input" } else { input })]
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
    /// Flushing the data to a device named as the output.
    WriteDevice,
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
            WriteStep::WriteDevice => "writing the output device".to_string(),
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
/// `tempfile` adds and which means nothing to the user (the message names
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

/// An encoder's error as the I/O error it carries, or as an I/O error that
/// wraps it, of the kind of the I/O error found among its causes: a closed
/// pipe then reads as `BrokenPipe` whichever encoder met it, however deep.
fn image_io_error(e: image::ImageError) -> io::Error {
    match e {
        image::ImageError::IoError(io) => io,
        other => wrapped_io_error(other),
    }
}

/// [`image_io_error`] for the `png` crate's encoder.
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

/// Reads a file that an input names (a stream's pattern, stripe map or
/// table): only a regular file (a scene naming `/dev/zero` or a FIFO is
/// refused, not read forever) of at most [`MAX_NAMED_FILE_BYTES`].
pub fn read_path(path: &Path) -> io::Result<Vec<u8>> {
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
    let too_large = || {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("is larger than the {MAX_NAMED_FILE_BYTES} bytes a named file may have"),
        )
    };
    if meta.len() > MAX_NAMED_FILE_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // Bounded even if the file grows while it is read.
    std::fs::File::open(path)?
        .take(MAX_NAMED_FILE_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_NAMED_FILE_BYTES {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Opens a file to read by name, with a clear error for a directory.
pub fn open_file(name: &str) -> Result<std::fs::File, IoError> {
    let path = Path::new(name);
    let opened = if path.is_dir() {
        Err(is_a_directory())
    } else {
        std::fs::File::open(path)
    };
    opened.map_err(|error| IoError::Read {
        input: name.to_string(),
        error,
    })
}

/// The error for a directory named as an input file.
fn is_a_directory() -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, "is a directory, not a file")
}

/// The most bytes an image file read from the command line may have: a
/// picture of [`MAX_IMAGE_PIXELS`] at 16 bits a channel, RGBA, uncompressed
/// (PAM), is 2 GiB.
pub const MAX_PICTURE_FILE_BYTES: u64 = MAX_IMAGE_PIXELS * 8 + (1 << 16);

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
    /// An image file the `image` crate recognises from its first bytes, at
    /// most [`MAX_PICTURE_FILE_BYTES`].
    Image,
    /// A pattern as `.pat` text or as an image (a background pattern).
    TextOrImage,
}

impl InputKind {
    /// Checks the first bytes; returns the size limit of what follows.
    fn check_start(self, start: &[u8]) -> io::Result<u64> {
        let text = || match start.iter().position(|&b| b == 0) {
            None => Ok(()),
            Some(at) => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("byte 0x00 at offset {at} is not text (a text format is expected)"),
            )),
        };
        let image = || image::guess_format(start).is_ok();
        match self {
            InputKind::Text => text().map(|()| MAX_NAMED_FILE_BYTES),
            InputKind::Stream => text().map(|()| u64::MAX),
            InputKind::Image if image() => Ok(MAX_PICTURE_FILE_BYTES),
            InputKind::Image => Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "not an image this tool can read (it does not start as PNG, JPEG, GIF, BMP, \
                 TIFF, WebP or PNM)",
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
    let read = if name == STDIO {
        read_checked(io::stdin().lock(), kind)
    } else if Path::new(name).is_dir() {
        Err(is_a_directory())
    } else {
        // Any file the user names, FIFOs and `<(...)` included.
        std::fs::File::open(name).and_then(|f| read_checked(f, kind))
    };
    read.map_err(|error| IoError::Read {
        input: name.to_string(),
        error,
    })
}

/// [`read_input`]'s reading: the start, its check, then the rest up to the
/// limit.
fn read_checked(mut r: impl Read, kind: InputKind) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    (&mut r).take(SNIFF_BYTES as u64).read_to_end(&mut bytes)?;
    let limit = kind.check_start(&bytes)?;
    r.take(limit.saturating_sub(bytes.len() as u64).saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("is larger than the {limit} bytes this input may have"),
        ));
    }
    Ok(bytes)
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
    /// A device or pipe named with `-o`, written in place.
    Device(BufWriter<std::fs::File>),
    File {
        tmp: BufWriter<tempfile::NamedTempFile>,
        path: PathBuf,
    },
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
        let mut path = PathBuf::from(name);
        if path.is_dir() {
            return Err(IoError::OutputIsDirectory {
                output: name.to_string(),
            });
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
                // `-o /dev/stdout` or `-o /dev/tty` on a terminal: refused
                // as `-` is, or the picture's bytes would garble the screen.
                if binary && f.is_terminal() {
                    return Err(IoError::BinaryToTerminal);
                }
                return Ok(Output {
                    inner: OutputInner::Device(BufWriter::with_capacity(1 << 16, f)),
                    failed: None,
                });
            }
        }
        if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            // Replace the file the link points to, not the link.
            path =
                std::fs::canonicalize(&path).map_err(write_error(name, WriteStep::ResolveLink))?;
        }
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
        Ok(Output {
            inner: OutputInner::File {
                tmp: BufWriter::with_capacity(1 << 16, tmp),
                path,
            },
            failed: None,
        })
    }

    /// Flushes and, for a file, moves it to its final name.
    pub fn commit(self) -> Result<(), IoError> {
        match self.inner {
            OutputInner::Stdout(mut w) => w.flush().map_err(write_error(STDIO, WriteStep::Write)),
            OutputInner::Device(mut w) => {
                w.flush().map_err(write_error("", WriteStep::WriteDevice))
            }
            OutputInner::File { tmp, path } => {
                let shown = path.display().to_string();
                let tmp_path = tmp.get_ref().path().to_path_buf();
                let tmp = tmp
                    .into_inner()
                    .map_err(|e| e.into_error())
                    .map_err(write_error(shown.clone(), WriteStep::Write))?;
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
            OutputInner::Device(w) => w.write(buf),
            OutputInner::File { tmp, .. } => tmp.write(buf),
        };
        self.noted(result)
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        let result = match &mut self.inner {
            OutputInner::Stdout(w) => w.write_all(buf),
            OutputInner::Device(w) => w.write_all(buf),
            OutputInner::File { tmp, .. } => tmp.write_all(buf),
        };
        self.noted(result)
    }
    fn flush(&mut self) -> io::Result<()> {
        let result = match &mut self.inner {
            OutputInner::Stdout(w) => w.flush(),
            OutputInner::Device(w) => w.flush(),
            OutputInner::File { tmp, .. } => tmp.flush(),
        };
        self.noted(result)
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
}

impl ImageFormat {
    /// The format named by `--format`, else by the output's extension, else PNG.
    pub fn choose(explicit: Option<ImageFormat>, output: &str) -> Result<ImageFormat, OptionError> {
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
            // Grey and bilevel: the tools write colour, and a silent
            // conversion would lose it.
            Some(grey @ ("pgm" | "pbm")) => Err(OptionError::new(
                format!(
                    "{output}: `.{grey}` is netpbm's {} format and the image is in colour: \
                     write .ppm (or .pnm) and convert with {}, or give ",
                    if grey == "pgm" { "greyscale" } else { "black-and-white" },
                    if grey == "pgm" { "ppmtopgm" } else { "ppmtopgm | pamditherbw" },
                ),
                "format",
                "",
            )),
            Some(other) => Err(OptionError::new(
                format!(
                    "{output}: unknown image extension `.{other}`: expected .png, .ppm or .pam, or give "
                ),
                "format",
                "",
            )),
            // `/dev/null`, `out`: PNG, as on standard output.
            None => Ok(ImageFormat::Png),
        }
    }

    /// Whether the format stores an alpha channel: PNG and PAM do, PPM does not.
    pub fn supports_alpha(self) -> bool {
        !matches!(self, ImageFormat::Ppm)
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
        let (wd, ht) = (self.width, self.height);
        match format {
            ImageFormat::Ppm => {
                write!(w, "P6\n{wd} {ht}\n255\n")?;
                if self.channels == 3 {
                    w.write_all(&self.data)?;
                } else {
                    let rgb: Vec<u8> = self
                        .data
                        .chunks_exact(4)
                        .flat_map(|p| [p[0], p[1], p[2]])
                        .collect();
                    w.write_all(&rgb)?;
                }
            }
            ImageFormat::Pam => {
                let (depth, tupl) = if self.channels == 4 {
                    (4, "RGB_ALPHA")
                } else {
                    (3, "RGB")
                };
                write!(
                    w,
                    "P7\nWIDTH {wd}\nHEIGHT {ht}\nDEPTH {depth}\nMAXVAL 255\nTUPLTYPE {tupl}\nENDHDR\n"
                )?;
                w.write_all(&self.data)?;
            }
            ImageFormat::Png => {
                use image::codecs::png::PngEncoder;
                use image::ImageEncoder;
                let color = if self.channels == 4 {
                    image::ExtendedColorType::Rgba8
                } else {
                    image::ExtendedColorType::Rgb8
                };
                PngEncoder::new_with_quality(&mut *w, png.compression, png.filter)
                    .write_image(&self.data, wd, ht, color)
                    .map_err(image_io_error)?;
            }
        }
        Ok(())
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
        let mut out = Output::create(name, true)?;
        self.encode_with(format, png, &mut out)
            .map_err(|e| write_error(name, WriteStep::Write)(out.cause(e)))?;
        out.commit()
    }
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
    /// The embedded ICC colour profile, if any. It is not applied: the
    /// tools take every pixel as sRGB.
    pub icc_profile: Option<Vec<u8>>,
}

/// The error of a file that is not an image this tool reads.
fn not_an_image(name: &str) -> impl Fn(image::ImageError) -> IoError + '_ {
    move |error| IoError::NotAnImage {
        input: name.to_string(),
        error,
    }
}

/// A decoder for `bytes`, its format guessed from the content, before any
/// pixel is decoded (so sizes can be checked first).
fn open_decoder<'a>(bytes: &'a [u8], name: &str) -> Result<impl image::ImageDecoder + 'a, IoError> {
    image::ImageReader::new(io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| not_an_image(name)(image::ImageError::IoError(e)))?
        .into_decoder()
        .map_err(not_an_image(name))
}

/// [`decode_image`] for pictures from cameras and phones: the EXIF
/// orientation (JPEG, PNG's `eXIf`, TIFF, WebP) is applied, and an ICC
/// profile is reported so the caller can warn that it is not.
pub fn decode_photo(bytes: &[u8], name: &str) -> Result<Photo, IoError> {
    use image::ImageDecoder as _;
    let not_an_image = not_an_image(name);
    let mut decoder = open_decoder(bytes, name)?;
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let icc_profile = decoder.icc_profile().ok().flatten();
    let mut img = image::DynamicImage::from_decoder(decoder).map_err(not_an_image)?;
    img.apply_orientation(orientation);
    Ok(Photo {
        image: img.into_rgba8(),
        orientation,
        icc_profile,
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
    let not_an_image = not_an_image(name);
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
    let mut img = image::DynamicImage::from_decoder(decoder).map_err(not_an_image)?;
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

/// Decodes any image the `image` crate reads (PNG, JPEG, GIF, BMP, TIFF, WebP,
/// PNM/PAM) into RGBA8, as stored (no EXIF orientation: see [`decode_photo`]).
pub fn decode_image(bytes: &[u8], name: &str) -> Result<image::RgbaImage, IoError> {
    let img = image::load_from_memory(bytes).map_err(|error| IoError::NotAnImage {
        input: name.to_string(),
        error,
    })?;
    Ok(img.into_rgba8())
}

#[cfg(test)]
mod tests {
    use super::*;

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
