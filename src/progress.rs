//! Progress of long jobs (a `--reference` frame, a palette search, a big
//! partition), told to whoever wants to show it. The library only counts;
//! the tools draw bars on a terminal (`cli::progress`), so the library stays
//! free of terminal code and a caller that passes [`Silent`] pays nothing.
//!
//! Reports come from any rayon worker and never change a result: they are
//! made per tile, row or iteration, never per pixel.

/// A receiver of progress reports. Both methods default to doing nothing.
pub trait Progress: Sync {
    /// A new phase of the job begins: `name` says what it does ("render",
    /// "k-means", ...), `total` how many steps it has (0 if not known).
    fn phase(&self, name: &str, total: u64) {
        let _ = (name, total);
    }
    /// `n` more steps of the current phase are done. Called from any thread.
    fn advance(&self, n: u64) {
        let _ = n;
    }
}

/// Reports to nobody: the default of every function that takes a
/// [`Progress`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}
