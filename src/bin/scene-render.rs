fn main() {
    patkit::cli::main(patkit::cli::scene_render::run)
}
