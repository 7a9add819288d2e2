//! Relink when `memory.x` changes (the linker finds it in the package root), and tell the
//! firmware its target, which it reports so the runner can check it ran the right build, and
//! (embedded-3dgfx) the command buffer's capacity, `PEEL_GFX3D_COMMANDS` (default 3200): a
//! const generic of the library, so the runner builds it for each scene with what the scene
//! needs.
fn main() {
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-env-changed=PEEL_GFX3D_COMMANDS");
    let target = std::env::var("TARGET").expect("cargo sets TARGET");
    println!("cargo:rustc-env=FIRMWARE_TARGET={target}");
    let commands = std::env::var("PEEL_GFX3D_COMMANDS").unwrap_or_else(|_| "3200".into());
    match commands.parse::<u32>() {
        Ok(n) if n > 0 => println!("cargo:rustc-env=GFX3D_COMMANDS={n}"),
        _ => panic!("PEEL_GFX3D_COMMANDS={commands:?}: a positive whole number expected"),
    }
}
