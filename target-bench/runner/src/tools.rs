//! The programs the runner drives: cargo (the `peel` binary and the firmware builds), `peel`
//! and `qemu-system-arm`. Each failure names the command and shows what it printed.

use std::ffi::{OsStr, OsString};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use peel_target_kit::config::Variant;
use peel_target_kit::layout::{ASSET_ADDR, CONFIG_ADDR};

use crate::plan::Core;

/// Paths of the tools and of the workspace.
pub struct Tools {
    /// The repository's root.
    pub root: PathBuf,
    /// The workspace's target directory (cargo's, `CARGO_TARGET_DIR` respected).
    pub target_dir: PathBuf,
    cargo: OsString,
    peel: PathBuf,
}

/// Run `command`; its stdout, or an error naming `what` with the tail of its output.
fn output(mut command: Command, what: &str) -> Result<String, String> {
    let out = command
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    if !out.status.success() {
        let stderr = text(&out.stderr);
        let tail: Vec<&str> = stderr.lines().rev().take(30).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(format!(
            "{what} failed ({}):\n{}",
            out.status,
            tail.join("\n")
        ));
    }
    Ok(text(&out.stdout))
}

impl Tools {
    /// Cargo as the runner was started by it (`CARGO`), and the workspace's target directory.
    pub fn find(root: &Path) -> Result<Tools, String> {
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let mut metadata = Command::new(&cargo);
        metadata
            .args(["metadata", "--format-version", "1", "--no-deps"])
            .current_dir(root);
        let json = output(metadata, "cargo metadata")?;
        let value: serde_json::Value =
            serde_json::from_str(&json).map_err(|e| format!("cargo metadata: {e}"))?;
        let target_dir = value["target_directory"]
            .as_str()
            .ok_or("cargo metadata: no target_directory")?
            .into();
        Ok(Tools {
            root: root.to_path_buf(),
            peel: PathBuf::new(),
            target_dir,
            cargo,
        })
    }

    /// Build the `peel` binary (release), the one the host references come from.
    pub fn build_peel(&mut self) -> Result<(), String> {
        let mut build = Command::new(&self.cargo);
        build
            .args([
                "build",
                "--release",
                "--quiet",
                "-p",
                "peel-compiler",
                "--bin",
                "peel",
            ])
            .current_dir(&self.root);
        output(build, "cargo build -p peel-compiler --bin peel")?;
        self.peel = self.target_dir.join("release").join("peel");
        Ok(())
    }

    /// Run `peel` with `args`.
    pub fn peel(&self, args: &[&OsStr]) -> Result<String, String> {
        let mut peel = Command::new(&self.peel);
        peel.args(args);
        let shown: Vec<String> = args
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        output(peel, &format!("peel {}", shown.join(" ")))
    }

    /// Build the firmware for `variant` on `core` and copy its ELF into `dir`. The firmware
    /// has its own workspace and target directory (under this workspace's), and its own
    /// rustflags (the linker script), so flags meant for the workspace are not passed on.
    /// `gfx3d_commands`: embedded-3dgfx's command buffer capacity (its build's default when
    /// `None`), also in the ELF's name.
    pub fn build_firmware(
        &self,
        core: Core,
        variant: Variant,
        gfx3d_commands: Option<u64>,
        dir: &Path,
    ) -> Result<PathBuf, String> {
        self.build(core, variant, None, gfx3d_commands, dir)
    }

    /// Build the streamed firmware that draws files of parts (`--features
    /// ftb-stream,objects`, the scene with moving objects) on `core` into `dir`.
    pub fn build_objects_firmware(&self, core: Core, dir: &Path) -> Result<PathBuf, String> {
        self.build(core, Variant::FtbStream, Some("objects"), None, dir)
    }

    /// Build `variant` (streamed, or embedded-3dgfx with `gfx3d_commands`) with textures
    /// (`--features <variant>,textures`, the textured scenes) on `core` into `dir`.
    pub fn build_textures_firmware(
        &self,
        core: Core,
        variant: Variant,
        gfx3d_commands: Option<u64>,
        dir: &Path,
    ) -> Result<PathBuf, String> {
        self.build(core, variant, Some("textures"), gfx3d_commands, dir)
    }

    /// Build the streamed firmware with transparency (`--features ftb-stream,transparency`,
    /// the glass box and its opaque baseline) on `core` into `dir`.
    pub fn build_transparency_firmware(&self, core: Core, dir: &Path) -> Result<PathBuf, String> {
        self.build(core, Variant::FtbStream, Some("transparency"), None, dir)
    }

    /// Build `variant` with the feature `extra` too, if any.
    fn build(
        &self,
        core: Core,
        variant: Variant,
        extra: Option<&str>,
        gfx3d_commands: Option<u64>,
        dir: &Path,
    ) -> Result<PathBuf, String> {
        let features = match extra {
            Some(extra) => format!("{},{extra}", variant.name()),
            None => variant.name().to_string(),
        };
        let crate_dir = self.root.join("target-bench/firmware");
        let build_dir = self.target_dir.join("peel-target/firmware-build");
        let mut build = Command::new(&self.cargo);
        build
            .args(["build", "--release", "--quiet", "--locked", "--target"])
            .arg(core.triple())
            .args(["--features", &features])
            .current_dir(&crate_dir)
            .env("CARGO_TARGET_DIR", &build_dir)
            .env_remove("RUSTFLAGS")
            .env_remove("CARGO_ENCODED_RUSTFLAGS")
            .env_remove("CARGO_BUILD_TARGET")
            .env_remove("PEEL_GFX3D_COMMANDS");
        if let Some(n) = gfx3d_commands {
            build.env("PEEL_GFX3D_COMMANDS", n.to_string());
        }
        let what = format!(
            "firmware build (target-bench/firmware: cargo build --release --target {} --features {})",
            core.triple(),
            features
        );
        output(build, &what)?;
        let elf = build_dir
            .join(core.triple())
            .join("release/peel-target-firmware");
        let mut suffix = gfx3d_commands.map_or_else(String::new, |n| format!("-{n}"));
        if let Some(extra) = extra {
            suffix.push('-');
            suffix.push_str(extra);
        }
        let copy = dir.join(format!("{}-{}{suffix}.elf", core.name(), variant.name()));
        std::fs::copy(&elf, &copy).map_err(|e| format!("{}: cannot copy: {e}", elf.display()))?;
        Ok(copy)
    }
}

/// Whether `elf` holds only ARMv6-M instructions: `llvm-objdump` (rustup's `llvm-tools`)
/// decodes its code as `thumbv6m`, and an instruction it cannot decode (`<unknown>`) is one of
/// ARMv7-M (QEMU's Cortex-M3 board would run it, a Cortex-M0+ would fault). An error names the
/// first such instruction.
pub fn check_armv6m(elf: &Path) -> Result<(), String> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let mut sysroot = Command::new(&rustc);
    sysroot.args(["--print", "sysroot"]);
    let sysroot = output(sysroot, "rustc --print sysroot")?;
    let mut version = Command::new(&rustc);
    version.arg("-vV");
    let version = output(version, "rustc -vV")?;
    let host = version
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .ok_or("rustc -vV: no host line")?;
    let objdump = Path::new(sysroot.trim())
        .join("lib/rustlib")
        .join(host)
        .join("bin/llvm-objdump");
    let mut disassemble = Command::new(&objdump);
    disassemble
        .args(["--triple=thumbv6m-none-eabi", "-d", "--no-show-raw-insn"])
        .arg(elf);
    let what = format!(
        "{} -d {} (llvm-tools, see .ci/setup)",
        objdump.display(),
        elf.display()
    );
    let listing = output(disassemble, &what)?;
    match unknown_instruction(&listing) {
        Some(line) => Err(format!(
            "{}: not ARMv6-M code, llvm-objdump cannot decode `{line}` as thumbv6m",
            elf.display()
        )),
        None => Ok(()),
    }
}

/// The first line of a disassembly listing with an instruction the decoder did not know.
fn unknown_instruction(listing: &str) -> Option<&str> {
    listing
        .lines()
        .find(|l| l.contains("<unknown>"))
        .map(str::trim)
}

/// A QEMU run's result: its stdout (the firmware's semihosting output).
pub struct QemuRun<'a> {
    /// The core (machine and CPU).
    pub core: Core,
    /// The firmware.
    pub elf: &'a Path,
    /// The asset loaded at [`ASSET_ADDR`].
    pub asset: &'a Path,
    /// The config block loaded at [`CONFIG_ADDR`].
    pub config: &'a Path,
    /// QEMU's working directory (where the firmware's frame files land) and its logs.
    pub dir: &'a Path,
    /// Seconds before the run is killed.
    pub timeout_s: u32,
}

/// Run QEMU as `run` says, under `timeout` (a QEMU left alone with a closed pipe can spin),
/// its output in files of `run.dir`; the firmware's output, or an error naming the run.
pub fn qemu(run: &QemuRun<'_>) -> Result<String, String> {
    let stdout_path = run.dir.join("qemu.out");
    let stderr_path = run.dir.join("qemu.err");
    let create = |p: &Path| File::create(p).map_err(|e| format!("{}: {e}", p.display()));
    let (stdout, stderr) = (create(&stdout_path)?, create(&stderr_path)?);
    let loader = |file: &Path, addr: u32| {
        let mut arg = OsString::from("loader,file=");
        arg.push(file.as_os_str());
        arg.push(format!(",addr={addr:#010x}"));
        arg
    };
    let mut command = Command::new("timeout");
    command
        .args([
            "--kill-after=5",
            &run.timeout_s.to_string(),
            "qemu-system-arm",
        ])
        .args(["-machine", run.core.machine(), "-cpu", run.core.qemu_cpu()])
        .args(["-display", "none", "-serial", "none", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-icount", "shift=0"])
        .arg("-kernel")
        .arg(run.elf)
        .arg("-device")
        .arg(loader(run.asset, ASSET_ADDR))
        .arg("-device")
        .arg(loader(run.config, CONFIG_ADDR))
        .current_dir(run.dir)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr);
    let what = format!("QEMU run in {}", run.dir.display());
    let status = command
        .status()
        .map_err(|e| format!("{what}: cannot start `timeout qemu-system-arm`: {e}"))?;
    let read = |p: &Path| std::fs::read_to_string(p).unwrap_or_default();
    let out = read(&stdout_path);
    match status.code() {
        Some(0) => Ok(out),
        Some(124) | Some(137) => Err(format!("{what}: timed out after {} s", run.timeout_s)),
        _ => {
            let firmware = out
                .lines()
                .find(|l| l.starts_with("error:"))
                .map(|l| format!(": the firmware says {l:?}"))
                .unwrap_or_default();
            let err = read(&stderr_path);
            Err(format!(
                "{what}: failed ({status}){firmware}{}",
                if err.is_empty() {
                    String::new()
                } else {
                    format!("\nQEMU: {}", err.trim())
                }
            ))
        }
    }
}

/// Whether `qemu-system-arm` and `timeout` can be run.
pub fn check_qemu() -> Result<(), String> {
    let ok = |program: &str, arg: &str| {
        Command::new(program)
            .arg(arg)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if !ok("qemu-system-arm", "--version") {
        return Err(
            "qemu-system-arm not found: run `bash .ci/setup` (or apt-get install qemu-system-arm)"
                .into(),
        );
    }
    if !ok("timeout", "--version") {
        return Err("`timeout` (coreutils) not found".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::unknown_instruction;

    #[test]
    fn an_undecodable_instruction_is_found() {
        let v6 = "00000400 <Reset>:\n     400:      \tbl\t0x500\n     404:      \tmovs\tr0, #0x0\n";
        assert_eq!(unknown_instruction(v6), None);
        let v7 = "     400:      \tbl\t0x500\n     404:      \t<unknown>\n";
        assert_eq!(unknown_instruction(v7), Some("404:      \t<unknown>"));
    }
}
