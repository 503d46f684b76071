fn main() {
    patkit::cli::main(patkit::cli::polyfill3::run)
}
