//! Command-line plumbing shared by every tool: the `main` shim, error reporting
//! and exit codes (the README's "Conventions", each man page's EXIT STATUS),
//! the common argument types, and each tool's argument definitions (kept here
//! so the man pages can be generated from them).
//!
//! Each tool module holds `Args` (clap) and `run(Args) -> anyhow::Result<()>`;
//! its file in `src/bin/` is one line that hands both to [`main`].

use crate::error::OptionError;
use crate::texture::place::PlaceError;
use clap::CommandFactory;
use std::fmt;
use std::str::FromStr;

pub mod alloc;
pub mod camera;
pub mod pat_from_image;
pub mod pat_info;
pub mod pat_tile;
pub mod polyfill3;
pub mod progress;
pub mod scene_render;
pub mod scene_stripe;
pub mod scene_texture;

/// A usage error found after clap's own parsing (contradictory flags, values out
/// of range): reported like any error, but the exit status is 2.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for UsageError {}

/// An error whose details were already printed (one line per failed file, say):
/// only the exit status 1 remains to be given.
#[derive(Debug)]
pub struct AlreadyReported;

impl fmt::Display for AlreadyReported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("failed (reported above)")
    }
}
impl std::error::Error for AlreadyReported {}

/// Returns early with a [`UsageError`].
macro_rules! usage_bail {
    ($($arg:tt)*) => {
        return Err(anyhow::Error::new($crate::cli::UsageError(format!($($arg)*))))
    };
}
pub(crate) use usage_bail;

/// `eprintln!` that drops what standard error cannot take (closed, a full
/// device) instead of panicking: the exit status still tells what happened
/// (docs/conventions.md). `eprintln!` panicked, exit 101, with `2>/dev/full`.
macro_rules! eprintln_or_drop {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}
pub(crate) use eprintln_or_drop;

/// `eprint!` as [`eprintln_or_drop!`] does it.
macro_rules! eprint_or_drop {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

/// Exit statuses (each man page's EXIT STATUS).
pub const EXIT_OK: i32 = 0;
pub const EXIT_FAILURE: i32 = 1;
pub const EXIT_USAGE: i32 = 2;

/// The version of every tool's `--json` output (docs/json.md). Scripts
/// check it before reading keys: a key renamed or retyped raises it, a key
/// added does not.
pub const JSON_VERSION: u32 = 1;

/// The top of every `--json` document: `{"version", "tool", KEY: items}`.
/// One object shape for every tool (not a bare array here and an object
/// there), so that a script can tell what it reads and a version can grow.
pub fn json_document(tool: &str, key: &str, items: Vec<serde_json::Value>) -> serde_json::Value {
    let mut doc = json_head(tool);
    doc.insert(key.into(), serde_json::Value::Array(items));
    serde_json::Value::Object(doc)
}

/// The `"version"` and `"tool"` keys that open every `--json` document.
pub fn json_head(tool: &str) -> serde_json::Map<String, serde_json::Value> {
    let mut doc = serde_json::Map::new();
    doc.insert("version".into(), JSON_VERSION.into());
    doc.insert("tool".into(), tool.into());
    doc
}

/// The whole `main` of a tool: parse arguments (clap exits 2 on a usage error),
/// run, print the error chain as `TOOL: error: a: b: c`, exit 0/1/2.
/// A closed output pipe (`| head`) ends the tool quietly with status 0.
pub fn main<A: clap::Parser>(run: fn(A) -> anyhow::Result<()>) -> ! {
    let tool = A::command().get_name().to_string();
    alloc::set_tool_name(&tool);
    clean_up_on_signals();
    widen_pipes();
    let words: Vec<std::ffi::OsString> = std::env::args_os().collect();
    // A negative number is a value, not a cluster of short flags: `--size
    // -16` said "unexpected argument '-1'", not what is wrong with -16 (a
    // hostile-input review).
    let parsed = A::command()
        .allow_negative_numbers(true)
        .try_get_matches_from(values_after_flags(&A::command(), words.clone()))
        .and_then(|mut m| A::from_arg_matches_mut(&mut m));
    let args = match parsed {
        Ok(args) => args,
        Err(e) if e.kind() == clap::error::ErrorKind::InvalidUtf8 => match not_utf8(&words) {
            Some(said) => {
                eprint_or_drop!("{tool}: error: {said}\n");
                std::process::exit(EXIT_USAGE)
            }
            None => exit_usage(&tool, e),
        },
        Err(e) => exit_usage(&tool, e),
    };
    std::process::exit(report(&tool, run(args)))
}

/// The error for the first argument (after the program's name) that is not
/// UTF-8, naming it with its bytes escaped, for clap's "invalid UTF-8 was
/// detected in one or more arguments", which left the user to find which
/// (a hostile-input review). The tools take their file names as text,
/// but for `polyfill3 --pattern`. README, "Limits".
fn not_utf8(words: &[std::ffi::OsString]) -> Option<String> {
    let (i, word) = words
        .iter()
        .enumerate()
        .skip(1)
        .find(|(_, w)| w.to_str().is_none())?;
    Some(format!(
        "argument {i}, {word:?}, is not UTF-8: file names and values are read as UTF-8 text \
         (rename the file, or link it under a UTF-8 name)"
    ))
}

/// `--flag VALUE` joined into `--flag=VALUE` for a flag whose value is
/// optional (`polyfill3 --cull[=FACES]`), when VALUE is one of the flag's
/// possible values: clap takes only the `=` form there, the word after a
/// bare `--cull` being the next argument (the input), so `--cull back`,
/// as scene-render's `--cull` is written and as the shell completions offer
/// it, read a file named `back`. Any other word after the flag stays an
/// argument of its own (`--cull scene.json`); a file named like a value is
/// given as `./back`. Words after `--` are left alone.
///
/// And `--flag VALUE` joined into `--flag=VALUE` for a flag that takes a
/// value when VALUE starts with `-` and a digit (`--size -1x5`): clap
/// read it as short flags and said "unexpected argument '-1'" (a
/// hostile-input review). Negative numbers alone clap takes as values
/// (`allow_negative_numbers`); marking `--size` as taking any hyphen value
/// swallowed the next flag (`--size -o x.png`, a review).
fn values_after_flags(
    command: &clap::Command,
    words: Vec<std::ffi::OsString>,
) -> Vec<std::ffi::OsString> {
    let valued: Vec<String> = command
        .get_arguments()
        .filter(|a| a.get_action().takes_values() && !a.is_require_equals_set())
        .filter_map(|a| Some(format!("--{}", a.get_long()?)))
        .collect();
    let optional: Vec<(String, Vec<String>)> = command
        .get_arguments()
        .filter(|a| a.is_require_equals_set())
        .filter_map(|a| {
            let values = a.get_possible_values();
            let names = values.iter().map(|v| v.get_name().to_string()).collect();
            Some((format!("--{}", a.get_long()?), names))
        })
        .collect();
    let mut out = Vec::with_capacity(words.len());
    let mut words = words.into_iter().peekable();
    while let Some(word) = words.next() {
        if word == "--" {
            out.push(word);
            out.extend(words);
            break;
        }
        let joined = optional
            .iter()
            .find_map(|(flag, values)| {
                let next = words.peek()?.to_str()?;
                (word == flag.as_str() && values.iter().any(|v| v == next))
                    .then(|| format!("{flag}={next}"))
            })
            .or_else(|| {
                let next = words.peek()?.to_str()?;
                let negative = next
                    .strip_prefix('-')?
                    .starts_with(|c: char| c.is_ascii_digit());
                let flag = valued.iter().find(|f| word == f.as_str())?;
                negative.then(|| format!("{flag}={next}"))
            });
        match joined {
            Some(j) => {
                words.next();
                out.push(j.into());
            }
            None => out.push(word),
        }
    }
    out
}

/// On a signal that ends a process ([`ENDING_SIGNALS`]: Ctrl-C, a batch
/// scheduler's pre-emption, a closed terminal, Ctrl-\\), removes the
/// temporary files of outputs being written, then dies of the signal as it
/// would have (status 128 + N to the shell), so a killed run leaves no
/// `.patkit-*.tmp` behind. A thread waits for the signals, so nothing runs
/// inside a signal handler but the flag it sets. A signal the tool was
/// started with ignored (`nohup`, `trap '' HUP`) stays ignored: a handler
/// would have made it kill.
fn clean_up_on_signals() {
    let caught = ENDING_SIGNALS.into_iter().filter(|&sig| !ignored(sig));
    let Ok(mut signals) = signal_hook::iterator::Signals::new(caught) else {
        return; // Without handlers a signal kills at once, as before.
    };
    // A small stack: the thread only removes files. If it cannot start (an
    // address-space limit, `ulimit -v`), the handlers go with `signals`,
    // unregistered, and a signal kills at once, as without them
    // (`std::thread::spawn` panicked there).
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .stack_size(256 << 10)
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                crate::io::remove_unfinished_outputs();
                // Resets the signal to its default action and raises it.
                let _ = signal_hook::low_level::emulate_default_handler(sig);
                std::process::exit(128 + sig);
            }
        });
}

/// The signals whose default action ends the process and that a user or a
/// scheduler sends: SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGUSR1, SIGUSR2,
/// SIGALRM, SIGXCPU (a CPU-time limit). Not SIGXFSZ (a file-size limit:
/// ignored, the write fails and is reported as a full disk is) nor the
/// profilers' SIGPROF and SIGVTALRM; SIGPIPE is taken as a closed pipe.
const ENDING_SIGNALS: [i32; 8] = {
    use signal_hook::consts::*;
    [
        SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGUSR1, SIGUSR2, SIGALRM, SIGXCPU,
    ]
};

/// Whether `sig` was ignored when the tool started.
fn ignored(sig: i32) -> bool {
    // SAFETY: sigaction with a null new action only reads the disposition
    // into `old`, which is zeroed plain data.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        libc::sigaction(sig, std::ptr::null(), &mut old) == 0 && old.sa_sigaction == libc::SIG_IGN
    }
}

/// How many bytes a pipe on standard input or output is widened to hold:
/// Linux's default, 64 KiB, is 16 pages, and a stream of cells through
/// `polyfill3 | scene-render` then makes the writer and the reader take
/// turns sixteen pages at a time. Demo 2's faces at incr 0.25, `polyfill3 |
/// scene-render`, median of 7 taking turns: the cells 1.041 s with 64 KiB,
/// 0.808 with 256 KiB, 0.800 with 1 MiB; `--merge=blocks` 0.452, 0.409,
/// 0.393 (a slow period of the machine; bench/stream_speed.sh prints the
/// pipeline's times). 256 KiB takes nearly all of the gain for a quarter of
/// the pages, which count against a user's pipe budget
/// (`/proc/sys/fs/pipe-user-pages-soft`, 16,384 pages: past it, the user's
/// new pipes get two pages), so 256 such pipes open at once reach it.
#[cfg(target_os = "linux")]
const PIPE_BYTES: libc::c_int = 1 << 18;

/// Widens standard input and standard output to `PIPE_BYTES` where they
/// are pipes (or FIFOs) of the kernel's default size, 16 pages, when that is
/// less: a pipe someone sized, narrower or wider, is left as it is. The
/// pipe's pages are taken as data fills it, not at once; where the request
/// is refused (past the user's pipe budget, an older kernel) the pipe keeps
/// its size, with nothing else changed.
fn widen_pipes() {
    #[cfg(target_os = "linux")]
    for fd in [0, 1] {
        // SAFETY: sysconf and F_GETPIPE_SZ only read; fstat writes only into
        // `st`; F_SETPIPE_SZ changes only the capacity of a pipe this process
        // already holds, never its data.
        unsafe {
            let default = 16 * libc::sysconf(libc::_SC_PAGESIZE);
            let mut st: libc::stat = std::mem::zeroed();
            if libc::fstat(fd, &mut st) == 0
                && st.st_mode & libc::S_IFMT == libc::S_IFIFO
                && libc::fcntl(fd, libc::F_GETPIPE_SZ) as libc::c_long == default
                && default < PIPE_BYTES as libc::c_long
            {
                libc::fcntl(fd, libc::F_SETPIPE_SZ, PIPE_BYTES);
            }
        }
    }
}

/// Prints clap's verdict: `--help` and `--version` to stdout with status 0
/// (1 if standard output cannot take them: `--help > /dev/full` said
/// nothing and exited 0, a hostile-input review; a closed pipe is no
/// error, as for every output), anything else as `TOOL: error: ...` with
/// status 2.
fn exit_usage(tool: &str, e: clap::Error) -> ! {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            use std::io::Write as _;
            if let Some(why) = stdout_unusable() {
                // Rust's standard output takes a closed descriptor's writes
                // as done.
                eprint_or_drop!("{tool}: error: standard output is {why}\n");
                std::process::exit(EXIT_FAILURE)
            }
            let printed = e.print().and_then(|()| std::io::stdout().flush());
            match printed {
                Err(err) if err.kind() != std::io::ErrorKind::BrokenPipe => {
                    eprint_or_drop!("{tool}: error: writing standard output: {err}\n");
                    std::process::exit(EXIT_FAILURE)
                }
                _ => std::process::exit(EXIT_OK),
            }
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
        _ => {
            let text = with_arguments_on_one_line(e.render().to_string());
            let text = text.strip_prefix("error: ").unwrap_or(&text);
            eprint_or_drop!("{tool}: error: {text}");
            std::process::exit(EXIT_USAGE)
        }
    }
}

/// Clap's error text with every argument (or `--flag=value`'s value) that
/// [`crate::text::one_line`] would escape written as it writes it: clap's message spans lines of its own (usage, a tip), so it cannot
/// be put on one line whole, but a newline in an echoed value split the
/// line that names it.
fn with_arguments_on_one_line(mut text: String) -> String {
    let args: Vec<String> = std::env::args_os()
        .skip(1)
        .filter_map(|a| a.into_string().ok())
        .collect();
    for arg in &args {
        let value = arg.split_once('=').map(|(_, v)| v);
        for echoed in [Some(arg.as_str()), value].into_iter().flatten() {
            if let std::borrow::Cow::Owned(escaped) = crate::text::one_line(echoed) {
                text = text.replace(echoed, &escaped);
            }
        }
    }
    text
}

/// Maps a result to an exit status, printing the error if there is one.
pub fn report(tool: &str, result: anyhow::Result<()>) -> i32 {
    match result {
        Ok(()) => EXIT_OK,
        Err(e) if is_broken_pipe(&e) => EXIT_OK,
        Err(e) if e.downcast_ref::<AlreadyReported>().is_some() => EXIT_FAILURE,
        Err(e) => {
            print_error(tool, &e);
            if is_usage_error(&e) {
                EXIT_USAGE
            } else {
                EXIT_FAILURE
            }
        }
    }
}

/// Prints an error as `TOOL: error: ...` on one line, the form every tool
/// uses: by [`report`] as a run ends, and by `pat-info` for each file it
/// cannot read before it goes on to the next.
pub fn print_error(tool: &str, e: &anyhow::Error) {
    let message = in_flag_words(e);
    eprintln_or_drop!(
        "{tool}: error: {}",
        crate::text::one_line(&crate::text::shorten_long_numbers(&message))
    );
}

/// Whether an error is the user's flags' fault (status 2): a
/// [`UsageError`], or an output named by the empty string (`-o ''`), which
/// the library refuses as it opens the output (status 1 before a
/// hostile-input review, though a bad flag value).
fn is_usage_error(e: &anyhow::Error) -> bool {
    e.chain().any(|layer| {
        layer.is::<UsageError>()
            || matches!(
                layer.downcast_ref::<crate::io::IoError>(),
                Some(crate::io::IoError::EmptyOutputName)
            )
    })
}

/// The error chain as `a: b: c` (anyhow's `{:#}`), with every library
/// [`OptionError`] naming its option by the flag that sets it: the field
/// `max_polygons` is `--max-polygons`. A layer whose text already ends
/// the line is left out: decoders (the `image` crate's) print their cause
/// in their own message and give it again as their source.
fn in_flag_words(e: &anyhow::Error) -> String {
    const REPEAT_MIN_CHARS: usize = 12;
    let mut line = String::new();
    for layer in e.chain() {
        let text = match option_error(layer) {
            Some(o) => o.worded(&format!("--{}", o.option.replace('_', "-"))),
            None => layer.to_string(),
        };
        let said = line.trim_end_matches(['.', ' ']);
        let cause = text.trim_end_matches(['.', ' ']);
        // (Short causes, a number or a word, may end a message by chance.)
        if cause.len() >= REPEAT_MIN_CHARS && said.ends_with(cause) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

/// The [`OptionError`] a chain layer is, or carries as its whole message
/// (inside an I/O error, or a pattern that cannot be placed).
fn option_error<'a>(layer: &'a (dyn std::error::Error + 'static)) -> Option<&'a OptionError> {
    if let Some(o) = layer.downcast_ref::<OptionError>() {
        return Some(o);
    }
    if let Some(PlaceError::Compose(o)) = layer.downcast_ref::<PlaceError>() {
        return Some(o);
    }
    layer
        .downcast_ref::<std::io::Error>()
        .and_then(|io| io.get_ref())
        .and_then(|inner| inner.downcast_ref::<OptionError>())
}

/// The C library's `pow`, replaced in the tools by the pure-Rust `libm`
/// one: indicatif's ETA estimate calls `f64::powf`, which would import `pow`
/// from the host's C library. Nothing on the pixel path calls it (that uses
/// [`crate::math`]), but the tools import no maths from the C library at all,
/// so no host can change a byte they print (test
/// `binaries_import_no_maths_from_the_c_library`).
#[no_mangle]
pub extern "C" fn pow(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// How standard input and output stood when the tool started: usable, or
/// why not. Rust's runtime opens /dev/null in place of a closed one before
/// `main`, after which a closed output and `> /dev/null` cannot be told
/// apart, and it takes a descriptor's EBADF as the end of the input or a
/// write done, so one open the wrong way (`tool 0>file`, `tool 1<file`)
/// read as empty or swallowed the output with status 0 (a hostile-input
/// review). So this is read earlier, by a constructor the loader runs
/// (Linux).
static STDIN_STATE: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(USABLE);
/// The same for standard output.
static STDOUT_STATE: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(USABLE);
/// The same for standard error.
static STDERR_STATE: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(USABLE);
/// [`STDIN_STATE`]'s, [`STDOUT_STATE`]'s and [`STDERR_STATE`]'s values.
const USABLE: u8 = 0;
const CLOSED: u8 = 1;
const WRONG_WAY: u8 = 2;

#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array"]
static NOTE_CLOSED_STDIO: extern "C" fn() = {
    extern "C" fn note() {
        let state = |fd, wrong_way| {
            // SAFETY: fcntl(F_GETFL) only reads the descriptor's flags.
            let flags = unsafe { libc::fcntl(fd, libc::F_GETFL) };
            match flags {
                -1 => CLOSED,
                f if f & libc::O_ACCMODE == wrong_way => WRONG_WAY,
                _ => USABLE,
            }
        };
        let relaxed = std::sync::atomic::Ordering::Relaxed;
        STDIN_STATE.store(state(0, libc::O_WRONLY), relaxed);
        STDOUT_STATE.store(state(1, libc::O_RDONLY), relaxed);
        STDERR_STATE.store(state(2, libc::O_RDONLY), relaxed);
    }
    note
};

/// Why standard input cannot be read, if it cannot.
fn stdin_unusable() -> Option<&'static str> {
    unusable(&STDIN_STATE, "open for writing only")
}

/// Why a standard stream whose state is `state` cannot be used, if it
/// cannot; `wrong_way` says how it was opened the wrong way.
fn unusable(state: &std::sync::atomic::AtomicU8, wrong_way: &'static str) -> Option<&'static str> {
    match state.load(std::sync::atomic::Ordering::Relaxed) {
        CLOSED => Some("closed"),
        WRONG_WAY => Some(wrong_way),
        _ => None,
    }
}

/// Why standard output cannot be written, if it cannot.
fn stdout_unusable() -> Option<&'static str> {
    unusable(&STDOUT_STATE, "open for reading only")
}

/// Writes a machine-read report asked for on standard error (polyfill3's
/// `--json`, scene-render's `--compare` report when the image is on
/// standard output), or an error if it could not be written. Diagnostics
/// for people (warnings, `--timings`, `pat-from-image --report`) are
/// dropped when standard error cannot take them (`eprintln_or_drop!`), but
/// such a report is an output, captured as `2> summary.json`: `2>/dev/full`
/// or `2>&-` lost it with status 0 (a hostile-input review). The error
/// itself has nowhere to go then, but the exit status says it. A closed
/// pipe is a reader that wanted no more, as on standard output: no error.
pub fn write_report_to_stderr(text: &str) -> anyhow::Result<()> {
    if let Some(why) = unusable(&STDERR_STATE, "open for reading only") {
        anyhow::bail!("standard error is {why}: the report could not be written");
    }
    use std::io::Write as _;
    let mut err = std::io::stderr().lock();
    match err.write_all(text.as_bytes()).and_then(|()| err.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        written => anyhow::Context::context(written, "writing the report to standard error"),
    }
}

/// An error unless standard output can be written: output to a closed
/// standard output would vanish while the tool reported success. A tool
/// calls it only when it will write there. `hint` ends the message with
/// the way round it in the tool's own terms (`use -o FILE` where there is
/// an -o): the one message for all suggested `-o FILE` to pat-info, which
/// has none.
pub fn check_stdout(hint: &str) -> anyhow::Result<()> {
    if let Some(why) = stdout_unusable() {
        anyhow::bail!("standard output is {why}: nothing could be written ({hint})");
    }
    Ok(())
}

/// [`check_stdout`]'s hint for a tool whose output may go to a file.
pub const USE_OUTPUT_FILE: &str = "use -o FILE";

/// When a tool's coloured output (`pat-info --preview`) uses colour
/// (<https://no-color.org>).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColorWhen {
    /// When standard output is a terminal and NO_COLOR is unset or empty.
    #[default]
    Auto,
    /// Always, even into a pipe and whatever NO_COLOR says.
    Always,
    /// Never.
    Never,
}

impl ColorWhen {
    /// Whether output to standard output gets colour.
    pub fn stdout_wants_colour(self) -> bool {
        use std::io::IsTerminal;
        match self {
            ColorWhen::Always => true,
            ColorWhen::Never => false,
            ColorWhen::Auto => {
                std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
                    && std::io::stdout().is_terminal()
            }
        }
    }
}

/// Prints a warning as `TOOL: warning: ...`, the form every tool uses.
pub fn warn(tool: &str, message: impl fmt::Display) {
    let message = message.to_string();
    eprintln_or_drop!(
        "{tool}: warning: {}",
        crate::text::one_line(&crate::text::shorten_long_numbers(&message))
    );
}

/// Whether `e` is a write to a closed pipe, which is no error
/// (docs/conventions.md): an I/O error of kind `BrokenPipe` anywhere in the
/// chain, or inside the wrappers that show an I/O error as their own text
/// rather than as their source. `polyfill3`'s
/// [`PartitionError::Write`](crate::scene::PartitionError::Write) is one:
/// a pipe closed while the end of the output (under its last batch) was
/// written failed with status 1 and "Broken pipe (os error 32)"
/// (`polyfill3_into_a_closed_pipe_exits_0_quietly_at_every_size`).
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    use crate::scene::PartitionError;
    use std::io::ErrorKind::BrokenPipe;
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == BrokenPipe)
            || c.downcast_ref::<PartitionError>()
                .is_some_and(|p| matches!(p, PartitionError::Write(io) if io.kind() == BrokenPipe))
            || c.downcast_ref::<serde_json::Error>()
                .is_some_and(|j| j.io_error_kind() == Some(BrokenPipe))
            || c.downcast_ref::<image::ImageError>().is_some_and(
                |ie| matches!(ie, image::ImageError::IoError(io) if io.kind() == BrokenPipe),
            )
    })
}

/// Refuses, before anything is read: an input named by the empty string, a
/// bad argument like `-o ''` (status 2; it was status 1, found when opened,
/// and `pat-info '' a.pat` reported it among the files); two inputs that
/// both name standard input (`-`): it can be read once, and the second
/// reader would silently get nothing (`--camera -` with the stream on `-`
/// rendered an empty scene with exit status 0); and an input on a standard
/// input that was closed when the tool started (`tool <&-`), or open for
/// writing only (`tool 0>>file`; status 1).
/// `inputs` are (what the user wrote, the value given).
pub fn check_inputs(inputs: &[(&str, Option<&str>)]) -> anyhow::Result<()> {
    if let Some((what, _)) = inputs.iter().find(|(_, v)| *v == Some("")) {
        usage_bail!("{what}: an empty input name: expected a file name, or - for standard input");
    }
    let dashes: Vec<&str> = inputs
        .iter()
        .filter(|(_, v)| *v == Some(crate::io::STDIO))
        .map(|(what, _)| *what)
        .collect();
    if let ([what, ..], Some(why)) = (&dashes[..], stdin_unusable()) {
        anyhow::bail!(
            "{what} is standard input, which is {why}: nothing could be read (give a file)"
        );
    }
    if let [first, second, ..] = dashes[..] {
        usage_bail!(
            "{first} and {second} both name `-`: standard input can be read only once; \
             give one of them a file"
        );
    }
    // `--camera /dev/stdin` beside a stream on `-`: the camera took all of
    // a pipe and the stream rendered as empty, with status 0.
    let stdins: Vec<(&str, &str)> = (inputs.iter())
        .filter_map(|&(what, v)| Some((what, v.filter(|v| is_stdin(v))?)))
        .collect();
    if let [(first, a), (second, b), ..] = stdins[..] {
        usage_bail!(
            "{first} {a} and {second} {b} both name standard input: it can be read only once; \
             give one of them a file"
        );
    }
    Ok(())
}

/// Whether an input name is standard input: `-`, or one of the names Linux
/// gives it (opening one reads the same pipe as `-`).
fn is_stdin(name: &str) -> bool {
    name == crate::io::STDIO || STDIN_NAMES.contains(&name)
}

/// The names of standard input and output besides `-`.
const STDIN_NAMES: [&str; 3] = ["/dev/stdin", "/dev/fd/0", "/proc/self/fd/0"];
const STDOUT_NAMES: [&str; 3] = ["/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"];

/// The format of an image output: `--format`, else the extension, else PNG
/// ([`crate::io::ImageFormat::choose`]). An extension it does not write is a
/// usage error (exit status 2), like any other bad flag value.
pub fn output_format(
    explicit: Option<crate::io::ImageFormat>,
    output: &str,
) -> anyhow::Result<crate::io::ImageFormat> {
    crate::io::ImageFormat::choose(explicit, output)
        .map_err(|e| UsageError(e.worded("--format")).into())
}

/// [`output_format`] for an image of 8-bit colours
/// ([`crate::io::ImageFormat::choose_8bit`]): `.pfm` is a usage error.
pub fn output_format_8bit(
    explicit: Option<crate::io::ImageFormat>,
    output: &str,
) -> anyhow::Result<crate::io::ImageFormat> {
    crate::io::ImageFormat::choose_8bit(explicit, output)
        .map_err(|e| UsageError(e.worded("--format")).into())
}

/// `--threads N`, shared by the tools that run a pool of workers
/// (`#[command(flatten)]`), so the flag reads and behaves the same in each.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct ThreadArgs {
    /// Worker threads (default: all cores). The output is identical for any N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=MAX_THREADS as i64))]
    pub threads: Option<u32>,
}

/// The most worker threads `--threads` (or `RAYON_NUM_THREADS`) may ask
/// for: far past any machine's cores, short of what starting them costs.
pub const MAX_THREADS: u64 = 1024;

impl ThreadArgs {
    /// Runs `job` in a pool of that many workers (rayon's, which the library
    /// uses wherever it works in parallel).
    pub fn install<R: Send>(self, job: impl FnOnce() -> R + Send) -> anyhow::Result<R> {
        let mut pool = rayon::ThreadPoolBuilder::new();
        if let Some(n) = self.threads {
            pool = pool.num_threads(n as usize);
        } else {
            // rayon's own variables, which the pool reads when --threads is
            // not given (RAYON_RS_NUM_CPUS the older name): a million took
            // 17 s of thread starts before "Resource temporarily
            // unavailable", naming nothing, and rayon passes over what is
            // not a number (`abc`, `-1`, ` 1 `: it does not trim) in silence
            // (hostile-input reviews). 0 is rayon's "one per core".
            for var in ["RAYON_NUM_THREADS", "RAYON_RS_NUM_CPUS"] {
                let Some(v) = std::env::var_os(var).filter(|v| !v.is_empty()) else {
                    continue;
                };
                let text = v.to_string_lossy();
                let said = match text.parse::<u64>() {
                    Ok(n) if n <= MAX_THREADS => continue,
                    Ok(n) => format!("{var}={n}: at most {MAX_THREADS} worker threads"),
                    Err(_) => format!(
                        "{var}={text}: expected a number of worker threads, 0 for one per core"
                    ),
                };
                return Err(UsageError(format!("{said} (--threads N overrides it)")).into());
            }
        }
        let pool = anyhow::Context::context(pool.build(), "starting worker threads")?;
        Ok(pool.install(job))
    }
}

/// `--size N` or `--size NxN` for a square pattern side, as the other tools
/// write sizes (`pat-tile --pat --size 32x32`).
pub fn parse_pattern_side(s: &str) -> Result<u64, String> {
    let number = |t: &str| {
        t.trim()
            .parse::<u64>()
            .map_err(|_| format!("invalid size `{s}`: expected N or NxN, e.g. 64 or 64x64"))
    };
    match s.split_once(['x', 'X']) {
        None => number(s),
        Some((w, h)) => {
            let (w, h) = (number(w)?, number(h)?);
            if w != h {
                return Err(format!("invalid size `{s}`: patterns are square (NxN)"));
            }
            Ok(w)
        }
    }
}

/// `--size WxH`: an image size, checked against the image limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl FromStr for Size {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || format!("invalid size `{s}`: expected WxH, e.g. 1024x768");
        let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
        // A side of digits past u32 is too large, not malformed.
        let side = |t: &str| {
            let t = t.trim();
            t.parse::<u32>().map_err(|_| {
                if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) {
                    format!(
                        "image size {s} is too large: each side at most {}",
                        crate::io::MAX_IMAGE_SIDE
                    )
                } else {
                    bad()
                }
            })
        };
        let (w, h) = (side(w)?, side(h)?);
        crate::io::Image::check_size(w, h).map_err(|e| e.to_string())?;
        Ok(Size {
            width: w,
            height: h,
        })
    }
}

impl fmt::Display for Size {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// A pair of integers `A,B` (texel coordinates, offsets).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IntPair(pub i64, pub i64);

impl FromStr for IntPair {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || format!("invalid pair `{s}`: expected two integers `A,B`");
        let (a, b) = s.split_once(',').ok_or_else(bad)?;
        Ok(IntPair(
            a.trim().parse().map_err(|_| bad())?,
            b.trim().parse().map_err(|_| bad())?,
        ))
    }
}

/// Every tool's clap command, for man pages and completion generation.
pub fn commands() -> Vec<clap::Command> {
    vec![
        pat_from_image::Args::command(),
        pat_info::Args::command(),
        pat_tile::Args::command(),
        polyfill3::Args::command(),
        scene_render::Args::command(),
    ]
}

/// Renders one tool's man page (roff) from its argument definitions, then
/// the sections clap_mangen does not make: EXIT STATUS, ENVIRONMENT, FILES
/// and SEE ALSO ([`man_sections`]).
pub fn man_page(cmd: clap::Command) -> String {
    let name = cmd.get_name().to_string();
    let mut out = Vec::new();
    clap_mangen::Man::new(cmd)
        .render(&mut out)
        .expect("rendering to a Vec cannot fail");
    let mut page = String::from_utf8(out).expect("clap_mangen writes UTF-8");
    page.push_str(&man_sections(&name));
    page
}

/// The section-5 man pages of the formats the tools read and write (made
/// from their `docs/` pages, installed by `make install`), which every
/// tool's SEE ALSO names.
pub const FORMAT_PAGES: [&str; 5] = [
    "pat",
    "patkit-stream",
    "patkit-camera",
    "patkit-stripe",
    "patkit-json",
];

/// The man page sections of `tool` that its arguments do not give, written
/// here beside the code whose behaviour they state: the exit statuses of
/// [`main`], [`report`] and the signal handler, the variables the tools
/// read, the files each reads and writes, and the pages to read next. An
/// installed tool's user has these pages only, so they cite man pages,
/// never a file of the repository.
pub fn man_sections(tool: &str) -> String {
    let mut s = String::from(".SH \"EXIT STATUS\"\n");
    let mut item = |tag: &str, text: &str| {
        s.push_str(&format!(".TP\n{tag}\n{text}\n"));
    };
    let ok = match tool {
        "pat-info" => "Success: every file was read and is valid. A closed output pipe (| head) also ends the tool quietly with status 0.",
        _ => "Success. A closed output pipe (| head) also ends the tool quietly with status 0.",
    };
    item("0", ok);
    let failure = match tool {
        "pat-info" => "Failure: a file could not be read or is invalid (each such file is reported on standard error, the others are still examined), or an output could not be written, or memory ran out.",
        _ => "Failure: an input could not be read or is invalid, an output could not be written, or memory ran out. The error is printed as TOOL: error: FILE:LINE: ... and no output file is left behind.",
    };
    item("1", failure);
    item(
        "2",
        "Usage error: an unknown flag, a bad flag value, or flags that contradict each other.",
    );
    item(
        "128 + N",
        "Killed by signal N: SIGHUP (129), SIGINT (130), SIGQUIT (131), SIGTERM (143), SIGUSR1, SIGUSR2, SIGALRM or SIGXCPU. The output being written is removed first, then the tool dies of the signal. A signal ignored when the tool started (nohup) stays ignored.",
    );
    s.push_str(".SH ENVIRONMENT\n");
    let mut item = |tag: &str, text: &str| {
        s.push_str(&format!(".TP\n.B {tag}\n{text}\n"));
    };
    if tool == "pat-info" {
        item(
            "NO_COLOR",
            "When set and not empty, --color auto draws the --preview without colour (https://no-color.org).",
        );
    }
    if matches!(tool, "pat-from-image" | "polyfill3" | "scene-render") {
        item(
            "TERM",
            "When dumb, no progress bar is drawn (it is drawn on standard error only when that is a terminal).",
        );
    }
    match tool {
        "scene-render" => item(
            "RAYON_NUM_THREADS",
            "The number of worker threads when --threads is not given (default, or 0: one per core; at most 1024, and anything but a number is refused). The output does not depend on it.",
        ),
        "pat-from-image" => item(
            "RAYON_NUM_THREADS",
            "The number of worker threads of the palette search (default, or 0: one per core; at most 1024, and anything but a number is refused). The output does not depend on it.",
        ),
        "polyfill3" => item(
            "RAYON_NUM_THREADS",
            "The number of worker threads that format the output when --threads is not given (default, or 0: one per core; at most 1024, and anything but a number is refused). The output does not depend on it.",
        ),
        _ => {}
    }
    s.push_str(".PP\nNo other variable changes what the tool does.\n");
    s.push_str(".SH FILES\n");
    let files = match tool {
        "pat-from-image" => "Reads a picture (PNG, JPEG, GIF, BMP, TIFF, WebP, PNM) and, with --palette, a .pat file (pat(5)) or a list of colours; writes a .pat file (pat(5)) or with --stripe a modulation map (patkit-stripe(5)).",
        "pat-info" => "Reads .pat files (pat(5)) and modulation maps (patkit-stripe(5)); with --record, a polygon stream (patkit-stream(5)) and the stripe files it names. --json prints the report of patkit-json(5).",
        "pat-tile" => "Reads a .pat file (pat(5)); writes a PNG, PPM or PAM image, or with --pat a .pat file.",
        "polyfill3" => "Reads a polygon stream (patkit-stream(5)), the pattern and stripe files its records name (relative to the stream's directory), --pattern (pat(5)) and --camera (patkit-camera(5)); writes a polygon stream and, with --depfile, a make rule. --json prints the summary of patkit-json(5).",
        _ => "Reads a polygon stream (patkit-stream(5)), the pattern, image and stripe files its records name (pat(5), patkit-stripe(5); relative to the stream's directory), --camera (patkit-camera(5)), --background-pattern and --compare and --image images (PFM too); writes a PNG, PPM or PAM image in 8- or 16-bit sRGB or a PFM in linear light (or frames, or an animated PNG) and, with --depfile, a make rule. --json prints the reports of patkit-json(5).",
    };
    s.push_str(&format!(".PP\n{files}\n"));
    if tool != "pat-info" {
        s.push_str(".PP\nAn output file is written to a temporary file .patkit-*.tmp in its directory and renamed into place when complete.\n");
    }
    let mut see: Vec<String> = commands()
        .iter()
        .map(|c| c.get_name().to_string())
        .filter(|n| n != tool)
        .map(|n| format!("{n}(1)"))
        .collect();
    see.extend(FORMAT_PAGES.map(|p| format!("{p}(5)")));
    s.push_str(&format!(".SH \"SEE ALSO\"\n{}\n", see.join(", ")));
    // In roff a bare `-` is a hyphen; flags and names need the minus.
    s.replace('-', "\\-")
}

/// The shells completion scripts are made for, with where each script of
/// `tool` goes under an install prefix (the places bash-completion, zsh's
/// site-functions and fish's vendor directory look).
pub const COMPLETION_SHELLS: [(clap_complete::Shell, &str); 3] = [
    (
        clap_complete::Shell::Bash,
        "share/bash-completion/completions/{}",
    ),
    (clap_complete::Shell::Zsh, "share/zsh/site-functions/_{}"),
    (
        clap_complete::Shell::Fish,
        "share/fish/vendor_completions.d/{}.fish",
    ),
];

/// One tool's completion script for `shell`, from the same argument
/// definitions as `--help` and the man page.
pub fn completion(mut cmd: clap::Command, shell: clap_complete::Shell) -> String {
    let name = cmd.get_name().to_string();
    let mut out = Vec::new();
    clap_complete::generate(shell, &mut cmd, name, &mut out);
    String::from_utf8(out).expect("clap_complete writes UTF-8")
}

/// `--depfile FILE`: writes the make rule `TARGETS: DEPS` of every file a run
/// read (as `cc -MD` does), and an empty rule for each dependency (as `-MP`
/// adds) so that a deleted pattern makes the target out of date instead of
/// stopping make. Names are spelled as GNU make reads them back
/// ([`make_escaped`]); a name make cannot spell ([`make_cannot_name`]: a
/// newline, `;`, `=`, ...) is an error before anything is written, since the
/// rule is written before the outputs and a rule that names other files (or
/// stops make) would make them look up to date. Written atomically, like
/// every output.
pub fn write_depfile(depfile: &str, targets: &[String], deps: &[String]) -> anyhow::Result<()> {
    use anyhow::Context as _;
    use std::io::Write as _;
    let mut seen = std::collections::HashSet::new();
    let deps: Vec<&String> = deps
        .iter()
        .filter(|d| d.as_str() != crate::io::STDIO && seen.insert(d.as_str()))
        .collect();
    for name in targets.iter().chain(deps.iter().copied()) {
        if let Some(why) = make_cannot_name(name) {
            anyhow::bail!("--depfile {depfile}: make cannot name the file {name:?}: {why}");
        }
    }
    let mut text = targets
        .iter()
        .map(|t| make_escaped(t, true))
        .collect::<Vec<_>>()
        .join(" ");
    text.push(':');
    for d in &deps {
        text.push_str(" \\\n  ");
        text.push_str(&make_escaped(d, false));
    }
    text.push('\n');
    for d in &deps {
        text.push_str(&format!("\n{}:\n", make_escaped(d, true)));
    }
    let mut out = crate::io::Output::create(depfile, false)?;
    out.write_all(text.as_bytes())
        .with_context(|| format!("writing {depfile}"))?;
    Ok(out.commit()?)
}

/// Why GNU make (4.x) cannot read `name` back from a rule as that file, if
/// it cannot; each case was checked by running make on the rule:
/// - a newline ends the rule, and a tab cannot be escaped in a target;
/// - `;` starts the recipe and `=` makes the line a variable assignment,
///   with no escape for either;
/// - a final `\` escapes the space, `:` or newline that follows it;
/// - a leading `~` is a home directory, `NAME(MEMBER)` an archive member,
///   a lone `|` the order-only separator, `define` and `undefine` start a
///   definition, and `.NAME` in capitals may be a special target
///   (`.SILENT:` would silence every recipe).
pub fn make_cannot_name(name: &str) -> Option<&'static str> {
    let archive_member = name.ends_with(')')
        && name
            .find('(')
            .is_some_and(|open| open > 0 && open + 2 < name.len());
    let special = name.len() > 1
        && name.starts_with('.')
        && name[1..]
            .bytes()
            .all(|b| b.is_ascii_uppercase() || b == b'_');
    Some(if name.contains('\n') {
        "a newline ends a make rule"
    } else if name.contains('\t') {
        "make cannot escape a tab in a target"
    } else if name.contains(';') {
        "make reads what follows ';' as a recipe"
    } else if name.contains('=') {
        "make reads a rule with '=' as a variable assignment"
    } else if name.ends_with('\\') {
        "make reads a final backslash as escaping what follows it"
    } else if name.starts_with('~') {
        "make reads a leading '~' as a home directory"
    } else if archive_member {
        "make reads NAME(MEMBER) as a member of an archive"
    } else if name == "|" {
        "make reads a lone '|' as the order-only separator"
    } else if name == "define" || name == "undefine" {
        "make reads it as a directive"
    } else if special {
        "make may read it as a special target"
    } else {
        return None;
    })
}

/// `name` spelled for a make rule, as GNU make reads it back (what `gcc
/// -MD` does, and more): `$` is `$$`; a space, `#` and `:` (in a target, also
/// `%`, which would make a pattern rule) take a backslash, and the
/// backslashes just before them are doubled; other backslashes are
/// literal to make (`back\slash.pat` is written as it is). make expands
/// `*`, `?` and `[` as wildcards (`a*.pat` would name `ab.pat` too): in a
/// name with one of them, each of them and each backslash takes a
/// backslash first, which the wildcard expansion removes. Names
/// [`make_cannot_name`] refuses have no spelling.
pub fn make_escaped(name: &str, target: bool) -> String {
    let wild = name.contains(['*', '?', '[']);
    let mut glob = String::with_capacity(name.len());
    for c in name.chars() {
        if wild && matches!(c, '\\' | '*' | '?' | '[') {
            glob.push('\\');
        }
        glob.push(c);
    }
    let mut out = String::with_capacity(glob.len());
    let mut backslashes = 0;
    for c in glob.chars() {
        if c == '\\' {
            backslashes += 1;
            continue;
        }
        let escape = matches!(c, ' ' | '#' | ':') || (target && c == '%');
        let run = if escape {
            2 * backslashes + 1
        } else {
            backslashes
        };
        out.extend(std::iter::repeat_n('\\', run));
        backslashes = 0;
        match c {
            '$' => out.push_str("$$"),
            _ => out.push(c),
        }
    }
    out.extend(std::iter::repeat_n('\\', backslashes));
    out
}

/// Where a written output named `name` lands: the directory entry it
/// replaces, its links followed ([`crate::io::output_target`]) and its
/// directory resolved, so that `a.png`, `./a.png`, `d/../a.png` and a link
/// to `a.png` land in one place; standard output for `-` and its names in
/// `/dev` and `/proc`. `None` where that cannot be found (a directory that
/// does not exist, a name ending in `/`: writing there fails anyway).
pub fn destination(name: &str) -> Option<std::path::PathBuf> {
    let name = stdio_file(name, true);
    if STDOUT_NAMES.contains(&name) {
        return Some(std::path::PathBuf::from("/dev/stdout"));
    }
    if name.ends_with('/') {
        return None;
    }
    let path = crate::io::output_target(std::path::Path::new(name)).ok()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(path.file_name()?))
}

/// A usage error if two outputs of the command line (`(flag, name)`) are
/// one file, as written or once resolved ([`destination`]): the one
/// written last would replace the other (`--depfile ./a.png -o a.png` left
/// the image where the make rule was meant to be, with status 0).
pub fn refuse_shared_outputs(outputs: &[(&str, Option<&str>)]) -> anyhow::Result<()> {
    let places: Vec<_> = (outputs.iter())
        .map(|&(_, name)| name.and_then(destination))
        .collect();
    for (k, &(flag, name)) in outputs.iter().enumerate() {
        for (j, &(earlier, other)) in outputs[..k].iter().enumerate() {
            let (Some(name), Some(other)) = (name, other) else {
                continue;
            };
            if name == other {
                usage_bail!(
                    "{flag} {name}: the same file as {earlier}: each output needs its own name"
                );
            }
            if places[k].is_some() && places[k] == places[j] {
                usage_bail!(
                    "{flag} {name}: the same file as {earlier} {other}: each output needs its \
                     own name"
                );
            }
        }
    }
    Ok(())
}

/// Whether the paths `a` and `b` name one existing regular file (the same
/// device and inode, through links): `./a`, `a` and a link to it do.
/// `-`, a path that does not exist yet and anything not a regular file
/// (`/dev/null`, a pipe, a terminal) is never the same file, since writing
/// it destroys nothing that is read.
pub fn same_file(a: &str, b: &str) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let file = |p: &str| {
            (p != crate::io::STDIO)
                .then(|| std::fs::metadata(p).ok())
                .flatten()
                .filter(|m| m.is_file())
        };
        matches!((file(a), file(b)), (Some(x), Some(y)) if x.dev() == y.dev() && x.ino() == y.ino())
    }
    #[cfg(not(unix))]
    {
        let _ = (a, b);
        false
    }
}

/// The file an input or output name stands for: `-` is standard input or
/// output, which may be a regular file (`tool - -o x < x`).
fn stdio_file(name: &str, output: bool) -> &str {
    match (name, output) {
        (crate::io::STDIO, false) => "/dev/stdin",
        (crate::io::STDIO, true) => "/dev/stdout",
        _ => name,
    }
}

/// A usage error (status 2) if an output of the command line (`(flag,
/// path)`) is the same file as one of its inputs ([`same_file`]; `-` as
/// the file standard input or output is): the output would be written in
/// the input's place once the input was read (`scene-render scene.json -o
/// scene.json` replaced the scene with a PNG, `--diff ref.png --compare
/// ref.png` the reference with the difference).
pub fn refuse_replacing_inputs(
    outputs: &[(&str, Option<&str>)],
    inputs: &[(&str, Option<&str>)],
) -> anyhow::Result<()> {
    for &(out_flag, out) in outputs {
        for &(in_flag, input) in inputs {
            if let (Some(out), Some(input)) = (out, input) {
                if same_file(stdio_file(out, true), stdio_file(input, false)) {
                    usage_bail!(
                        "{out_flag} {out}: the same file as {in_flag} {input}: the output would \
                         replace an input"
                    );
                }
            }
        }
    }
    Ok(())
}

/// An error if an output (`(flag, path)`) is the same file as one of
/// `inputs` ([`same_file`]): files the input stream named, found before the
/// output is put in place (`polyfill3 -o brick.pat` for a scene of
/// `brick.pat` would replace the pattern with polygons), or any input,
/// checked before an animation's frame is written.
pub fn refuse_replacing_read_files(
    outputs: &[(&str, Option<&str>)],
    inputs: &[std::path::PathBuf],
) -> anyhow::Result<()> {
    for &(flag, out) in outputs {
        let Some(out) = out else { continue };
        let out_file = stdio_file(out, true);
        if let Some(f) = inputs
            .iter()
            .find(|f| same_file(out_file, &f.to_string_lossy()))
        {
            anyhow::bail!(
                "{flag} {out}: the same file as the input {}: the output would replace it",
                f.display()
            );
        }
    }
    Ok(())
}

/// A path as a depfile names it, the way a Makefile would spell it: `.`
/// components and `dir/..` pairs dropped (`scenes/../../fixtures/p.pat` is
/// `../fixtures/p.pat`), since make matches names by their letters.
pub fn dep_name(path: &std::path::Path) -> String {
    use std::path::Component;
    let mut parts: Vec<Component> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(parts.last(), Some(Component::Normal(_))) => {
                parts.pop();
            }
            other => parts.push(other),
        }
    }
    let joined: std::path::PathBuf = parts.iter().collect();
    if joined.as_os_str().is_empty() {
        ".".to_string()
    } else {
        joined.display().to_string()
    }
}

/// A `.pat` named on the command line, opened by [`crate::io::open_input`]
/// (`name` for errors), read as a stream: in memory of its texels, however
/// large its text, and bounded by its header. Whatever it starts with: the
/// stream's errors are [`crate::pat::Pattern::parse`]'s, and what is not a
/// pattern is refused at its first word. (Reading whole what did not start
/// as a pattern in its first 4096 bytes took 256 MiB before refusing
/// `yes | pat-tile -` or `yes ' ' | pat-tile -`, and refused a large
/// pattern after 4 KiB of blank lines.)
pub fn read_pattern(opened: crate::io::Opened, name: &str) -> anyhow::Result<crate::pat::Pattern> {
    Ok(crate::pat::Pattern::read_from(
        &mut opened.into_reader(),
        name,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_after_a_flag_whose_value_is_optional_is_joined_to_it() {
        use clap::CommandFactory;
        let command = polyfill3::Args::command();
        let join = |words: &[&str]| -> Vec<String> {
            let words = words.iter().map(std::ffi::OsString::from).collect();
            values_after_flags(&command, words)
                .into_iter()
                .map(|w| w.into_string().unwrap())
                .collect()
        };
        assert_eq!(
            join(&["p", "--cull", "none", "a.json"]),
            ["p", "--cull=none", "a.json"]
        );
        assert_eq!(join(&["p", "--cull", "a.json"]), ["p", "--cull", "a.json"]);
        assert_eq!(join(&["p", "--cull", "./none"]), ["p", "--cull", "./none"]);
        assert_eq!(
            join(&["p", "--cull=back", "front"]),
            ["p", "--cull=back", "front"]
        );
        assert_eq!(
            join(&["p", "--", "--cull", "none"]),
            ["p", "--", "--cull", "none"]
        );
        // Flags whose value is required are clap's own business.
        assert_eq!(join(&["p", "--incr", "none"]), ["p", "--incr", "none"]);
    }

    #[test]
    fn size_parses_and_repeats_bad_values() {
        assert_eq!(
            "64x32".parse::<Size>().unwrap(),
            Size {
                width: 64,
                height: 32
            }
        );
        for bad in ["64", "x", "-1x5", "0x10", "100000x2", "1e3x2"] {
            let e = bad.parse::<Size>().unwrap_err();
            assert!(
                e.contains(bad) || e.contains("too large") || e.contains("empty"),
                "{e}"
            );
        }
        // Past u32 is too large too, with the value as given (it was
        // "expected WxH").
        for big in ["4294967297x1", "1x18446744073709551632"] {
            assert_eq!(
                big.parse::<Size>().unwrap_err(),
                format!("image size {big} is too large: each side at most 65535")
            );
        }
    }

    #[test]
    fn broken_pipe_exits_quietly_with_status_0() {
        let e = anyhow::Error::new(std::io::Error::from(std::io::ErrorKind::BrokenPipe))
            .context("writing standard output");
        assert_eq!(report("t", Err(e)), EXIT_OK);
    }

    #[test]
    fn library_option_errors_name_the_flag() {
        let inner = std::io::Error::other(OptionError::new("past ", "max_polygons", " 5"));
        let e = anyhow::Error::new(inner).context("scene.json: record 3");
        assert_eq!(
            in_flag_words(&e),
            "scene.json: record 3: past --max-polygons 5"
        );
        let e = anyhow::Error::new(OptionError::new("", "compat", " thesis: no"));
        assert_eq!(in_flag_words(&e), "--compat thesis: no");
        let plain = anyhow::anyhow!("root").context("outer");
        assert_eq!(in_flag_words(&plain), format!("{plain:#}"));
    }

    #[test]
    fn a_cause_the_message_already_ends_with_is_not_repeated() {
        #[derive(Debug)]
        struct Inner;
        impl fmt::Display for Inner {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("chunk too short.")
            }
        }
        impl std::error::Error for Inner {}
        #[derive(Debug)]
        struct Outer(Inner);
        impl fmt::Display for Outer {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "Format error decoding Png: {}", self.0)
            }
        }
        impl std::error::Error for Outer {
            fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
                Some(&self.0)
            }
        }
        let e = anyhow::Error::new(Outer(Inner)).context("x.png: not an image");
        assert_eq!(
            in_flag_words(&e),
            "x.png: not an image: Format error decoding Png: chunk too short."
        );
        let e = anyhow::anyhow!("b").context("a");
        assert_eq!(in_flag_words(&e), "a: b");
    }

    #[test]
    fn usage_errors_exit_2_other_errors_exit_1() {
        let u = anyhow::Error::new(UsageError("bad".into()));
        assert_eq!(report("t", Err(u)), EXIT_USAGE);
        assert_eq!(report("t", Err(anyhow::anyhow!("x"))), EXIT_FAILURE);
    }
}
