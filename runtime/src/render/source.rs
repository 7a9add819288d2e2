//! What a [`Renderer`](super::Renderer) reads from a scene: the [`Source`] trait, on top of
//! the traversal's [`Tree`], and its implementation for a parsed [`Scene`]. It exists apart
//! so that the renderer depends on this small interface, not on the file format: tests draw
//! small in-memory trees through it, and a scene stored another way needs only this trait.

use glam::Vec3;

use crate::display::Colour;
use crate::read::{Polygon, Scene, Texture};
use crate::traverse::Tree;

/// Everything a [`Renderer`] reads from a scene; [`Scene`] implements it (tests use small
/// in-memory trees).
///
/// [`Renderer`]: super::Renderer
pub trait Source: Tree {
    /// World position the scene's coordinates are relative to.
    fn centre(&self) -> [f64; 3];
    /// Largest polygon vertex count.
    fn max_polygon_vertices(&self) -> u32;
    /// Vertex `i` of `polygon`, relative to the centre.
    fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3;
    /// Whether the scene holds triangle ids.
    fn has_ids(&self) -> bool;
    /// Source triangle id of polygon `i`.
    fn id(&self, i: u32) -> Option<u32>;
    /// The colour polygon `i` (whose record is `polygon`) shows an eye on its interior side
    /// (`interior`) or on its exterior side. The default: one colour for both.
    fn colour_seen(&self, i: u32, polygon: &Polygon, interior: bool) -> Colour {
        let _ = (i, interior);
        polygon.colour
    }
    /// Bounding box `(min, max)` of the polygons of node `i`'s subtree, relative to the
    /// centre, when the scene stores one (it is never required).
    fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        let _ = i;
        None
    }
    /// Node `i`'s box in the 16-bit steps of its vertices ([`Source::vertex_steps`]), when the
    /// scene stores one: it holds the steps of every vertex of the subtree.
    fn node_box_steps(&self, i: u32) -> Option<([u16; 3], [u16; 3])> {
        let _ = i;
        None
    }
    /// The index of vertex `i` of `polygon` in the scene's shared vertex list, when it has one:
    /// a frame then projects each shared vertex once, the first time its index comes, from the
    /// position [`Source::polygon_vertex`] gives (see [`crate::vertices`]). Equal indices must
    /// therefore mean equal positions.
    fn vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        let _ = (polygon, i);
        None
    }
    /// Shared vertex `v`, relative to the centre: what [`Source::polygon_vertex`] gives for a
    /// vertex whose [`Source::vertex_index`] is `v`, read without the polygon's index again.
    /// Only asked for indices that [`Source::vertex_index`] gave, so a source without shared
    /// vertices keeps the default.
    fn vertex(&self, v: u32) -> Vec3 {
        let _ = v;
        Vec3::ZERO
    }
    /// `(min, step)` when every shared vertex lies at exactly `min + q ∘ step` for its 16-bit
    /// steps `q` ([`Source::vertex_steps`]), which [`super::Renderer::integer_vertices`]
    /// projects in integers; `None` (the default) keeps the `f32` path.
    fn step_grid(&self) -> Option<(Vec3, Vec3)> {
        None
    }
    /// The steps `q` of shared vertex `v` (see [`Source::step_grid`]).
    fn vertex_steps(&self, v: u32) -> Option<[u16; 3]> {
        let _ = v;
        None
    }
    /// For a smoothly shaded `polygon`, which of its corners' two intensities shade the side an
    /// eye on its interior side (`interior`) or exterior side sees ([`Scene::shade_side`]);
    /// `None` (the default) for a polygon of one colour a side.
    fn shade_side(&self, polygon: &Polygon, interior: bool) -> Option<usize> {
        let _ = (polygon, interior);
        None
    }
    /// Intensity `side` of corner `i` of `polygon` (255: the full colour), for a side that
    /// [`Source::shade_side`] named.
    fn corner_shade(&self, polygon: &Polygon, i: u32, side: usize) -> u8 {
        let _ = (polygon, i, side);
        u8::MAX
    }
    /// The texture of polygon `i`, or `None` (the default) for an untextured polygon.
    fn texture(&self, i: u32) -> Option<Texture<'_>> {
        let _ = i;
        None
    }
    /// The texture coordinates `[s, t]` of corner `i` of `polygon` (`2^16` a whole side of
    /// its texture), for a polygon that [`Source::texture`] gave a texture.
    fn corner_uv(&self, polygon: &Polygon, i: u32) -> [i32; 2] {
        let _ = (polygon, i);
        [0, 0]
    }
    /// Whether some polygon is transparent ([`Source::opacity`] below 255); `false` (the
    /// default) for an opaque scene, whose frames need no composite memory.
    fn has_transparency(&self) -> bool {
        false
    }
    /// The opacity of polygon `i` (of 255; 255, the default, is opaque).
    fn opacity(&self, i: u32, polygon: &Polygon) -> u8 {
        let _ = (i, polygon);
        u8::MAX
    }
}

impl Source for Scene<'_> {
    fn centre(&self) -> [f64; 3] {
        self.header().centre
    }
    fn max_polygon_vertices(&self) -> u32 {
        self.header().max_polygon_vertices
    }
    fn polygon_vertex(&self, polygon: &Polygon, i: u32) -> Vec3 {
        Scene::polygon_vertex(self, polygon, i)
    }
    fn has_ids(&self) -> bool {
        self.header().flags & crate::read::layout::header_flags::IDS != 0
    }
    fn id(&self, i: u32) -> Option<u32> {
        Scene::id(self, i)
    }
    fn colour_seen(&self, i: u32, polygon: &Polygon, interior: bool) -> Colour {
        let _ = polygon;
        Scene::colour_seen(self, i, interior)
    }
    fn node_bounds(&self, i: u32) -> Option<(Vec3, Vec3)> {
        Scene::node_bounds(self, i)
    }
    fn node_box_steps(&self, i: u32) -> Option<([u16; 3], [u16; 3])> {
        Scene::node_box_steps(self, i)
    }
    fn vertex_index(&self, polygon: &Polygon, i: u32) -> Option<u32> {
        Scene::polygon_vertex_index(self, polygon, i)
    }
    fn vertex(&self, v: u32) -> Vec3 {
        Scene::vertex(self, v)
    }
    fn step_grid(&self) -> Option<(Vec3, Vec3)> {
        Scene::step_grid(self)
    }
    fn vertex_steps(&self, v: u32) -> Option<[u16; 3]> {
        Scene::vertex_steps(self, v)
    }
    fn shade_side(&self, polygon: &Polygon, interior: bool) -> Option<usize> {
        Scene::shade_side(polygon.flags, interior)
    }
    fn corner_shade(&self, polygon: &Polygon, i: u32, side: usize) -> u8 {
        Scene::polygon_vertex_index(self, polygon, i).map_or(0, |v| self.vertex_shade(v, side))
    }
    fn texture(&self, i: u32) -> Option<Texture<'_>> {
        Scene::polygon_texture(self, i)
    }
    fn corner_uv(&self, polygon: &Polygon, i: u32) -> [i32; 2] {
        Scene::polygon_vertex_index(self, polygon, i).map_or([0, 0], |v| self.vertex_uv(v))
    }
    fn has_transparency(&self) -> bool {
        Scene::has_transparency(self)
    }
    fn opacity(&self, i: u32, polygon: &Polygon) -> u8 {
        self.opacity_of(i, polygon.flags)
    }
}
