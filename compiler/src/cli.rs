//! The `peel` subcommands other than `compile`: inspect, dump, render, demo.

use std::path::{Path, PathBuf};

use clap::Args;
use glam::DVec3;

use peel_compiler::compile::CompileOptions;
use peel_compiler::raster::{png, render_bytes, Frame, View};

/// Parse `x,y,z` (negative numbers allowed: `--eye=-1,2,3` or `--eye -1,2,3`).
pub fn parse_dvec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected x,y,z, got '{s}'"));
    }
    let mut v = [0.0f64; 3];
    for (slot, p) in v.iter_mut().zip(&parts) {
        let x: f64 = p
            .parse()
            .map_err(|_| format!("'{p}' is not a number (in '{s}')"))?;
        if !x.is_finite() {
            return Err(format!("'{p}' is not finite (in '{s}')"));
        }
        *slot = x;
    }
    Ok(DVec3::from_array(v))
}

/// Parse `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, got '{s}'"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!(
            "image size '{s}' must be between 1x1 and 16384x16384"
        ));
    }
    Ok((w, h))
}

/// Parse `r,g,b` with 0..=255 channels.
pub fn parse_rgb(s: &str) -> Result<[u8; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let mut c = [0u8; 3];
    if parts.len() != 3 {
        return Err(format!("expected r,g,b, got '{s}'"));
    }
    for (slot, p) in c.iter_mut().zip(&parts) {
        *slot = p
            .parse()
            .map_err(|_| format!("'{p}' is not a channel value 0..=255 (in '{s}')"))?;
    }
    Ok(c)
}

/// Arguments of `peel render`.
#[derive(Args)]
pub struct RenderArgs {
    /// The .peel file.
    pub file: PathBuf,
    /// Eye position x,y,z.
    #[arg(long, value_parser = parse_dvec3, allow_hyphen_values = true)]
    pub eye: DVec3,
    /// Point looked at x,y,z.
    #[arg(long, value_parser = parse_dvec3, allow_hyphen_values = true)]
    pub target: DVec3,
    /// Up direction x,y,z.
    #[arg(long, value_parser = parse_dvec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: DVec3,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 60.0)]
    pub fov: f64,
    /// Image size WxH.
    #[arg(long, value_parser = parse_size)]
    pub size: (u32, u32),
    /// Near distance (default: 1e-3 x the scene's bounding-box diagonal).
    #[arg(long)]
    pub near: Option<f64>,
    /// Write the id image (source triangle id + 1 as 24-bit RGB; needs a file compiled with --ids).
    #[arg(long)]
    pub ids: bool,
    /// Background colour r,g,b.
    #[arg(long, value_parser = parse_rgb, default_value = "0,0,0")]
    pub background: [u8; 3],
    /// Output PNG.
    #[arg(short, long)]
    pub output: PathBuf,
}

fn read(path: &Path) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))
}

/// `peel inspect`.
pub fn inspect(path: &Path, json: bool) -> Result<(), String> {
    let bytes = read(path)?;
    let info = peel_compiler::dump::inspect(&bytes)
        .map_err(|e| format!("{}: invalid .peel file: {e}", path.display()))?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&info).map_err(|e| e.to_string())?
        );
    } else {
        let v = serde_json::to_value(info).map_err(|e| e.to_string())?;
        if let Some(map) = v.as_object() {
            for (k, v) in map {
                println!("{k}: {v}");
            }
        }
    }
    Ok(())
}

/// `peel dump`.
pub fn dump(path: &Path) -> Result<(), String> {
    let bytes = read(path)?;
    let yaml = peel_compiler::dump::dump_yaml(&bytes)
        .map_err(|e| format!("{}: invalid .peel file: {e}", path.display()))?;
    print!("{yaml}");
    Ok(())
}

/// `peel render`.
pub fn render(args: &RenderArgs) -> Result<(), String> {
    let bytes = read(&args.file)?;
    let view = View {
        eye: args.eye,
        target: args.target,
        up: args.up,
        fov_y_deg: args.fov,
        width: args.size.0,
        height: args.size.1,
        near: args.near,
    };
    let frame = render_bytes(&bytes, &view, args.ids, args.background)
        .map_err(|e| format!("{}: {e}", args.file.display()))?;
    write_png(&args.output, &frame)?;
    println!(
        "{} -> {}: {}x{}, {} polygons visited, {} drawn, {} pixels written",
        args.file.display(),
        args.output.display(),
        frame.width,
        frame.height,
        frame.stats.polygons_visited,
        frame.stats.polygons_drawn,
        frame.stats.pixels_written
    );
    Ok(())
}

fn write_png(path: &Path, frame: &Frame) -> Result<(), String> {
    let png = png(frame)?;
    peel_compiler::write::write_atomic(path, &png).map_err(|e| e.to_string())
}

/// The demo's camera: above and in front of the scene, looking at its middle.
pub const DEMO_VIEW: View = View {
    eye: DVec3::new(5.5, 4.5, 7.5),
    target: DVec3::new(0.0, 0.8, 0.0),
    up: DVec3::Y,
    fov_y_deg: 50.0,
    width: 800,
    height: 600,
    near: None,
};

/// `peel demo`: write the built-in scene, compile it, render it.
pub fn demo(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let obj = out.join("demo.obj");
    std::fs::write(&obj, DEMO_OBJ).map_err(|e| format!("{}: {e}", obj.display()))?;
    let mtl = out.join("demo.mtl");
    std::fs::write(&mtl, DEMO_MTL).map_err(|e| format!("{}: {e}", mtl.display()))?;
    let peel = out.join("demo.peel");
    let bytes = crate::compile_to(&obj, &peel, &CompileOptions::default(), None)?;
    let frame = render_bytes(&bytes, &DEMO_VIEW, false, [24, 26, 32])?;
    let png_path = out.join("demo.png");
    write_png(&png_path, &frame)?;
    println!(
        "{}: {}x{}, {} polygons drawn, {} pixels written",
        png_path.display(),
        frame.width,
        frame.height,
        frame.stats.polygons_drawn,
        frame.stats.pixels_written
    );
    Ok(())
}

/// The demo scene (also `fixtures/demo.obj`).
const DEMO_OBJ: &str = include_str!("../../fixtures/demo.obj");
const DEMO_MTL: &str = include_str!("../../fixtures/demo.mtl");
