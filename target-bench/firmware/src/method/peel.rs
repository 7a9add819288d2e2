//! Peel's renderer: front to back (into a framebuffer, streamed, in scan order, in bands) and
//! back to front (into a framebuffer, in bands).

use peel_runtime::camera::LocalView;
#[cfg(feature = "transparency")]
use peel_runtime::composite::{Composite, CompositeRun};
use peel_runtime::coverage::Coverage;
#[cfg(not(any(feature = "scan", feature = "smooth")))]
use peel_runtime::display::DrawTargetSink;
#[cfg(not(feature = "scan"))]
use peel_runtime::display::Rgb565Framebuffer;
#[cfg(feature = "aa")]
use peel_runtime::pending::Pending;
#[cfg(feature = "objects")]
use peel_runtime::place::{Object, ObjectMemory, Posed};
#[cfg(feature = "objects")]
use peel_runtime::read::Parts;
use peel_runtime::read::{Header, Scene};
use peel_runtime::render::{Renderer, Workspace};
#[cfg(feature = "scan")]
use peel_runtime::scan::ScanMemory;
use peel_runtime::vertices::{CachedVertex, VertexCache};
use peel_target_kit::config::{Config, Variant};

use crate::display::Panel;
use crate::pool::{Pool, Use};
use crate::{Failure, VARIANT};

use peel_target_kit::{STACK, VERTS};

/// Vertex memory entries (8 bytes each, 4,096 B): the vertices used close together in the
/// walk. 512 keep the teapot's streamed frame within 32 KiB of RAM on both cores.
const VERTEX_MEMORY: usize = 512;
/// The vertex memory ([`CachedVertex::EMPTY`] is all zeros: `.bss`).
static mut VERTEX_ENTRIES: [CachedVertex; VERTEX_MEMORY] = [CachedVertex::EMPTY; VERTEX_MEMORY];

/// Object memory of the streamed build (the scene with objects, [`peel_target_kit::objects`]):
/// its objects and the steps of the frame's order. From the pool, so that only a run with
/// objects counts it as RAM.
#[cfg(feature = "objects")]
type Memory =
    ObjectMemory<{ peel_target_kit::objects::OBJECTS }, { peel_target_kit::objects::STEPS }>;

/// A file of parts' objects and the poses of the current camera.
#[cfg(feature = "objects")]
struct Moving {
    objects: [Object<'static>; peel_target_kit::objects::OBJECTS],
    headers: [Header; peel_target_kit::objects::OBJECTS],
}

/// A Peel variant's scene, renderer and pixel memory.
#[cfg_attr(feature = "scan", allow(dead_code))]
pub struct Method {
    /// The scene, or a file of parts' world.
    scene: Scene<'static>,
    /// A file of parts' objects (`None` for a plain scene).
    #[cfg(feature = "objects")]
    moving: Option<Moving>,
    /// Made once, draws every frame (and band): the background set, span memory for one
    /// frame or band when front to back.
    renderer: Renderer<'static>,
    /// The framebuffer, the band buffer or (scan order) the row buffer; empty when streaming.
    pixels: &'static mut [u16],
    width: u32,
    height: u32,
    /// Rows per band (the height when not banded).
    band: u32,
    /// Anti-aliased: the pending-pixel records, and whether the last frame was anti-aliased.
    #[cfg(feature = "aa")]
    pending_records: usize,
    #[cfg(feature = "aa")]
    antialiased: bool,
    /// Transparency: the composite runs there are, and the rows of the last frame that fell
    /// back to screen-door transparency (`FrameStats::fallback_rows`).
    #[cfg(feature = "transparency")]
    composite_runs: usize,
    #[cfg(feature = "transparency")]
    fallback_rows: u32,
}

impl Method {
    /// Validate the scene (once, at boot), take the variant's memory and make the
    /// renderer. With objects never inlined: the workspace and object memory it moves into
    /// the pool would otherwise have slots in `run`'s stack frame, which every frame's stack
    /// peak counts.
    #[cfg_attr(feature = "objects", inline(never))]
    pub fn new(asset: &'static [u8], config: &Config, pool: &mut Pool) -> Result<Method, Failure> {
        #[cfg(feature = "objects")]
        let (parts, scene) = {
            let parts = Parts::parse(asset)?;
            (parts, parts.world().ok_or(Failure::NoWorld)?)
        };
        #[cfg(feature = "objects")]
        let objects = parts.object_count() as usize;
        // Other builds read a plain scene as before (a file of parts: `ReadError`'s version).
        #[cfg(not(feature = "objects"))]
        let scene = Scene::parse(asset)?;
        let (width, height) = (config.width, config.height);
        let band = if VARIANT.banded() {
            config.band_rows
        } else {
            height
        };
        #[cfg(not(feature = "objects"))]
        let mut renderer = {
            let workspace = cortex_m::singleton!(: Workspace<STACK, VERTS> = Workspace::new())
                .ok_or(Failure::Host("workspace taken twice"))?;
            Renderer::new(workspace).background(config.background_colour())
        };
        // The build that draws objects takes its workspace from the pool: a posed frame needs
        // longer clip buffers (its pieces' cuts), which a plain scene's run does not pay for.
        #[cfg(feature = "objects")]
        let mut renderer = {
            // Once only, for the vertex memory below.
            cortex_m::singleton!(: () = ()).ok_or(Failure::Host("renderer made twice"))?;
            let renderer = if objects > 0 {
                type Posed = Workspace<STACK, { peel_target_kit::objects::VERTS }>;
                Renderer::new(pool.value(Posed::new(), Use::Workspace)?)
            } else {
                type Plain = Workspace<STACK, VERTS>;
                Renderer::new(pool.value(Plain::new(), Use::Workspace)?)
            };
            renderer.background(config.background_colour())
        };
        // Without an FPU (a soft-float ABI) a subtree's box test costs more than it saves
        // in a whole frame; a band skips most of the tree by those tests, so there they pay.
        if !cfg!(target_abi = "eabihf") && !VARIANT.banded() {
            renderer = renderer.without_subtree_culling();
        }
        // Without an FPU a vertex costs thousands of instructions in software floats, a
        // fraction of that in integers; with one the `f32` path is the cheaper (and the
        // build leaves the feature out).
        if !cfg!(target_abi = "eabihf") {
            renderer = renderer.integer_vertices();
        }
        if VARIANT.front_to_back() {
            let rows = band as usize;
            let intervals = pool.pairs(config.spans_per_row as usize * rows, Use::SpanMemory)?;
            let counts = pool.u16s(rows, Use::RowCounts)?;
            renderer = renderer.span_memory(Coverage::new(intervals, counts, width, band)?);
        }
        // Scan order: the nodes the builder measures over an orbit, a head per row.
        #[cfg(feature = "scan")]
        {
            let nodes = pool.scan_nodes(config.scan_nodes as usize)?;
            let heads = pool.u16s(height as usize, Use::ScanHeads)?;
            renderer = renderer.scan_memory(ScanMemory::new(nodes, heads, width, height)?);
        }
        // Anti-aliased: the records the builder measures over an orbit (`PENDING_PIXELS`), a
        // list head per row. Element types as `Pending::new` takes them.
        #[cfg(feature = "aa")]
        {
            let n = config.pending_pixels as usize;
            let records = pool.filled(n, Default::default(), Use::PendingRecords)?;
            let heads = pool.filled(height as usize, Default::default(), Use::PendingHeads)?;
            renderer = renderer.antialias(Pending::new(records, heads, height)?);
        }
        // Transparency: the runs the runner measures over the orbit (none for an opaque
        // scene), a list head per row. Element types as `Composite::new` takes them.
        #[cfg(feature = "transparency")]
        if config.composite_runs > 0 {
            let n = config.composite_runs as usize;
            let runs = pool.filled(n, CompositeRun::default(), Use::CompositeRuns)?;
            let heads = pool.filled(height as usize, 0u16, Use::CompositeHeads)?;
            renderer = renderer.composite_memory(Composite::new(runs, heads, height)?);
        }
        // A static rather than a singleton, which would build the array in `main`'s stack
        // frame first and so count it twice (`.bss` and the stack's high-water mark).
        // SAFETY: the singleton above makes this run once, so this is the only reference.
        let vertices = unsafe { &mut *core::ptr::addr_of_mut!(VERTEX_ENTRIES) };
        renderer = renderer.vertex_memory(VertexCache::new(vertices));
        #[cfg(feature = "objects")]
        let moving = if objects > 0 {
            use peel_target_kit::objects::OBJECTS;
            if objects != OBJECTS {
                return Err(Failure::Objects(objects));
            }
            let memory = pool.value(Memory::new(), Use::ObjectMemory)?;
            renderer = renderer.object_memory(memory);
            let object = |k: usize| {
                let (_, scene) = parts.object(k as u32).ok_or(Failure::Objects(objects))?;
                Ok::<_, Failure>(Object::new(scene, None))
            };
            let objects = [object(0)?, object(1)?];
            Some(Moving {
                headers: objects.map(|o| o.scene.header()),
                objects,
            })
        } else {
            None
        };
        let pixel_count = match VARIANT {
            Variant::FtbStream | Variant::StreamAa => 0,
            // The row buffer a DMA takes each row from.
            Variant::ScanOrder | Variant::ScanAa => width as usize,
            _ => width as usize * band as usize,
        };
        Ok(Method {
            scene,
            #[cfg(feature = "objects")]
            moving,
            renderer,
            pixels: pool.u16s(pixel_count, Use::Framebuffer)?,
            width,
            height,
            band,
            #[cfg(feature = "aa")]
            pending_records: config.pending_pixels as usize,
            #[cfg(feature = "aa")]
            antialiased: false,
            #[cfg(feature = "transparency")]
            composite_runs: config.composite_runs as usize,
            #[cfg(feature = "transparency")]
            fallback_rows: 0,
        })
    }

    /// Transparency: the rows of the last frame that fell back to screen-door transparency,
    /// the most composite runs it held at once and the runs there are. With no row fallen
    /// back the frame's transparent pixels are exact.
    #[cfg(feature = "transparency")]
    pub fn transparency(&self) -> (u32, usize, usize) {
        let peak = self.renderer.composite().map_or(0, |c| c.peak());
        (self.fallback_rows, peak, self.composite_runs)
    }

    /// Anti-aliased: whether the last frame was, the most records it held pending at once
    /// and the records there are. A row falls back to plain pixels only when a pixel finds
    /// every record in use, so a peak below the records means none did.
    #[cfg(feature = "aa")]
    pub fn antialiasing(&self) -> (bool, usize, usize) {
        let peak = self.renderer.pending().map_or(0, |p| p.peak());
        (self.antialiased, peak, self.pending_records)
    }

    /// The scene's header (for the camera).
    pub fn header(&self) -> Header {
        self.scene.header()
    }

    /// A file of parts: pose its objects for camera `k` ([`peel_target_kit::objects::poses`]);
    /// the header that frames the posed scene (`None` for a plain scene).
    #[cfg(feature = "objects")]
    pub fn pose(&mut self, k: usize) -> Option<Header> {
        let moving = self.moving.as_mut()?;
        let poses = peel_target_kit::objects::poses(k, &moving.headers);
        for (object, pose) in moving.objects.iter_mut().zip(poses) {
            object.pose = Some(pose);
        }
        let world = self.scene.header();
        Some(peel_target_kit::objects::posed_header(
            &world,
            &moving.headers,
            &poses,
        ))
    }

    /// Bytes of pixel memory: the framebuffer, the band buffer or the row buffer (0 when
    /// streaming).
    pub fn framebuffer_bytes(&self) -> usize {
        core::mem::size_of_val(self.pixels)
    }

    /// Draw the frame seen by `view` and send it to `panel`; returns whether front to
    /// back ran out of span memory (the frame is then finished back to front: the same
    /// pixels, with overdraw).
    pub fn frame(&mut self, view: &LocalView, panel: &mut Panel) -> Result<bool, Failure> {
        #[cfg(feature = "scan")]
        {
            // The frame into scan memory, then to the panel in one window, each row read out
            // into the row buffer and sent as one transfer.
            let frame = self.renderer.draw_scan(&self.scene, view)?;
            #[cfg(feature = "aa")]
            {
                self.antialiased = frame.stats().antialiased;
            }
            panel.open_rows(0..self.height);
            for y in 0..self.height {
                frame.row_into(y, self.pixels);
                panel.send(self.pixels);
            }
            Ok(false)
        }
        #[cfg(not(feature = "scan"))]
        self.other_frame(view, panel)
    }

    /// [`Method::frame`] of the variants other than scan order.
    #[cfg(not(feature = "scan"))]
    fn other_frame(&mut self, view: &LocalView, panel: &mut Panel) -> Result<bool, Failure> {
        let (w, h) = (self.width, self.height);
        let scene = &self.scene;
        #[cfg(feature = "objects")]
        if let Some(moving) = &self.moving {
            return posed_frame(&mut self.renderer, *scene, moving, view, panel);
        }
        if matches!(VARIANT, Variant::FtbStream | Variant::StreamAa) {
            // Every span straight to the panel, the uncovered ones last (anti-aliased: the
            // pending pixels before them).
            // Builds that draw smooth files: the panel's own sink, a shaded span one write.
            #[cfg(feature = "smooth")]
            let stats =
                self.renderer
                    .draw(scene, view, &mut crate::display::PanelSink::new(panel))?;
            #[cfg(not(feature = "smooth"))]
            let stats = {
                let mut sink = DrawTargetSink::new(panel);
                let stats = self.renderer.draw(scene, view, &mut sink)?;
                let Ok(()) = sink.finish();
                stats
            };
            #[cfg(feature = "aa")]
            {
                self.antialiased = stats.antialiased;
            }
            #[cfg(feature = "transparency")]
            {
                self.fallback_rows = stats.fallback_rows;
            }
            return Ok(stats.fallback);
        }
        if !VARIANT.banded() {
            let mut fb = Rgb565Framebuffer::new(&mut self.pixels[..], w, h)?;
            let stats = self.renderer.draw(scene, view, &mut fb)?;
            panel.write_framebuffer(&fb);
            return Ok(stats.fallback);
        }
        // Band by band, each sent when drawn.
        let mut fallback = false;
        let mut first = 0;
        while first < h {
            let rows = first..(first + self.band).min(h);
            let mut fb = Rgb565Framebuffer::band(&mut self.pixels[..], w, rows.clone())?;
            let stats = self
                .renderer
                .draw_rows(scene, view, rows.clone(), &mut fb)?;
            panel.write_framebuffer(&fb);
            fallback |= stats.fallback;
            first = rows.end;
        }
        Ok(fallback)
    }
}

/// A posed frame streamed to `panel`; whether span memory ran out. Never inlined: inlined,
/// its stack frame (the plan's and the pieces' state) would be reserved by every frame of a
/// plain scene too, which the static baseline draws with this build.
#[cfg(feature = "objects")]
#[inline(never)]
fn posed_frame(
    renderer: &mut Renderer<'static>,
    world: Scene<'static>,
    moving: &Moving,
    view: &LocalView,
    panel: &mut Panel,
) -> Result<bool, Failure> {
    let posed = Posed::new(Some(world), &moving.objects);
    let stats = renderer.draw(&posed, view, &mut crate::display::PanelSink::new(panel))?;
    Ok(stats.fallback)
}
