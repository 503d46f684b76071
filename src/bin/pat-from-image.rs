/// Out of memory is reported as `TOOL: error: ...` with status 1, and the
/// outputs being written are removed (`patkit::cli::alloc`).
#[global_allocator]
static ALLOC: patkit::cli::alloc::Reporting = patkit::cli::alloc::Reporting;

fn main() {
    patkit::cli::main(patkit::cli::pat_from_image::run)
}
