//! What a run measures: cores, image sizes, display paths and cameras, and the command line.

use std::path::PathBuf;

use peel_compiler::shade::normals::DEFAULT_CREASE_DEG;
use peel_target_kit::config::{OrbitAngles, Variant};

/// A core class and how QEMU emulates it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Core {
    /// Cortex-M4F: `thumbv7em-none-eabihf` on `mps2-an386`.
    M4f,
    /// Cortex-M0+: `thumbv6m-none-eabi` (ARMv6-M code runs unchanged on the Cortex-M3 of
    /// `mps2-an385`, which has the same memory map as `mps2-an386`).
    M0Plus,
}

impl Core {
    /// Whether the firmware draws with integer vertices (`Renderer::integer_vertices`): on the
    /// core without an FPU, where they cost a fraction of the software `f32` path.
    pub fn integer_vertices(self) -> bool {
        self == Core::M0Plus
    }

    /// The `core` of the records.
    pub fn name(self) -> &'static str {
        match self {
            Core::M4f => "cortex-m4f",
            Core::M0Plus => "cortex-m0plus",
        }
    }

    /// The Rust target.
    pub fn triple(self) -> &'static str {
        match self {
            Core::M4f => "thumbv7em-none-eabihf",
            Core::M0Plus => "thumbv6m-none-eabi",
        }
    }

    /// QEMU's machine.
    pub fn machine(self) -> &'static str {
        match self {
            Core::M4f => "mps2-an386",
            Core::M0Plus => "mps2-an385",
        }
    }

    /// QEMU's CPU.
    pub fn qemu_cpu(self) -> &'static str {
        match self {
            Core::M4f => "cortex-m4",
            Core::M0Plus => "cortex-m3",
        }
    }

    /// Image sizes measured on this core: 320x240 on both, 160x120 too on the M0+ class.
    pub fn sizes(self) -> &'static [(u32, u32)] {
        match self {
            Core::M4f => &[(320, 240)],
            Core::M0Plus => &[(320, 240), (160, 120)],
        }
    }
}

/// A firmware variant and, when banded, its band height.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Setup {
    /// The build.
    pub variant: Variant,
    /// Rows per band (0: whole frames).
    pub band_rows: u32,
}

impl Setup {
    /// The record's `path`: how the frame reaches the display.
    pub fn path(&self) -> String {
        match self.variant {
            // Streamed, anti-aliased (the record's method says which).
            Variant::FtbStream | Variant::StreamAa => "stream".into(),
            Variant::ScanOrder | Variant::ScanAa => "scan-order".into(),
            // One row of colour and depth, sent when done.
            Variant::ScanlineZbuffer => "bands-1".into(),
            v if v.banded() => format!("bands-{}", self.band_rows),
            _ => "framebuffer".into(),
        }
    }

    /// A short name for directories and messages, e.g. `ftb-bands-16`.
    pub fn label(&self) -> String {
        if self.band_rows > 0 {
            format!("{}-{}", self.variant.name(), self.band_rows)
        } else {
            self.variant.name().to_string()
        }
    }
}

/// Every display path: front to back into a framebuffer, streamed and in scan order (each also
/// anti-aliased), and in
/// bands of 8, 16 and 30 rows; back to front into a framebuffer and in bands of 16 rows; the peers: the z-buffer
/// (whole frame, and tiled, its band height chosen per scene by [`tiled_band_rows`], 0 here),
/// the scanline z-buffer and embedded-3dgfx.
pub fn setups(only: Option<&[Variant]>) -> Vec<Setup> {
    let whole = |variant| Setup {
        variant,
        band_rows: 0,
    };
    let band = |variant, band_rows| Setup { variant, band_rows };
    let all = [
        whole(Variant::FtbFramebuffer),
        whole(Variant::FtbStream),
        whole(Variant::StreamAa),
        whole(Variant::ScanOrder),
        whole(Variant::ScanAa),
        band(Variant::FtbBands, 8),
        band(Variant::FtbBands, 16),
        band(Variant::FtbBands, 30),
        whole(Variant::B2fFramebuffer),
        band(Variant::B2fBands, 16),
        whole(Variant::Zbuffer),
        band(Variant::TiledZbuffer, 0),
        whole(Variant::ScanlineZbuffer),
        whole(Variant::Gfx3d),
    ];
    all.into_iter()
        .filter(|s| only.is_none_or(|o| o.contains(&s.variant)))
        .collect()
}

/// The smooth runs (each scene's smooth file beside its flat one, [`smooth_scene`]), on both
/// cores at 320x240: Peel streamed and in scan order, and embedded-3dgfx's Gouraud mode; in
/// the quick run only Peel streamed. Those of `only`, if given.
pub fn smooth_setups(only: Option<&[Variant]>, quick: bool) -> Vec<Setup> {
    let all: &[Variant] = if quick {
        &[Variant::FtbStream]
    } else {
        &[Variant::FtbStream, Variant::ScanOrder, Variant::Gfx3d]
    };
    all.iter()
        .filter(|v| only.is_none_or(|o| o.contains(v)))
        .map(|&variant| Setup {
            variant,
            band_rows: 0,
        })
        .collect()
}

/// Whether the scene named `name` is measured smooth too: the teapot and the cow (or their
/// generated stand-ins), the demo in the quick run.
pub fn smooth_scene(name: &str, quick: bool) -> bool {
    let name = name.trim_end_matches(" (generated)");
    if quick {
        name == "demo"
    } else {
        name == "teapot" || name == "cow"
    }
}

/// The crease of the smooth files, in degrees: `peel compile --shading smooth`'s default
/// ([`DEFAULT_CREASE_DEG`]), except in the quick run, whose demo scene of boxes and a pyramid
/// has no faces that close (it would have no smooth polygon): 180, every edge smooth.
pub fn smooth_crease_deg(quick: bool) -> f64 {
    if quick {
        180.0
    } else {
        DEFAULT_CREASE_DEG
    }
}

/// The image size of the smooth runs.
pub const SMOOTH_SIZE: (u32, u32) = (320, 240);

/// The tiled z-buffer's band height at `width` pixels a row: the most rows whose colour and
/// 16-bit depth (4 bytes a pixel) fit in `budget` bytes of RAM beside `other` bytes (its code's
/// statics and stack); at least one row, at most `height`.
pub fn tiled_band_rows(budget: u64, other: u64, width: u32, height: u32) -> u32 {
    let rows = budget.saturating_sub(other) / (4 * u64::from(width));
    rows.clamp(1, u64::from(height)) as u32
}

/// Orbit elevation of the camera path, in degrees (the CLI's default).
pub const ELEVATION_DEG: f64 = 20.0;
/// Vertical field of view, in degrees (the CLI's default).
pub const FOV_Y_DEG: f64 = 60.0;

/// The camera path: `count` cameras of the orbit at azimuths 0, 45, 90, ... degrees.
pub fn cameras(count: usize) -> Vec<OrbitAngles> {
    (0..count)
        .map(|k| OrbitAngles {
            azimuth_deg: 45.0 * k as f64,
            elevation_deg: ELEVATION_DEG,
        })
        .collect()
}

/// The command line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Args {
    /// The CI run: the demo scene, two cameras, both cores, 320x240, every display path.
    pub quick: bool,
    /// Where the shared models are (default `../shared/models` from the repository root).
    pub models: Option<PathBuf>,
    /// Only these variants (for working on one).
    pub only: Option<Vec<Variant>>,
    /// Scenes compiled with the default sun's shadows (`peel compile --shadows`).
    pub shadows: bool,
}

/// Usage text.
pub const USAGE: &str = "\
usage: bash .ci/target [--quick] [--shadows] [--models DIR] [--only VARIANT,...]

Runs Peel's renderer in qemu-system-arm (Cortex-M4F and Cortex-M0+ builds), checks its pixels
against the host and writes target/peel-target/results.json and results.md. The teapot and the
cow are measured smooth too (peel compile --shading smooth: streamed, in scan order, and
embedded-3dgfx's Gouraud mode, 320x240, both cores). With ftb-stream (not in the quick run),
the scene with moving objects (a world with the teapot and the cow posed per camera, a file
of parts) and the same posed geometry as one static file per camera; with ftb-stream or
embedded-3dgfx (not in the quick run), the textured box and a textured sphere, each beside
the same OBJ untextured, by the builds with textures (320x240, both cores).

  --quick         the demo scene, two cameras, 320x240, both cores, every method, and the
                  demo's smooth file streamed (CI)
  --shadows       scenes compiled with the default sun's shadows (peel compile --shadows)
  --models DIR    the shared models (default: ../shared/models from the repository root)
  --only LIST     only these firmware variants: ftb-framebuffer, ftb-stream, stream-aa,
                  scan-order, scan-aa, ftb-bands, b2f-framebuffer, b2f-bands, zbuffer, tiled-zbuffer,
                  scanline-zbuffer, embedded-3dgfx";

/// Parse the arguments after the program name; `Ok(None)` for `--help`.
pub fn parse_args<I: IntoIterator<Item = String>>(args: I) -> Result<Option<Args>, String> {
    let mut parsed = Args::default();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let (flag, inline) = match arg.split_once('=') {
            Some((f, v)) => (f.to_string(), Some(v.to_string())),
            None => (arg.clone(), None),
        };
        let mut value = |name: &str| {
            inline
                .clone()
                .or_else(|| args.next())
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match flag.as_str() {
            "--quick" if inline.is_none() => parsed.quick = true,
            "--shadows" if inline.is_none() => parsed.shadows = true,
            "--models" => parsed.models = Some(value("--models")?.into()),
            "--only" => {
                let list = value("--only")?;
                let variants = list
                    .split(',')
                    .map(|name| {
                        Variant::ALL
                            .into_iter()
                            .find(|v| v.name() == name)
                            .ok_or_else(|| format!("--only: unknown variant {name:?}"))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                parsed.only = Some(variants);
            }
            "-h" | "--help" => return Ok(None),
            _ => return Err(format!("unknown argument {arg:?}\n{USAGE}")),
        }
    }
    Ok(Some(parsed))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Option<Args>, String> {
        parse_args(args.iter().map(|s| s.to_string()))
    }

    #[test]
    fn arguments() {
        assert_eq!(parse(&[]).unwrap(), Some(Args::default()));
        let a = parse(&["--quick", "--models", "m", "--only=zbuffer,ftb-stream"])
            .unwrap()
            .unwrap();
        assert!(a.quick && !a.shadows);
        assert!(parse(&["--shadows"]).unwrap().unwrap().shadows);
        assert_eq!(a.models, Some(PathBuf::from("m")));
        assert_eq!(a.only, Some(vec![Variant::Zbuffer, Variant::FtbStream]));
        assert_eq!(parse(&["--help"]).unwrap(), None);
        assert!(parse(&["--models"]).unwrap_err().contains("needs a value"));
        assert!(parse(&["--only", "zbuf"]).unwrap_err().contains("zbuf"));
        assert!(parse(&["--fast"]).unwrap_err().contains("--fast"));
        assert!(parse(&["--quick=1"]).is_err());
    }

    #[test]
    fn smooth_runs() {
        let names = |setups: Vec<Setup>| setups.iter().map(Setup::label).collect::<Vec<_>>();
        assert_eq!(
            names(smooth_setups(None, false)),
            ["ftb-stream", "scan-order", "embedded-3dgfx"]
        );
        let paths: Vec<String> = smooth_setups(None, false).iter().map(Setup::path).collect();
        assert_eq!(paths, ["stream", "scan-order", "framebuffer"]);
        assert_eq!(names(smooth_setups(None, true)), ["ftb-stream"]);
        let only = [Variant::ScanOrder, Variant::Zbuffer];
        assert_eq!(names(smooth_setups(Some(&only), false)), ["scan-order"]);
        assert!(smooth_setups(Some(&only), true).is_empty());
        for (name, quick, smooth) in [
            ("teapot", false, true),
            ("cow (generated)", false, true),
            ("suzanne", false, false),
            ("demo", false, false),
            ("demo", true, true),
            ("teapot", true, false),
        ] {
            assert_eq!(smooth_scene(name, quick), smooth, "{name} {quick}");
        }
        assert_eq!(smooth_crease_deg(false), 60.0);
        assert_eq!(smooth_crease_deg(true), 180.0);
        // Both cores draw at the smooth runs' size.
        assert!([Core::M4f, Core::M0Plus]
            .iter()
            .all(|c| c.sizes().contains(&SMOOTH_SIZE)));
    }

    #[test]
    fn camera_path_and_setups() {
        let c = cameras(8);
        assert_eq!(c.len(), 8);
        assert_eq!(c[7].azimuth_deg, 315.0);
        assert!(c.iter().all(|c| c.elevation_deg == 20.0));
        assert_eq!(setups(None).len(), 14);
        let paths: Vec<String> = setups(None).iter().map(Setup::path).collect();
        assert_eq!(
            paths,
            [
                "framebuffer",
                "stream",
                "stream",
                "scan-order",
                "scan-order",
                "bands-8",
                "bands-16",
                "bands-30",
                "framebuffer",
                "bands-16",
                "framebuffer",
                "bands-0",
                "bands-1",
                "framebuffer"
            ]
        );
        // 32 KiB beside 9 kB of code memory at 320 pixels a row: 18 rows of 1,280 bytes.
        assert_eq!(tiled_band_rows(32768, 9000, 320, 240), 18);
        assert_eq!(tiled_band_rows(1000, 9000, 320, 240), 1);
        assert_eq!(tiled_band_rows(1 << 30, 0, 320, 240), 240);
        let z = setups(Some(&[Variant::FtbBands]));
        assert_eq!(
            z.iter().map(Setup::label).collect::<Vec<_>>(),
            ["ftb-bands-8", "ftb-bands-16", "ftb-bands-30"]
        );
    }
}
