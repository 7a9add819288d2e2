//! embedded-3dgfx 0.7.2 as a firmware engineer would set it up for a lit mesh: its z-buffer
//! path, `K3dengine::record` into a command buffer then `execute`, with per-face Lambert
//! colours (`RenderMode::SolidLightDir`), or for a smooth scene (vertex normals) its
//! per-vertex Lambert colours interpolated (`RenderMode::GouraudLightDir`), a 16-bit depth buffer (`depth-u16`) and an RGB565
//! framebuffer, sent to the panel as one block (`Panel::write_framebuffer`). One colour for the whole mesh,
//! lit from the compiler's default light direction `(0.4, 0.8, 0.45)` (towards the light, in
//! scene axes: [`LIGHT`]). The mesh, its faces and their normals stay in code memory
//! ([`peel_target_kit::gfx3d`]), as the library's README advises for MCUs. Not
//! `execute_tiled`: it only bins the triangles and still needs the whole framebuffer and
//! depth buffer.
//!
//! The build with textures (`--features embedded-3dgfx,textures`, the library's `textured`)
//! draws a textured scene as one mesh a group (a texture and a colour,
//! [`peel_target_kit::gfx3d::Group`]) in its textured mode lit per face
//! (`RenderMode::TexturedGouraud` with face normals only: each corner lit by its face's
//! normal, the texel times the lit colour), with `execute_with_textures` and a
//! `TextureManager` of the scene's textures read in place from code memory (RGB565, or a
//! palette and `u8` indices: `Texture::new_palettized8`), nearest texel, perspective-correct
//! at the ends of 16-pixel runs (its defaults). It always repeats a texture (it has no
//! clamp). An untextured scene draws as in the other build, through `execute_with_textures`.

use core::convert::Infallible;

use embedded_3dgfx::engine::K3dengine;
use embedded_3dgfx::error::RenderError;
use embedded_3dgfx::pipeline::command_buffer::CommandBuffer;
#[cfg(feature = "textures")]
use embedded_3dgfx::pipeline::rasterize::texture::{Texture, TextureManager};
use embedded_3dgfx::pipeline::renderer::FrameCtx;
use embedded_3dgfx::pipeline::vertex::mesh::{Geometry, K3dMesh, RenderMode};
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565};
use embedded_graphics_core::Pixel;
use nalgebra::{Point3, Vector3};
use peel_runtime::camera::LocalView;
use peel_runtime::display::Rgb565Framebuffer;
use peel_runtime::read::Header;
use peel_target_kit::config::Config;
use peel_target_kit::gfx3d::{Gfx3dError, Scene, LIGHT};

use crate::display::Panel;
use crate::pool::{Pool, Use};
use crate::Failure;

/// Capacity of the command buffer, a const generic of the library (44 bytes a command): the
/// depth clear and one command per front face drawn (`SolidLightDir` neither clips nor splits
/// a triangle). Set at build time (`PEEL_GFX3D_COMMANDS`, see `build.rs`): the runner builds
/// with the most a scene needs over its cameras (the teapot 3,184, the cow 2,965), found by a
/// run with a larger buffer; a scene that needs more fails with `OutOfBudget`.
pub const COMMANDS: usize = parse(env!("GFX3D_COMMANDS"));

/// A decimal number (checked by `build.rs`).
const fn parse(digits: &str) -> usize {
    let bytes = digits.as_bytes();
    let (mut n, mut k) = (0, 0);
    while k < bytes.len() {
        n = n * 10 + (bytes[k] - b'0') as usize;
        k += 1;
    }
    n
}

/// Textures a scene may have (the library's `TextureManager` capacity).
#[cfg(feature = "textures")]
const MAX_TEXTURES: usize = 8;

/// The command buffer, in `.bss` (counted in the statics; a `CommandBuffer` is the library's
/// own type, so it cannot come from the pool's words).
static mut COMMAND_BUFFER: CommandBuffer<COMMANDS> = CommandBuffer::new();

// The faces are read in place as the library's `[usize; 3]` from the scene's `u32` indices.
const _: () = assert!(core::mem::size_of::<usize>() == 4);

/// What stopped embedded-3dgfx.
#[derive(Debug)]
pub enum Gfx3dFailure {
    /// The scene bytes.
    Scene(Gfx3dError),
    /// Scene bytes that are not 4-aligned in code memory: they cannot be read in place.
    Misaligned,
    /// An image too large for the library's 16-bit sizes.
    ImageTooLarge,
    /// More textures than the texture manager holds ([`MAX_TEXTURES`]).
    #[cfg(feature = "textures")]
    TooManyTextures(u32),
    /// The library.
    Render(RenderError),
}

impl core::fmt::Display for Gfx3dFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Gfx3dFailure::Scene(e) => write!(f, "{e}"),
            Gfx3dFailure::Misaligned => write!(f, "scene not 4-aligned in code memory"),
            Gfx3dFailure::ImageTooLarge => write!(f, "image over 65535 pixels wide or high"),
            #[cfg(feature = "textures")]
            Gfx3dFailure::TooManyTextures(n) => {
                write!(f, "{n} textures, the texture manager holds {MAX_TEXTURES}")
            }
            // The library's errors have no `Display`.
            Gfx3dFailure::Render(e) => write!(f, "{e:?}"),
        }
    }
}

impl From<Gfx3dFailure> for Failure {
    fn from(e: Gfx3dFailure) -> Self {
        Failure::Gfx3d(e)
    }
}

impl From<RenderError> for Failure {
    fn from(e: RenderError) -> Self {
        Failure::Gfx3d(Gfx3dFailure::Render(e))
    }
}

impl From<Gfx3dError> for Failure {
    fn from(e: Gfx3dError) -> Self {
        Failure::Gfx3d(Gfx3dFailure::Scene(e))
    }
}

/// An element of the scene read in place: numbers, any bit pattern valid.
trait Plain {}
impl Plain for [f32; 3] {}
impl Plain for [usize; 3] {}
#[cfg(feature = "textures")]
impl Plain for [f32; 2] {}
// An RGB565 texel: one `u16` (its only field, so at offset 0 of a 2-byte value), any value a
// colour.
#[cfg(feature = "textures")]
impl Plain for Rgb565 {}
#[cfg(feature = "textures")]
const _: () = assert!(core::mem::size_of::<Rgb565>() == 2 && core::mem::align_of::<Rgb565>() == 2);

/// `bytes` (a whole number of `T`) as `T`s, in place.
fn in_place<T: Plain>(bytes: &'static [u8]) -> Result<&'static [T], Failure> {
    let size = core::mem::size_of::<T>();
    if bytes.as_ptr().align_offset(core::mem::align_of::<T>()) != 0
        || !bytes.len().is_multiple_of(size)
    {
        return Err(Gfx3dFailure::Misaligned.into());
    }
    // SAFETY: aligned, within `bytes`, which are never written (code memory), and every bit
    // pattern is a `T` ([`Plain`]); little-endian like the scene (and a `.peel` file's texels).
    Ok(unsafe { core::slice::from_raw_parts(bytes.as_ptr().cast::<T>(), bytes.len() / size) })
}

/// The framebuffer as the library's draw target: it writes one pixel per `draw_iter` call.
struct Target<'a> {
    pixels: &'a mut [u16],
    width: u32,
    height: u32,
}

impl OriginDimensions for Target<'_> {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Target<'_> {
    type Color = Rgb565;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        for Pixel(p, colour) in pixels {
            let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) else {
                continue;
            };
            if x < self.width && y < self.height {
                self.pixels[(y * self.width + x) as usize] = colour.into_storage();
            }
        }
        Ok(())
    }
}

/// The engine, the mesh, the command buffer, the framebuffer and the depth buffer.
pub struct Method {
    scene: Scene<'static>,
    engine: K3dengine,
    #[cfg(not(feature = "textures"))]
    mesh: K3dMesh<'static>,
    /// The build with textures: a mesh a group of a textured scene (one for another scene),
    /// and the textures.
    #[cfg(feature = "textures")]
    meshes: &'static mut [K3dMesh<'static>],
    #[cfg(feature = "textures")]
    textures: &'static mut TextureManager<MAX_TEXTURES>,
    commands: &'static mut CommandBuffer<COMMANDS>,
    colour: &'static mut [u16],
    depth: &'static mut [u16],
    width: u32,
    height: u32,
    background: u16,
    /// The most commands a frame recorded.
    commands_peak: usize,
}

impl Method {
    /// Validate the scene (once, at boot), make the mesh and the engine, take the buffers.
    pub fn new(asset: &'static [u8], config: &Config, pool: &mut Pool) -> Result<Method, Failure> {
        let scene = Scene::parse(asset)?;
        let (width, height) = (config.width, config.height);
        let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
            return Err(Gfx3dFailure::ImageTooLarge.into());
        };
        // The library negates the light's z before its dot product with the normal: this is
        // the direction towards the light `LIGHT` (the compiler's default) in scene axes.
        let light = Vector3::new(LIGHT[0], LIGHT[1], -LIGHT[2]);
        // Indices and sizes were checked by `parse`: the library's own check (an assertion)
        // passes.
        #[cfg(not(feature = "textures"))]
        let mesh = whole_mesh(&scene, light)?;
        #[cfg(feature = "textures")]
        let (meshes, textures) = {
            let textures = pool.value(TextureManager::new(), Use::Textures)?;
            for k in 0..scene.texture_count() {
                let texture = texture(&scene, k)?;
                textures
                    .add_texture(texture)
                    .ok_or(Gfx3dFailure::TooManyTextures(scene.texture_count()))?;
            }
            let meshes = if scene.textured() {
                let groups = scene.group_count() as usize;
                pool.made(groups, |g| group_mesh(&scene, g as u32, light), Use::Meshes)?
            } else {
                pool.made(1, |_| whole_mesh(&scene, light), Use::Meshes)?
            };
            (meshes, textures)
        };
        cortex_m::singleton!(: () = ()).ok_or(Failure::Host("command buffer taken twice"))?;
        // SAFETY: the singleton above makes this run once, so this is the only reference.
        let commands = unsafe { &mut *core::ptr::addr_of_mut!(COMMAND_BUFFER) };
        let n = width as usize * height as usize;
        Ok(Method {
            scene,
            engine: K3dengine::new(w, h),
            #[cfg(not(feature = "textures"))]
            mesh,
            #[cfg(feature = "textures")]
            meshes,
            #[cfg(feature = "textures")]
            textures,
            commands,
            colour: pool.u16s(n, Use::Framebuffer)?,
            depth: pool.u16s(n, Use::DepthBuffer)?,
            width,
            height,
            background: config.background_colour().to_rgb565(),
            commands_peak: 0,
        })
    }

    /// The most commands a frame recorded, and the buffer's capacity.
    pub fn commands(&self) -> (usize, usize) {
        (self.commands_peak, COMMANDS)
    }

    /// The scene's header (for the camera).
    pub fn header(&self) -> Header {
        self.scene.header()
    }

    /// Bytes of pixel memory: the framebuffer (the depth buffer is not pixels).
    pub fn framebuffer_bytes(&self) -> usize {
        core::mem::size_of_val(self.colour)
    }

    /// Draw the frame seen by `view` and send it to `panel` (never a fallback).
    pub fn frame(&mut self, view: &LocalView, panel: &mut Panel) -> Result<bool, Failure> {
        let setup = self.scene.camera(view);
        let camera = &mut self.engine.camera;
        camera.set_fovy(setup.fov_y);
        camera.set_near_far(setup.near, setup.far);
        camera.set_position(Point3::from(setup.eye));
        camera.set_target(Point3::from(setup.target));
        // The depth clear, then one triangle per front face.
        #[cfg(not(feature = "textures"))]
        self.engine
            .record(core::iter::once(&self.mesh), self.commands, None)?;
        #[cfg(feature = "textures")]
        self.engine
            .record(self.meshes.iter(), self.commands, None)?;
        self.commands_peak = self.commands_peak.max(self.commands.len());
        // `record` asks for no colour clear.
        self.colour.fill(self.background);
        let (width, height) = (self.width as usize, self.height as usize);
        let mut frame = FrameCtx {
            zbuffer: &mut self.depth[..],
            width,
            height,
        };
        let mut target = Target {
            pixels: &mut self.colour[..],
            width: self.width,
            height: self.height,
        };
        #[cfg(not(feature = "textures"))]
        self.engine
            .execute(&mut target, &mut frame, self.commands, None)?;
        #[cfg(feature = "textures")]
        self.engine.execute_with_textures(
            &mut target,
            &mut frame,
            self.commands,
            self.textures,
            None,
        )?;
        let fb = Rgb565Framebuffer::new(&mut self.colour[..], self.width, self.height)?;
        panel.write_framebuffer(&fb);
        Ok(false)
    }
}

/// The whole scene as one mesh of its one colour, lit per face, or for a smooth scene (vertex
/// normals) each corner lit and the colours interpolated.
fn whole_mesh(scene: &Scene<'static>, light: Vector3<f32>) -> Result<K3dMesh<'static>, Failure> {
    let geometry = Geometry::new(
        in_place(scene.vertex_bytes())?,
        in_place(scene.face_bytes())?,
    )
    .with_normals(in_place(scene.normal_bytes())?)
    .with_vertex_normals(in_place(scene.vertex_normal_bytes())?);
    let mut mesh = K3dMesh::new(geometry);
    mesh.color = Rgb565::from(RawU16::new(scene.colour()));
    mesh.render_mode = if scene.smooth() {
        RenderMode::GouraudLightDir(light)
    } else {
        RenderMode::SolidLightDir(light)
    };
    Ok(mesh)
}

/// Group `g` of a textured scene as one mesh of its colour lit per face: textured
/// (`TexturedGouraud` without vertex normals: each corner lit by its face's normal) when it
/// has a texture, else as [`whole_mesh`] lights a flat scene.
#[cfg(feature = "textures")]
fn group_mesh(
    scene: &Scene<'static>,
    g: u32,
    light: Vector3<f32>,
) -> Result<K3dMesh<'static>, Failure> {
    let group = scene.group(g).ok_or(Gfx3dError::Group(g))?;
    let geometry = Geometry::new(in_place(group.vertices)?, in_place(group.faces)?)
        .with_normals(in_place(group.normals)?)
        .with_uvs(in_place(group.uvs)?);
    let (geometry, mode) = match group.texture {
        // Textures are added in order: texture `k` has id `k`.
        Some(k) => (geometry.with_texture(k), RenderMode::TexturedGouraud(light)),
        None => (geometry, RenderMode::SolidLightDir(light)),
    };
    let mut mesh = K3dMesh::new(geometry);
    mesh.color = Rgb565::from(RawU16::new(group.colour));
    mesh.render_mode = mode;
    Ok(mesh)
}

/// Texture `k` of `scene` as the library's, its bytes read in place: RGB565 texels, or a
/// palette and `u8` indices.
#[cfg(feature = "textures")]
fn texture(scene: &Scene<'static>, k: u32) -> Result<Texture, Failure> {
    use peel_runtime::read::layout::texture_flags::PALETTE;
    let t = scene.texture(k).ok_or(Gfx3dError::Texture(k))?;
    let (w, h) = (1u32 << t.log2_width, 1u32 << t.log2_height);
    Ok(if t.flags & PALETTE != 0 {
        Texture::new_palettized8(t.texels, in_place(t.colours)?, w, h)
    } else {
        Texture::new(in_place(t.texels)?, w, h)
    })
}
