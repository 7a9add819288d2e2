//! Relink when `memory.x` changes (the linker finds it in the package root), and tell the
//! firmware its target, which it reports so the runner can check it ran the right build, and
//! (embedded-3dgfx) the command buffer's capacity, `PEEL_GFX3D_COMMANDS` (default 3200): a
//! const generic of the library, so the runner builds it for each scene with what the scene
//! needs. It also sets `cfg(peel_method)` in the builds of Peel's own variants, so the code
//! they share is selected once.
fn main() {
    println!("cargo::rustc-check-cfg=cfg(peel_method)");
    let peel = [
        "FTB_FRAMEBUFFER",
        "FTB_STREAM",
        "STREAM_AA",
        "FTB_BANDS",
        "SCAN_ORDER",
        "SCAN_AA",
        "B2F_FRAMEBUFFER",
        "B2F_BANDS",
    ];
    if peel
        .iter()
        .any(|f| std::env::var_os(format!("CARGO_FEATURE_{f}")).is_some())
    {
        println!("cargo::rustc-cfg=peel_method");
    }
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
