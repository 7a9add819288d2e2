//! Smooth files before the writer: which polygons are smooth, and the vertices they need.
//!
//! A file stores one pair of intensities per vertex ([`format::PeelFile::shades`]), so a vertex
//! where polygons meet with different intensities is stored once per pair: copies of one
//! position. A polygon whose colour is the same at all its vertices, on each side, is written
//! as in a faceted file (one colour per side, read from no vertex's shades) and needs no copy
//! of its own: it takes the first copy of each of its vertices. If no polygon is smooth, the
//! tree is written as it is, without shades.
//!
//! Vertices are numbered in order of first use over the polygons in tree order (as the tree
//! numbers them), so the copies of a vertex lie close to it.

use std::borrow::Cow;

use crate::error::CompileError;
use crate::hash::FastMap;
use crate::shade::corners::apply;
use crate::tree::{DisplayTree, TreePolygon};

use super::format::polygon_flags;

/// One polygon's material and intensities, as [`shade_vertices`] takes them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PolygonShades {
    /// The material colour.
    pub kd: [u8; 3],
    /// Per vertex (in the order of the polygon's list), the 8-bit intensities of its source
    /// triangle's `[front, back]`.
    pub vertices: Vec<[u8; 2]>,
}

/// What the writer takes for a smooth file ([`super::WriteInput`]).
#[derive(Debug, Clone)]
pub(crate) struct Shaded<'t> {
    /// The tree with its vertices copied where shades differ (the tree itself when no
    /// polygon is smooth).
    pub tree: Cow<'t, DisplayTree>,
    /// Per polygon, its interior side's colour field: the side's colour, or `kd` if smooth.
    pub colours: Vec<[u8; 3]>,
    /// Per polygon, its exterior side's colour field.
    pub exterior: Vec<[u8; 3]>,
    /// Per polygon, [`polygon_flags::SMOOTH`] and [`polygon_flags::INTERIOR_BACK`] or 0.
    pub flags: Vec<u8>,
    /// Per vertex of `tree`, `[front, back]`: empty when no polygon is smooth.
    pub shades: Vec<[u8; 2]>,
}

/// Which of `[front, back]` is `polygon`'s interior side: 0 when its source triangle's front.
fn interior_side(polygon: &TreePolygon) -> usize {
    usize::from(polygon.interior_is_back())
}

/// The colours of a polygon's `[interior, exterior]` sides when each is one colour over the
/// polygon, else `None` (the polygon is smooth).
fn flat_colours(polygon: &TreePolygon, shades: &PolygonShades) -> Option<[[u8; 3]; 2]> {
    let inside = interior_side(polygon);
    let side = |k: usize| {
        let mut colours = shades.vertices.iter().map(|s| apply(shades.kd, s[k]));
        let first = colours.next()?;
        colours.all(|c| c == first).then_some(first)
    };
    Some([side(inside)?, side(1 - inside)?])
}

/// The polygons of `tree` shaded by `shades` (one per polygon, in order): each flat or smooth,
/// and the vertices that gives. Deterministic.
///
/// # Errors
/// [`CompileError::Invariant`] when the shades do not match the polygons.
pub(crate) fn shade_vertices<'t>(
    tree: &'t DisplayTree,
    shades: &[PolygonShades],
) -> Result<Shaded<'t>, CompileError> {
    let mismatch = shades.len() != tree.polygons.len()
        || tree
            .polygons
            .iter()
            .zip(shades)
            .any(|(p, s)| p.vertices.len() != s.vertices.len());
    if mismatch {
        return Err(CompileError::Invariant(
            "smooth shades do not match the polygons".into(),
        ));
    }
    let mut colours = Vec::with_capacity(shades.len());
    let mut exterior = Vec::with_capacity(shades.len());
    let mut flags = Vec::with_capacity(shades.len());
    for (p, s) in tree.polygons.iter().zip(shades) {
        let (sides, flag) = match flat_colours(p, s) {
            Some(sides) => (sides, 0),
            None if interior_side(p) == 1 => (
                [s.kd; 2],
                polygon_flags::SMOOTH | polygon_flags::INTERIOR_BACK,
            ),
            None => ([s.kd; 2], polygon_flags::SMOOTH),
        };
        colours.push(sides[0]);
        exterior.push(sides[1]);
        flags.push(flag);
    }
    if flags.iter().all(|&f| f == 0) {
        return Ok(Shaded {
            tree: Cow::Borrowed(tree),
            colours,
            exterior,
            flags,
            shades: Vec::new(),
        });
    }
    // A flat polygon takes its vertex's copy of the first smooth use (in tree order), or of
    // its first use when no smooth polygon uses the vertex.
    let mut first: Vec<Option<[u8; 2]>> = vec![None; tree.vertices.len()];
    for smooth in [true, false] {
        for ((p, s), &flag) in tree.polygons.iter().zip(shades).zip(&flags) {
            if (flag != 0) == smooth {
                for (&v, &shade) in p.vertices.iter().zip(&s.vertices) {
                    first[v as usize].get_or_insert(shade);
                }
            }
        }
    }
    let mut copies: FastMap<(u32, [u8; 2]), u32> = FastMap::default();
    let mut vertices = Vec::with_capacity(tree.vertices.len());
    let mut vertex_shades = Vec::with_capacity(tree.vertices.len());
    let mut polygons = tree.polygons.clone();
    for ((p, s), flag) in polygons.iter_mut().zip(shades).zip(&mut flags) {
        // A smooth polygon wound against its neighbours has their intensities the other way
        // round at its corners: stored swapped, with its interior side's index swapped too,
        // it shares their copies.
        let swap = |[f, b]: [u8; 2]| [b, f];
        let swapped = *flag != 0 && {
            let found = |turn: bool| {
                let pairs = p.vertices.iter().zip(&s.vertices);
                pairs
                    .filter(|&(&v, &shade)| {
                        let key = if turn { swap(shade) } else { shade };
                        copies.contains_key(&(v, key))
                    })
                    .count()
            };
            found(true) > found(false)
        };
        if swapped {
            *flag ^= polygon_flags::INTERIOR_BACK;
        }
        let flag = *flag;
        for (v, &shade) in p.vertices.iter_mut().zip(&s.vertices) {
            let key = if flag == 0 {
                first[*v as usize].unwrap_or(shade)
            } else if swapped {
                swap(shade)
            } else {
                shade
            };
            *v = *copies.entry((*v, key)).or_insert_with(|| {
                vertices.push(tree.vertices[*v as usize]);
                vertex_shades.push(key);
                // No more copies than polygon vertices, which the writer counts in `u32`.
                (vertices.len() - 1) as u32
            });
        }
    }
    Ok(Shaded {
        tree: Cow::Owned(DisplayTree {
            centre: tree.centre,
            vertices,
            planes: tree.planes.clone(),
            polygons,
            nodes: tree.nodes.clone(),
            stats: tree.stats,
        }),
        colours,
        exterior,
        flags,
        shades: vertex_shades,
    })
}

#[cfg(test)]
mod tests;
