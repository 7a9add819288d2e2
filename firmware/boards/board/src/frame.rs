//! How a frame reaches the panel: the one place that decides it.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::Rgb565;
use peel_runtime::camera::LocalView;
use peel_runtime::read::Scene;
use peel_runtime::render::Renderer;
use peel_runtime::stats::FrameStats;

use crate::Failure;

/// Draw the frame `view` sees and send it to `panel` in scan order: the walk keeps every
/// covered interval with its colour in scan memory (anti-aliased, the partly covered pixels
/// in pending memory), then the frame goes out row by row, top to bottom, in one address
/// window (one `fill_contiguous`: mipidsi sets the window once and streams the pixels), so
/// the panel never shows two frames mixed beyond the row being written. A frame needing more
/// scan memory than the build script measured is an error (`RenderError::ScanMemoryFull`),
/// sent nowhere: never a frame with overdraw. Returns what the walk did.
pub fn draw_frame<D>(
    renderer: &mut Renderer<'_>,
    scene: &Scene<'_>,
    view: &LocalView,
    panel: &mut D,
) -> Result<FrameStats, Failure>
where
    D: DrawTarget<Color = Rgb565>,
{
    let frame = renderer.draw_scan(scene, view)?;
    frame.draw_to(panel).map_err(|_| Failure::Hardware)?;
    Ok(frame.stats())
}
