//! Peel on the desktop, as embedded-graphics users prototype firmware on a PC: the scene
//! build.rs compiled (or a `.peel` file) drawn exactly as firmware draws it, front to back in
//! RGB565 with memory sized for the scene, into the embedded-graphics simulator's display. An
//! orbit in a window (feature `window`), or, with `--png`, frames of it to a PNG file with no
//! window and no SDL2. See docs/desktop.md.

mod error;
mod frame;
#[cfg(feature = "window")]
mod window;

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use embedded_graphics_core::geometry::Size;
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay};
use peel_runtime::read::Scene;
use peel_runtime::render::{FrameStats, Renderer};

use error::Error;
use frame::{Memory, Order};

/// The scene, compiled by build.rs.
static SCENE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

/// The scene's sizes, written beside it by build.rs: the memory its frames need at the
/// display size it was measured at (`SPANS_MEASURED_AT`).
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

/// Draw a scene as firmware does into the embedded-graphics simulator's display: an orbit in
/// a window, or its frames to a PNG file.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// A `.peel` file to draw instead of the scene build.rs compiled (`peel compile
    /// scene.obj -o scene.peel` makes one).
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// How a frame reaches the display: in scan order (the boards' way) or span by span.
    #[arg(long, value_enum, default_value_t = Order::Scan)]
    order: Order,
    /// Write the last frame to this PNG file (the display's pixels) instead of opening a
    /// window.
    #[arg(long, value_name = "OUT.png")]
    png: Option<PathBuf>,
    /// The first frame's azimuth around the scene, degrees (from +z towards +x).
    #[arg(long, default_value_t = 30.0, value_parser = finite, allow_hyphen_values = true)]
    azimuth: f64,
    /// Degrees the orbit turns from one frame to the next.
    #[arg(long, default_value_t = 1.0, value_parser = finite, allow_hyphen_values = true)]
    step: f64,
    /// Frames to draw before the PNG is written (with `--png`).
    #[arg(
        long,
        default_value_t = 1,
        value_parser = clap::value_parser!(u64).range(1..),
        requires = "png"
    )]
    frames: u64,
    /// Window pixels per display pixel (the window only).
    #[arg(
        long,
        default_value_t = 2,
        value_parser = clap::value_parser!(u32).range(1..=16),
        conflicts_with = "png"
    )]
    scale: u32,
}

/// A finite number of degrees.
fn finite(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("'{s}' is not a finite number of degrees"))
}

/// The orbit, frame after frame into one display: frame `k` at azimuth
/// `start + k * step` (modulo 360).
pub struct Orbiter<'s, 'm> {
    scene: Scene<'s>,
    name: String,
    renderer: Renderer<'m>,
    order: Order,
    size: (u32, u32),
    start_deg: f64,
    step_deg: f64,
    frame: u64,
}

impl Orbiter<'_, '_> {
    /// Draw the next frame into `display`; its azimuth and what the renderer counted.
    ///
    /// # Errors
    /// [`Error::Frame`], naming the frame.
    pub fn next_frame(
        &mut self,
        display: &mut SimulatorDisplay<Rgb565>,
    ) -> Result<(f64, FrameStats), Error> {
        let azimuth_deg = (self.start_deg + self.step_deg * self.frame as f64).rem_euclid(360.0);
        let (width, height) = self.size;
        let stats = frame::orbit_view(&self.scene.header(), azimuth_deg, width, height)
            .and_then(|view| {
                frame::draw_frame(&mut self.renderer, &self.scene, &view, self.order, display)
            })
            .map_err(|source| Error::Frame {
                scene: self.name.clone(),
                frame: self.frame,
                azimuth_deg,
                source,
            })?;
        self.frame += 1;
        Ok((azimuth_deg, stats))
    }
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Error> {
    let (bytes, name) = match &args.scene {
        Some(path) => {
            let bytes = std::fs::read(path).map_err(|source| Error::ReadFile {
                path: path.clone(),
                source,
            })?;
            (Cow::Owned(bytes), path.display().to_string())
        }
        None => (
            Cow::Borrowed(SCENE),
            concat!(env!("PEEL_DESKTOP_SCENE_NAME"), " (compiled by build.rs)").to_owned(),
        ),
    };
    let scene = Scene::parse(&bytes).map_err(|source| Error::Scene {
        scene: name.clone(),
        source,
    })?;
    let mut memory = match args.scene {
        Some(_) => Memory::any(&scene.header(), args.order),
        None => Memory::built_in(args.order),
    };
    let size = memory.size();
    let renderer = memory.renderer(args.order).map_err(Error::Memory)?;
    let mut orbit = Orbiter {
        scene,
        name,
        renderer,
        order: args.order,
        size,
        start_deg: args.azimuth,
        step_deg: args.step,
        frame: 0,
    };
    let mut display = SimulatorDisplay::<Rgb565>::new(Size::new(size.0, size.1));
    match &args.png {
        Some(path) => headless(&mut orbit, &mut display, args.frames, path),
        None => show(&mut orbit, &mut display, args.scale),
    }
}

/// Draw `frames` frames of the orbit, then write the display's pixels to `path` as PNG
/// (through a temporary file beside it: no PNG at all when a frame or the write fails).
fn headless(
    orbit: &mut Orbiter<'_, '_>,
    display: &mut SimulatorDisplay<Rgb565>,
    frames: u64,
    path: &Path,
) -> Result<(), Error> {
    let mut last = None;
    for _ in 0..frames {
        last = Some(orbit.next_frame(display)?);
    }
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let written = display
        .to_rgb_output_image(&OutputSettings::default())
        .save_png(&partial)
        .map_err(|e| e.to_string())
        .and_then(|()| std::fs::rename(&partial, path).map_err(|e| e.to_string()));
    if let Err(message) = written {
        // The partial file may not exist: nothing else to do about it.
        let _ = std::fs::remove_file(&partial);
        return Err(Error::Png {
            path: path.to_owned(),
            message,
        });
    }
    if let Some((azimuth_deg, stats)) = last {
        let (w, h) = orbit.size;
        println!(
            "{}: {name}, frame {frames} of the orbit (azimuth {azimuth_deg} degrees), {w}x{h}: \
             {} polygons drawn, {} pixels written",
            path.display(),
            stats.polygons_drawn,
            stats.pixels_written,
            name = orbit.name,
        );
    }
    Ok(())
}

/// The orbit in a window until it is closed.
#[cfg(feature = "window")]
fn show(
    orbit: &mut Orbiter<'_, '_>,
    display: &mut SimulatorDisplay<Rgb565>,
    scale: u32,
) -> Result<(), Error> {
    let title = format!("Peel: {}", orbit.name);
    window::run(orbit, display, &title, scale)
}

/// Without the `window` feature there is no window to show.
#[cfg(not(feature = "window"))]
fn show(_: &mut Orbiter<'_, '_>, _: &mut SimulatorDisplay<Rgb565>, _: u32) -> Result<(), Error> {
    Err(Error::NoWindow)
}
