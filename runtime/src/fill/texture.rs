//! A textured polygon's perspective map over the pixel grid ([`TextureMap`]): `w = 1/z`,
//! `s/z` and `t/z` as integer planes (a value at pixel `(0, 0)` and a step a column and a
//! row, wrapping `i32`s as a [`Gradient`]'s), handed to a sink one row at a time
//! ([`RowTexture`]), which divides at the ends of short runs (see its module).
//!
//! The renderer sets the planes up in `f32` from the polygon's plane in camera space
//! (`render/texture.rs`), scaled so that every value the polygon's pixels reach fits: `w` at
//! most `2^30`, `s` and `t` at most `2^30` in magnitude. Rounding the steps to integers errs
//! by half a unit a pixel away from the anchor, a few hundred units across a frame: below
//! `2^-20` of a polygon's nearest `w`.

use super::gradient::Gradient;
use super::Shader;
use crate::display::{Colour, Filter, Modulation, RowTexture, SpanSink};
use crate::read::Texture;

/// What a [`TextureMap`]'s texels are multiplied by, for the whole polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lighting<const SUB: u32> {
    /// One colour (white: none).
    Colour(Colour),
    /// A smooth polygon's gradient.
    Smooth(Gradient<SUB>),
}

/// A textured polygon's perspective planes over the pixel grid and its lighting:
/// [`TextureMap::row`] gives each row's [`RowTexture`].
#[derive(Debug, Clone, Copy)]
pub struct TextureMap<'a, const SUB: u32> {
    texture: Texture<'a>,
    /// `[w, s, t]` at the centre of pixel `(0, 0)`, modulo `2^32`.
    origin: [i32; 3],
    /// Their change a pixel to the right and a row down, modulo `2^32`.
    step: [i32; 3],
    row_step: [i32; 3],
    shift: [u8; 2],
    lighting: Lighting<SUB>,
    filter: Filter,
}

/// Largest magnitude of a plane's step: beyond, the polygon is a sliver the planes cannot
/// describe in `i32`.
const MAX_STEP: f32 = 2_147_483_000.0;

impl<'a, const SUB: u32> TextureMap<'a, SUB> {
    /// The map of `planes` (`[w, s, t]`, each `[per column, per row, at the centre of pixel
    /// anchor]` in `f32`, scaled as the module says), with `shift` the powers of two that
    /// `s / w` and `t / w` are short of the file's coordinates. `None` when a value is not
    /// finite or a step too large for `i32`.
    pub fn new(
        texture: Texture<'a>,
        planes: [[f32; 3]; 3],
        anchor: (u32, u32),
        shift: [u8; 2],
        lighting: Lighting<SUB>,
        filter: Filter,
    ) -> Option<Self> {
        let mut map = TextureMap {
            texture,
            origin: [0; 3],
            step: [0; 3],
            row_step: [0; 3],
            shift,
            lighting,
            filter,
        };
        let (ax, ay) = (anchor.0 as i32, anchor.1 as i32);
        let slots = map
            .step
            .iter_mut()
            .zip(map.row_step.iter_mut())
            .zip(map.origin.iter_mut());
        for (((step, row_step), origin), [dx, dy, at]) in slots.zip(planes) {
            let fits = |v: f32| v.is_finite() && v.abs() < MAX_STEP;
            if !(fits(dx) && fits(dy) && fits(at)) {
                return None;
            }
            // `as` rounds toward zero; adding half away from zero rounds to nearest (below
            // `MAX_STEP`, within `i32`; the origin is kept modulo `2^32`).
            let round = |v: f32| (v + 0.5f32.copysign(v)) as i32;
            let (sx, sy) = (round(dx), round(dy));
            *step = sx;
            *row_step = sy;
            *origin = round(at)
                .wrapping_sub(sx.wrapping_mul(ax))
                .wrapping_sub(sy.wrapping_mul(ay));
        }
        Some(map)
    }

    /// The texture.
    pub fn texture(&self) -> Texture<'a> {
        self.texture
    }

    /// Row `y`, whose pixels of the polygon are `first .. end`.
    #[inline]
    pub fn row(&self, y: u32, first: u32, end: u32) -> RowTexture<'a> {
        let base = core::array::from_fn(|k| {
            self.origin[k].wrapping_add(self.row_step[k].wrapping_mul(y as i32))
        });
        RowTexture {
            texture: self.texture,
            base,
            step: self.step,
            shift: self.shift,
            first,
            end,
            modulation: match self.lighting {
                Lighting::Colour(Colour {
                    r: 255,
                    g: 255,
                    b: 255,
                }) => Modulation::None,
                Lighting::Colour(k) => Modulation::Colour(k),
                Lighting::Smooth(g) => Modulation::Shade(g.row(y)),
            },
            filter: self.filter,
        }
    }
}

impl<const SUB: u32> Shader for TextureMap<'_, SUB> {
    #[inline]
    fn span<S: SpanSink + ?Sized>(&mut self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        let row = self.row(y, x_start, x_end);
        sink.textured_span(y, x_start, x_end, &row);
    }
}
