//! What a polygon is painted with: [`Paint`], its baked colour or its source triangle id as a
//! colour ([`id_colour`]). A file of its own because both the renderer (the switch) and the
//! painter (the colour of each polygon) read it, and neither should import the other for it.

use crate::display::Colour;

/// What a polygon is painted with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Paint {
    /// Its baked colour.
    #[default]
    Colours,
    /// Its source triangle id plus one, as 24 bits (red the high byte); needs a file with ids.
    Ids,
}

/// The colour of an id image pixel for triangle `id`: `id + 1` in 24 bits, red high
/// (ids past `2^24 - 2` wrap: the format's ids are far below that).
pub fn id_colour(id: u32) -> Colour {
    let v = id.wrapping_add(1);
    Colour::new((v >> 16) as u8, (v >> 8) as u8, v as u8)
}
