fn main() {
    patkit::cli::main(patkit::cli::pat_from_image::run)
}
