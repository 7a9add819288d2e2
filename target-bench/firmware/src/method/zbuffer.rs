//! The integer z-buffer baseline: the whole frame into a framebuffer (`zbuffer`), or tiled
//! (`tiled-zbuffer`): band by band, the whole mesh submitted again for each band, into a
//! band-sized colour and depth buffer sent when done.

use peel_runtime::camera::LocalView;
use peel_runtime::display::Rgb565Framebuffer;
use peel_runtime::read::Header;
use peel_target_kit::config::Config;
use peel_target_kit::mesh::Mesh;

use crate::display::Panel;
use crate::pool::{Pool, Use};
use crate::{Failure, VARIANT};

/// The mesh, the colour and the depth buffer (a frame's or a band's).
pub struct Method {
    mesh: Mesh<'static>,
    colour: &'static mut [u16],
    depth: &'static mut [u16],
    width: u32,
    height: u32,
    /// Rows per band (the height when not banded).
    band: u32,
    background: u16,
}

impl Method {
    /// Validate the mesh (once, at boot) and take the buffers.
    pub fn new(asset: &'static [u8], config: &Config, pool: &mut Pool) -> Result<Method, Failure> {
        let band = if VARIANT.banded() {
            config.band_rows
        } else {
            config.height
        };
        let n = config.width as usize * band as usize;
        Ok(Method {
            mesh: Mesh::parse(asset)?,
            colour: pool.u16s(n, Use::Framebuffer)?,
            depth: pool.u16s(n, Use::DepthBuffer)?,
            width: config.width,
            height: config.height,
            band,
            background: config.background_colour().to_rgb565(),
        })
    }

    /// The scene's header (for the camera).
    pub fn header(&self) -> Header {
        self.mesh.header()
    }

    /// Bytes of pixel memory: the framebuffer or band buffer (the depth buffer is not pixels).
    pub fn framebuffer_bytes(&self) -> usize {
        core::mem::size_of_val(self.colour)
    }

    /// Draw the frame seen by `view` and send it to `panel`, band by band when tiled (never a
    /// fallback).
    pub fn frame(&mut self, view: &LocalView, panel: &mut Panel) -> Result<bool, Failure> {
        let (w, h) = (self.width, self.height);
        let mut first = 0;
        while first < h {
            let rows = first..(first + self.band).min(h);
            peel_target_kit::zbuffer::draw_rows(
                &self.mesh,
                view,
                self.background,
                rows.clone(),
                self.colour,
                self.depth,
            )?;
            let fb = Rgb565Framebuffer::band(&mut self.colour[..], w, rows.clone())?;
            panel.write_framebuffer(&fb);
            first = rows.end;
        }
        Ok(false)
    }
}
