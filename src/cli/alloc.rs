//! Out of memory as the tools' own error line, not an abort (issue 17,
//! item 3).
//!
//! Rust's default reaction to a failed allocation prints "memory allocation
//! of N bytes failed" and aborts (status 134), which skips the cleanup of
//! unfinished outputs and reads like a crash. Each tool's binary installs
//! [`Reporting`] as its global allocator: it hands every request to the
//! system allocator and, when one fails, writes `TOOL: error: out of memory:
//! ...` to standard error, removes the temporary files of outputs being
//! written ([`crate::io::remove_unfinished_outputs`]) and exits with status
//! 1, like any other error. Limits checked before allocating (the README's
//! "Limits") remain the first line; this is the backstop for what no limit
//! foresaw (an address-space limit, a small machine).
//!
//! Nothing here may allocate: the message is formatted into a stack buffer
//! and written with `write(2)`, and a second failure while reporting the
//! first exits at once.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

/// The global allocator of the tools: the system's, reporting failure as an
/// error line and exit status 1 (see the module documentation).
pub struct Reporting;

/// The running tool's name, for the message (set by [`crate::cli::main`]).
static TOOL: OnceLock<&'static str> = OnceLock::new();

/// Set while a failure is being reported, so a failure inside the report
/// ends the process without recursion.
static REPORTING: AtomicBool = AtomicBool::new(false);

/// Names the tool in the out-of-memory message.
pub(crate) fn set_tool_name(name: &str) {
    let _ = TOOL.set(Box::leak(name.to_owned().into_boxed_str()));
}

// SAFETY: every method forwards to `System` with the caller's arguments and
// returns its result unchanged; only a null result diverts into
// `out_of_memory`, which never returns.
unsafe impl GlobalAlloc for Reporting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }
}

/// A `fmt::Write` into a fixed stack buffer; what does not fit is dropped.
struct StackText {
    buf: [u8; 320],
    len: usize,
}

impl std::fmt::Write for StackText {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let n = s.len().min(self.buf.len() - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        Ok(())
    }
}

/// Reports a failed request for `bytes` bytes, removes unfinished outputs
/// and exits with status 1.
#[cold]
fn out_of_memory(bytes: usize) -> ! {
    if REPORTING.swap(true, Ordering::SeqCst) {
        // SAFETY: `_exit` ends the process; no Rust state is touched after.
        unsafe { libc::_exit(1) }
    }
    let mut text = StackText {
        buf: [0; 320],
        len: 0,
    };
    let tool = TOOL.get().copied().unwrap_or("patkit");
    // Megabytes as a person writes them; exact bytes when small.
    let _ = if bytes >= 1 << 20 {
        std::fmt::write(
            &mut text,
            format_args!(
                "{tool}: error: out of memory: a request for {:.1} MiB failed \
                 (the machine's memory or a limit such as `ulimit -v`)\n",
                bytes as f64 / (1u64 << 20) as f64
            ),
        )
    } else {
        std::fmt::write(
            &mut text,
            format_args!(
                "{tool}: error: out of memory: a request for {bytes} bytes failed \
                 (the machine's memory or a limit such as `ulimit -v`)\n"
            ),
        )
    };
    // SAFETY: writes `len` initialised bytes of a live stack buffer to fd 2.
    unsafe {
        libc::write(2, text.buf.as_ptr().cast(), text.len);
    }
    crate::io::remove_unfinished_outputs_now();
    // SAFETY: as above; buffered output of a failed run is not wanted.
    unsafe { libc::_exit(1) }
}
