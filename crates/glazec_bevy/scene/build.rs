// The shipped materials and the textured clay as Bevy materials, exactly as a user's build.rs
// does it (one `Build` per folder, each into its own directory of OUT_DIR).
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    glazec::build::Build::new("../../../materials").bevy().out_dir(out.join("shipped")).run();
    glazec::build::Build::new("../../../examples/textures").bevy().out_dir(out.join("textured")).run();
}
