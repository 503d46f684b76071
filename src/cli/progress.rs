//! Progress bars on standard error for the long jobs (issue 22): only when
//! standard error is a terminal whose `TERM` is not `dumb`, never in a pipe
//! or a file, and not with `--no-progress`. The library reports through
//! [`crate::progress::Progress`]; this is its one implementation that draws.
//! Bars are cleared when the job ends, so a finished run leaves the
//! terminal as it would without them, and nothing on standard output moves.

use crate::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{BufRead, IsTerminal, Read};
use std::time::Duration;

/// How often a spinner turns while a phase of unknown length runs.
const SPIN_EVERY: Duration = Duration::from_millis(120);
/// Most redraws per second: indicatif drops the updates in between, so a
/// per-tile report costs an atomic add.
const REDRAWS_PER_SECOND: u8 = 10;

/// The flag shared by the tools with long jobs (`#[command(flatten)]`).
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct ProgressArgs {
    /// Show no progress bar. Bars are drawn on standard error only when it
    /// is a terminal (and TERM is not "dumb"), never into a pipe or a file,
    /// and cleared when the job ends.
    #[arg(long)]
    pub no_progress: bool,
}

impl ProgressArgs {
    /// A bar headed `tool`, hidden unless it is wanted (module docs).
    pub fn bar(&self, tool: &str) -> Bar {
        let term_ok = std::env::var_os("TERM").is_none_or(|t| t != "dumb");
        if self.no_progress || !term_ok || !std::io::stderr().is_terminal() {
            return Bar(None);
        }
        let bar = ProgressBar::with_draw_target(
            None,
            ProgressDrawTarget::stderr_with_hz(REDRAWS_PER_SECOND),
        );
        bar.set_style(spinner_style(""));
        bar.set_prefix(tool.to_string());
        Bar(Some(bar))
    }
}

/// A progress bar on standard error, or nothing. Cleared when dropped.
pub struct Bar(Option<ProgressBar>);

impl Bar {
    /// Counts bytes of an input of `total` bytes (0: not known) as `reader`
    /// gives them.
    pub fn reading(
        &self,
        name: &str,
        total: u64,
        reader: Box<dyn BufRead + Send>,
    ) -> Box<dyn BufRead + Send> {
        let Some(bar) = &self.0 else {
            return reader;
        };
        bar.set_message(format!("reading {name}"));
        if total == 0 {
            bar.set_style(spinner_style("{binary_bytes}"));
            bar.enable_steady_tick(SPIN_EVERY);
        } else {
            bar.set_style(bar_style("{binary_bytes}/{binary_total_bytes}"));
            bar.set_length(total);
        }
        Box::new(Counting {
            inner: reader,
            bar: bar.clone(),
        })
    }
}

fn bar_style(counts: &str) -> ProgressStyle {
    ProgressStyle::with_template(&format!(
        "{{prefix}}: {{msg}} [{{wide_bar}}] {counts} {{elapsed}}"
    ))
    .expect("a valid template")
    .progress_chars("=> ")
}

fn spinner_style(counts: &str) -> ProgressStyle {
    ProgressStyle::with_template(&format!(
        "{{prefix}}: {{msg}} {{spinner}} {counts} {{elapsed}}"
    ))
    .expect("a valid template")
}

impl Progress for Bar {
    fn phase(&self, name: &str, total: u64) {
        let Some(bar) = &self.0 else { return };
        bar.set_message(name.to_string());
        bar.set_position(0);
        if total == 0 {
            bar.set_style(spinner_style(""));
            bar.enable_steady_tick(SPIN_EVERY);
        } else {
            bar.disable_steady_tick();
            bar.set_style(bar_style("{pos}/{len}"));
            bar.set_length(total);
        }
    }

    fn advance(&self, n: u64) {
        if let Some(bar) = &self.0 {
            bar.inc(n);
        }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        if let Some(bar) = &self.0 {
            bar.finish_and_clear();
        }
    }
}

/// A reader that reports the bytes consumed from it.
struct Counting {
    inner: Box<dyn BufRead + Send>,
    bar: ProgressBar,
}

impl Read for Counting {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.bar.inc(n as u64);
        Ok(n)
    }
}

impl BufRead for Counting {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.inner.fill_buf()
    }
    fn consume(&mut self, amt: usize) {
        self.inner.consume(amt);
        self.bar.inc(amt as u64);
    }
}
