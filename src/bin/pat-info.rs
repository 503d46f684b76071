fn main() {
    patkit::cli::main(patkit::cli::pat_info::run)
}
