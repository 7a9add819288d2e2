//! The scanline z-buffer ([`peel_target_kit::scanline`]): one row of colour and depth, each
//! row sent to the panel when done (one window for the frame, one transfer per row, as scan
//! order sends its rows), lists sized for the scene.

use peel_runtime::camera::LocalView;
use peel_runtime::fill::SubpixelPoint;
use peel_runtime::read::Header;
use peel_target_kit::config::Config;
use peel_target_kit::mesh::Mesh;
use peel_target_kit::scanline::{self, ActiveEdge, Lists, Polygon, RowSink};

use crate::display::Panel;
use crate::pool::{Pool, Use};
use crate::Failure;

/// The mesh and the lists.
pub struct Method {
    mesh: Mesh<'static>,
    lists: Lists<'static>,
    background: u16,
}

impl Method {
    /// Validate the mesh (once, at boot) and take the lists: a polygon table entry per
    /// triangle, a screen point per vertex, a list head per row, one row of colour and depth,
    /// and the active edges and clipped points the config block asks for (the most the camera
    /// path needs, measured on the host).
    pub fn new(asset: &'static [u8], config: &Config, pool: &mut Pool) -> Result<Method, Failure> {
        let mesh = Mesh::parse(asset)?;
        let header = mesh.header();
        let (w, h) = (config.width as usize, config.height as usize);
        let list = Use::ScanlineList;
        let lists = Lists {
            polygons: pool.filled(header.polygon_count as usize, Polygon::EMPTY, list)?,
            vertices: pool.filled(header.vertex_count as usize, SubpixelPoint::default(), list)?,
            extra: pool.filled(
                config.clipped_points as usize,
                SubpixelPoint::default(),
                list,
            )?,
            heads: pool.filled(h, 0u32, list)?,
            active: pool.filled(config.active_edges as usize, ActiveEdge::default(), list)?,
            colour: pool.u16s(w, Use::Framebuffer)?,
            depth: pool.u16s(w, Use::DepthBuffer)?,
        };
        Ok(Method {
            mesh,
            lists,
            background: config.background_colour().to_rgb565(),
        })
    }

    /// The scene's header (for the camera).
    pub fn header(&self) -> Header {
        self.mesh.header()
    }

    /// Bytes of pixel memory: one row.
    pub fn framebuffer_bytes(&self) -> usize {
        core::mem::size_of_val(self.lists.colour)
    }

    /// Draw the frame seen by `view`, each row sent to `panel` when done (never a fallback).
    pub fn frame(&mut self, view: &LocalView, panel: &mut Panel) -> Result<bool, Failure> {
        // The rows come top to bottom: one window holds them all.
        panel.open_rows(0..view.height);
        let mut rows = Rows(panel);
        scanline::draw(
            &self.mesh,
            view,
            self.background,
            &mut self.lists,
            &mut rows,
        )?;
        Ok(false)
    }
}

/// Rows to the panel's open window, one transfer each.
struct Rows<'p>(&'p mut Panel);

impl RowSink for Rows<'_> {
    fn row(&mut self, _y: u32, pixels: &[u16]) {
        self.0.send(pixels);
    }
}
