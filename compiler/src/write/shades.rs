//! Smooth and textured files before the writer: which polygons are smooth, and the vertices
//! they need.
//!
//! A file stores one pair of intensities per vertex ([`format::PeelFile::shades`]) and one pair
//! of texture coordinates ([`format::PeelFile::uvs`]), so a vertex where polygons meet with
//! different intensities or coordinates is stored once per distinct (intensities,
//! coordinates): copies of one position. A polygon whose colour is the same at all its
//! vertices, on each side, is written as in a faceted file (one colour per side, read from no
//! vertex's shades) and needs no shades of its own; an untextured polygon needs no
//! coordinates: each takes a copy its vertices have already ([`copy_vertices`]). If no polygon
//! is smooth or textured, the tree is written as it is, without shades or coordinates.
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
    /// The tree with its vertices copied where shades or texture coordinates differ (the tree
    /// itself when no polygon is smooth or textured).
    pub tree: Cow<'t, DisplayTree>,
    /// Per polygon, its interior side's colour field: the side's colour, or `kd` if smooth.
    pub colours: Vec<[u8; 3]>,
    /// Per polygon, its exterior side's colour field.
    pub exterior: Vec<[u8; 3]>,
    /// Per polygon, [`polygon_flags::SMOOTH`] and [`polygon_flags::INTERIOR_BACK`] or 0.
    pub flags: Vec<u8>,
    /// Per vertex of `tree`, `[front, back]`: empty when no polygon is smooth.
    pub shades: Vec<[u8; 2]>,
    /// Per vertex of `tree`, its texture coordinates: empty when no polygon is textured.
    pub uvs: Vec<[i32; 2]>,
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

/// Per polygon, its vertices' texture coordinates in the order of its list (the file's fixed
/// point, [`crate::texture::fixed`]), or `None` for an untextured polygon.
pub(crate) type PolygonUvs = Option<Vec<[i32; 2]>>;

/// The polygons of `tree` shaded by `shades` (one per polygon, in order): each flat or smooth,
/// and the vertices that gives with the texture coordinates `uvs` (none, or one entry per
/// polygon; see [`copy_vertices`]). Deterministic.
///
/// # Errors
/// [`CompileError::Invariant`] when the shades or coordinates do not match the polygons.
pub(crate) fn shade_vertices<'t>(
    tree: &'t DisplayTree,
    shades: &[PolygonShades],
    uvs: &[PolygonUvs],
) -> Result<Shaded<'t>, CompileError> {
    check_uvs(tree, uvs)?;
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
    let copied = copy_vertices(tree, Some(shades), &mut flags, uvs);
    Ok(Shaded {
        tree: copied.tree,
        colours,
        exterior,
        flags,
        shades: copied.shades,
        uvs: copied.uvs,
    })
}

/// The vertices of a faceted file with textures ([`copy_vertices`] without shades): `tree`
/// with its vertices copied where polygons meet with different coordinates, and each copy's
/// coordinates (empty, and the tree itself, when no polygon is textured).
///
/// # Errors
/// [`CompileError::Invariant`] when `uvs` do not match the polygons.
pub(crate) fn uv_vertices<'t>(
    tree: &'t DisplayTree,
    uvs: &[PolygonUvs],
) -> Result<Copied<'t>, CompileError> {
    check_uvs(tree, uvs)?;
    let mut flat = vec![0; tree.polygons.len()];
    Ok(copy_vertices(tree, None, &mut flat, uvs))
}

/// `uvs` are none, or one per polygon with one per vertex of each textured one.
fn check_uvs(tree: &DisplayTree, uvs: &[PolygonUvs]) -> Result<(), CompileError> {
    let matches = uvs.is_empty()
        || (uvs.len() == tree.polygons.len()
            && (tree.polygons.iter().zip(uvs))
                .all(|(p, uv)| uv.as_ref().is_none_or(|uv| uv.len() == p.vertices.len())));
    if matches {
        Ok(())
    } else {
        Err(CompileError::Invariant(
            "texture coordinates do not match the polygons".into(),
        ))
    }
}

/// A tree with its vertices copied ([`copy_vertices`]).
#[derive(Debug, Clone)]
pub(crate) struct Copied<'t> {
    /// The tree, its polygons naming the copies (the tree itself when nothing needs a copy).
    pub tree: Cow<'t, DisplayTree>,
    /// Per vertex, `[front, back]`: empty when no polygon is smooth.
    pub shades: Vec<[u8; 2]>,
    /// Per vertex, its texture coordinates: empty when no polygon is textured.
    pub uvs: Vec<[i32; 2]>,
}

/// What each vertex of each polygon of `tree` needs of its copy: a smooth polygon (`flags`
/// not 0) its shades (`shades`, which a faceted file has none of), a textured one its
/// coordinates (`uvs`); a vertex is copied once per distinct (shades, coordinates) pair.
/// What a polygon does not need it takes from a copy its vertex has already: a flat polygon
/// the shades of the vertex's first smooth use (in tree order) with its coordinates, else
/// the first; an untextured polygon the coordinates of the vertex's first textured use with
/// its shades, else the first, else `(0, 0)`. A smooth polygon wound against its neighbours
/// is stored with its shades swapped (and [`polygon_flags::INTERIOR_BACK`] toggled in
/// `flags`) when that shares more copies. Without smooth or textured polygons the tree is
/// returned as it is.
fn copy_vertices<'t>(
    tree: &'t DisplayTree,
    shades: Option<&[PolygonShades]>,
    flags: &mut [u8],
    uvs: &[PolygonUvs],
) -> Copied<'t> {
    let smooth_any = flags.iter().any(|&f| f != 0);
    let textured_any = uvs.iter().any(Option::is_some);
    if !smooth_any && !textured_any {
        return Copied {
            tree: Cow::Borrowed(tree),
            shades: Vec::new(),
            uvs: Vec::new(),
        };
    }
    let shade = |i: usize, k: usize| shades.map_or([0; 2], |s| s[i].vertices[k]);
    let uv = |i: usize, k: usize| uvs.get(i).and_then(Option::as_ref).map(|uv| uv[k]);
    // A flat polygon takes its vertex's copy of the first smooth use (in tree order), or of
    // its first use when no smooth polygon uses the vertex.
    let mut first: Vec<Option<[u8; 2]>> = vec![None; tree.vertices.len()];
    for smooth in [true, false] {
        for (i, p) in tree.polygons.iter().enumerate() {
            if (flags[i] != 0) == smooth {
                for (k, &v) in p.vertices.iter().enumerate() {
                    first[v as usize].get_or_insert(shade(i, k));
                }
            }
        }
    }
    // An untextured polygon takes the coordinates of the first textured use with the shades
    // it takes, else of the first textured use; a flat textured one the shades of the first
    // smooth use with its coordinates, else those of `first`.
    let mut first_uv: Vec<Option<[i32; 2]>> =
        vec![None; tree.vertices.len() * usize::from(textured_any)];
    let mut uv_by_shade: FastMap<(u32, [u8; 2]), [i32; 2]> = FastMap::default();
    let mut shade_by_uv: FastMap<(u32, [i32; 2]), [u8; 2]> = FastMap::default();
    for (i, p) in (tree.polygons.iter().enumerate()).filter(|_| textured_any) {
        for (k, &v) in p.vertices.iter().enumerate() {
            if let Some(uv) = uv(i, k) {
                first_uv[v as usize].get_or_insert(uv);
                if flags[i] != 0 {
                    uv_by_shade.entry((v, shade(i, k))).or_insert(uv);
                    shade_by_uv.entry((v, uv)).or_insert(shade(i, k));
                }
            }
        }
    }
    // The copy a use takes: its shades if it needs them (`Some`) and its coordinates if it
    // has them, the others as above.
    let key = |i: usize, k: usize, v: u32, needed: Option<[u8; 2]>| {
        let uv = uv(i, k);
        let shades = needed.unwrap_or_else(|| {
            (uv.and_then(|uv| shade_by_uv.get(&(v, uv)).copied()))
                .or(first[v as usize])
                .unwrap_or([0; 2])
        });
        let uv = match uv {
            Some(uv) => uv,
            None if textured_any => (uv_by_shade.get(&(v, shades)).copied())
                .or_else(|| first_uv[v as usize])
                .unwrap_or([0; 2]),
            None => [0; 2],
        };
        (v, shades, uv)
    };
    let mut copies: FastMap<(u32, [u8; 2], [i32; 2]), u32> = FastMap::default();
    let mut vertices = Vec::with_capacity(tree.vertices.len());
    let mut vertex_shades = Vec::with_capacity(tree.vertices.len());
    let mut vertex_uvs = Vec::with_capacity(tree.vertices.len());
    let mut polygons = tree.polygons.clone();
    for (i, (p, flag)) in polygons.iter_mut().zip(flags.iter_mut()).enumerate() {
        // A smooth polygon wound against its neighbours has their intensities the other way
        // round at its corners: stored swapped, with its interior side's index swapped too,
        // it shares their copies.
        let swap = |[f, b]: [u8; 2]| [b, f];
        let swapped = *flag != 0 && {
            let found = |turn: bool| {
                (p.vertices.iter().enumerate())
                    .filter(|&(k, &v)| {
                        let shade = shade(i, k);
                        let needed = if turn { swap(shade) } else { shade };
                        copies.contains_key(&key(i, k, v, Some(needed)))
                    })
                    .count()
            };
            found(true) > found(false)
        };
        if swapped {
            *flag ^= polygon_flags::INTERIOR_BACK;
        }
        let smooth = *flag != 0;
        for (k, v) in p.vertices.iter_mut().enumerate() {
            let needed = smooth.then(|| {
                let shade = shade(i, k);
                if swapped {
                    swap(shade)
                } else {
                    shade
                }
            });
            let at = key(i, k, *v, needed);
            *v = *copies.entry(at).or_insert_with(|| {
                vertices.push(tree.vertices[*v as usize]);
                vertex_shades.push(at.1);
                vertex_uvs.push(at.2);
                // No more copies than polygon vertices, which the writer counts in `u32`.
                (vertices.len() - 1) as u32
            });
        }
    }
    Copied {
        tree: Cow::Owned(DisplayTree {
            centre: tree.centre,
            vertices,
            planes: tree.planes.clone(),
            polygons,
            nodes: tree.nodes.clone(),
            stats: tree.stats,
        }),
        shades: if smooth_any {
            vertex_shades
        } else {
            Vec::new()
        },
        uvs: if textured_any { vertex_uvs } else { Vec::new() },
    }
}

#[cfg(test)]
mod tests;
