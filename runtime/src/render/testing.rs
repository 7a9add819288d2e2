//! Shorthands for the render tests: one frame drawn by a fresh [`Renderer`].

use super::*;
use crate::camera::{Camera, LocalView};
use crate::coverage::Coverage;
use crate::display::SpanSink;
use crate::error::RenderError;
use crate::fill;
use crate::traverse::Order;
use crate::vertices::VertexCache;

/// How a test frame is drawn: front to back (given span memory), colours, culling on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Options {
    pub order: Order,
    pub paint: Paint,
    pub cull: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            order: Order::FrontToBack,
            paint: Paint::Colours,
            cull: true,
        }
    }
}

/// The memory a test frame's renderer gets besides its workspace.
#[derive(Debug, Default)]
pub(crate) struct Memory<'m, const SUB: u32 = { fill::SUBPIXEL_BITS }> {
    pub coverage: Option<Coverage<'m>>,
    pub vertices: Option<VertexCache<'m, SUB>>,
}

impl<'m, const SUB: u32> From<Coverage<'m>> for Memory<'m, SUB> {
    fn from(coverage: Coverage<'m>) -> Self {
        Memory {
            coverage: Some(coverage),
            vertices: None,
        }
    }
}

/// Back to front at the default precision, with culling.
pub(crate) fn draw_test_frame<T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    paint: Paint,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    draw_test_frame_at::<{ fill::SUBPIXEL_BITS }, T, S, STACK, VERTS>(
        scene, camera, workspace, paint, sink,
    )
}

/// Back to front at `SUB` fractional bits, with culling.
pub(crate) fn draw_test_frame_at<const SUB: u32, T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS, SUB>,
    paint: Paint,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    let options = Options {
        order: Order::BackToFront,
        paint,
        cull: true,
    };
    draw_test_frame_with_at::<SUB, T, S, STACK, VERTS>(
        scene,
        camera,
        workspace,
        options,
        Memory::default(),
        sink,
    )
}

/// As `options` say, at the default precision.
pub(crate) fn draw_test_frame_with<T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS>,
    options: Options,
    memory: Memory<'_>,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    draw_test_frame_with_at::<{ fill::SUBPIXEL_BITS }, T, S, STACK, VERTS>(
        scene, camera, workspace, options, memory, sink,
    )
}

/// As `options` say, at `SUB` fractional bits, for a camera.
pub(crate) fn draw_test_frame_with_at<
    const SUB: u32,
    T,
    S,
    const STACK: usize,
    const VERTS: usize,
>(
    scene: &T,
    camera: &Camera,
    workspace: &mut Workspace<STACK, VERTS, SUB>,
    options: Options,
    memory: Memory<'_, SUB>,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    let view = camera.view(scene.centre());
    draw::<SUB, T, S, STACK, VERTS>(scene, &view, workspace, options, memory, sink)
}

/// One frame by a renderer made for it, for a view: span memory only when `options` ask for
/// front to back, so that back to front draws without it as a caller would.
pub(crate) fn draw<const SUB: u32, T, S, const STACK: usize, const VERTS: usize>(
    scene: &T,
    view: &LocalView,
    workspace: &mut Workspace<STACK, VERTS, SUB>,
    options: Options,
    memory: Memory<'_, SUB>,
    sink: &mut S,
) -> Result<FrameStats, RenderError>
where
    T: Source + ?Sized,
    S: SpanSink + ?Sized,
{
    let mut renderer = Renderer::<SUB>::with_precision(workspace);
    if let Some(c) = memory.coverage {
        renderer = renderer.span_memory(c);
    }
    if let Some(v) = memory.vertices {
        renderer = renderer.vertex_memory(v);
    }
    if options.order == Order::BackToFront {
        renderer = renderer.back_to_front();
    }
    if options.paint == Paint::Ids {
        renderer = renderer.ids();
    }
    if !options.cull {
        renderer = renderer.without_culling();
    }
    renderer.draw(scene, view, sink)
}
