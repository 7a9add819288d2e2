//! Relink when `memory.x` changes (the linker finds it in the package root), and tell the
//! firmware its target, which it reports so the runner can check it ran the right build.
fn main() {
    println!("cargo:rerun-if-changed=memory.x");
    let target = std::env::var("TARGET").expect("cargo sets TARGET");
    println!("cargo:rustc-env=FIRMWARE_TARGET={target}");
}
