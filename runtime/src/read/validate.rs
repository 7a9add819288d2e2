//! [`Scene::parse`]: the layout first (so that any prefix of a valid file is `Truncated`), then
//! every record, then the tree. Linear time, no allocation, no recursion.
//!
//! The tree check needs no per-node memory because every node stores its parent: each child
//! link must be answered by the child's parent link and vice versa, parents come before their
//! children, and a split's two children differ. Then every node but the root has exactly one
//! parent, which precedes it, so the nodes form one tree rooted at node 0. Its depth is measured
//! by a walk that goes down child links and back up parent links, keeping only the current
//! node and its depth: no stack, each edge walked twice.

use glam::Vec3;

use super::layout::{
    self, colour_size, f32_at, f64_at, field_at, field_size, header_flags as hf,
    header_offset as h, index_size, node_kind, node_size, polygon_flags, polygon_size, u16_at,
    u64_at, u8_at, vertex_size, BOUNDS_SIZE, FORMAT_VERSION, HEADER_SIZE, ID_SIZE, LENGTH_SIZE,
    MAGIC, NONE, PALETTE_SIZE, PLANE_SIZE, SHADE_SIZE,
};
#[cfg(feature = "textures")]
use super::layout::{
    texture_flags, u32_at, MAX_TEXTURES, MAX_TEXTURE_LOG2, NO_TEXTURE, TEXTURE_SIZE, UV_SIZE,
};
#[cfg(feature = "transparency")]
use super::layout::{OPACITY_SIZE, OPAQUE};
use super::layout::{TEXTURED_VERSION, TRANSPARENT_VERSION};
#[cfg(feature = "textures")]
use super::texture::TextureArrays;
use super::{Header, Scene};
use crate::error::ReadError;

/// `value`, or `Truncated { offset }` when it lies past the end.
fn need<T>(value: Option<T>, offset: usize) -> Result<T, ReadError> {
    value.ok_or(ReadError::Truncated { offset })
}

fn bad(offset: usize) -> ReadError {
    ReadError::BadRecord { offset }
}

pub(super) fn parse(bytes: &[u8]) -> Result<Scene<'_>, ReadError> {
    let scene = parse_layout(bytes)?;
    check_header_values(bytes)?;
    check_vertices(&scene)?;
    check_planes(&scene)?;
    check_indices(&scene)?;
    check_bounds(&scene)?;
    check_polygons(&scene)?;
    check_nodes(&scene)?;
    check_depth(&scene)?;
    #[cfg(feature = "textures")]
    check_textures(&scene)?;
    #[cfg(feature = "transparency")]
    check_opacities(&scene)?;
    Ok(scene)
}

/// The header and the array layout only (constant time): what [`Scene::parse_trusted`] checks.
pub(super) fn parse_layout(bytes: &[u8]) -> Result<Scene<'_>, ReadError> {
    let header = read_header(bytes)?;
    locate_arrays(bytes, header)
}

/// Magic, version and flags are judged on whatever bytes there are, so that a foreign or newer
/// file is reported as such even when it is shorter than this version's header.
fn read_header(bytes: &[u8]) -> Result<Header, ReadError> {
    match bytes.get(..MAGIC.len()) {
        Some(magic) if magic != MAGIC => return Err(ReadError::BadMagic),
        Some(_) => {}
        None if MAGIC.starts_with(bytes) => return Err(ReadError::Truncated { offset: 0 }),
        None => return Err(ReadError::BadMagic),
    }
    let version = u16_at(bytes, h::VERSION);
    if let Some(version) = version {
        if version != FORMAT_VERSION
            && version != TEXTURED_VERSION
            && version != TRANSPARENT_VERSION
        {
            return Err(ReadError::UnsupportedVersion { version });
        }
    }
    if let Some(flags) = u16_at(bytes, h::FLAGS) {
        if flags & !hf::KNOWN != 0 {
            return Err(ReadError::UnknownFlags { flags });
        }
        // Textures are version 6's (and may be version 7's), and version 6 always has them;
        // transparency is version 7's, which always has it.
        let textures = flags & hf::TEXTURES != 0;
        let transparent = flags & hf::TRANSPARENT != 0;
        if (version == Some(TRANSPARENT_VERSION)) != transparent
            || (version == Some(TEXTURED_VERSION)) != (textures && !transparent)
        {
            return Err(ReadError::InconsistentFlags { flags });
        }
        let both_widths = hf::NARROW | hf::MEDIUM;
        let both_indices = hf::INDEX16 | hf::INDEX24;
        if flags & hf::PALETTE16 != 0 && flags & hf::PALETTE == 0
            || flags & both_widths == both_widths
            || flags & both_indices == both_indices
        {
            return Err(ReadError::InconsistentFlags { flags });
        }
        // Without the features, only 16-bit fields, indices and vertex steps.
        let large = !cfg!(feature = "large-scenes")
            && (flags & hf::NARROW == 0 || flags & hf::INDEX16 == 0);
        let wide = !cfg!(feature = "wide-vertices") && flags & hf::WIDE_VERTICES != 0;
        let textures = !cfg!(feature = "textures") && textures;
        let transparent = !cfg!(feature = "transparency") && transparent;
        if large || wide || textures || transparent {
            return Err(ReadError::UnsupportedFlags { flags });
        }
    }
    match bytes.get(..HEADER_SIZE).and_then(|b| b.try_into().ok()) {
        Some(header) => Ok(Header::from_bytes(header)),
        None => Err(ReadError::Truncated { offset: 0 }),
    }
}

/// One array: its `u64` length at `*at` must equal `count` and its records must fit.
/// Returns the offset of its first record and moves `*at` past its end.
fn array(bytes: &[u8], at: &mut usize, count: u32, size: usize) -> Result<usize, ReadError> {
    let length_at = *at;
    let length = need(u64_at(bytes, length_at), length_at)?;
    if length != u64::from(count) {
        return Err(ReadError::CountMismatch { offset: length_at });
    }
    let start = length_at + LENGTH_SIZE;
    let end = usize::try_from(count)
        .ok()
        .and_then(|n| n.checked_mul(size))
        .and_then(|n| n.checked_add(start))
        .filter(|&end| end <= bytes.len())
        .ok_or(ReadError::Truncated { offset: start })?;
    *at = end;
    Ok(start)
}

fn locate_arrays(bytes: &[u8], header: Header) -> Result<Scene<'_>, ReadError> {
    let flags = header.flags;
    let id_count = if flags & hf::IDS != 0 {
        header.polygon_count
    } else {
        0
    };
    // Optional parts: a count without its flag (or a palette flag without colours) is
    // inconsistent, as is a palette too large for its index width.
    let palette_max = match (flags & hf::PALETTE != 0, flags & hf::PALETTE16 != 0) {
        (false, _) => 0,
        (true, false) => 1 << 8,
        (true, true) => 1 << 16,
    };
    let palette_ok = if palette_max == 0 {
        header.palette_count == 0
    } else {
        (1..=palette_max).contains(&header.palette_count)
    };
    if !palette_ok {
        return Err(bad(h::PALETTE_COUNT));
    }
    if flags & hf::BOUNDS == 0 && header.bounds_count != 0 {
        return Err(bad(h::BOUNDS_COUNT));
    }
    if flags & hf::INDEX16 != 0 && header.vertex_count > 1 << 16
        || flags & hf::INDEX24 != 0 && header.vertex_count > 1 << 24
    {
        return Err(bad(h::VERTEX_COUNT));
    }
    if flags & (hf::NARROW | hf::MEDIUM) != 0 {
        // Narrower fields: every count they index fits, and no node or box is numbered NONE.
        let narrow = layout::none_of_width(field_size(flags));
        for (count, at) in [
            (header.plane_count, h::PLANE_COUNT),
            (header.index_count, h::INDEX_COUNT),
            (header.polygon_count, h::POLYGON_COUNT),
            (header.node_count, h::NODE_COUNT),
            (header.bounds_count, h::BOUNDS_COUNT),
        ] {
            if count > narrow {
                return Err(bad(at));
            }
        }
    }
    let (vertex_size, index_size, polygon_size, node_size) = (
        vertex_size(flags),
        index_size(flags),
        polygon_size(flags),
        node_size(flags),
    );
    let field_size = field_size(flags);
    let mut at = HEADER_SIZE;
    let mut scene = Scene {
        bytes,
        header,
        vertices: array(bytes, &mut at, header.vertex_count, vertex_size)?,
        planes: array(bytes, &mut at, header.plane_count, PLANE_SIZE)?,
        indices: array(bytes, &mut at, header.index_count, index_size)?,
        polygons: array(bytes, &mut at, header.polygon_count, polygon_size)?,
        ids: array(bytes, &mut at, id_count, ID_SIZE)?,
        palette: array(bytes, &mut at, header.palette_count, PALETTE_SIZE)?,
        bounds: array(bytes, &mut at, header.bounds_count, BOUNDS_SIZE)?,
        nodes: array(bytes, &mut at, header.node_count, node_size)?,
        // Present only with its flag (no length either without it).
        shades: if flags & hf::SHADES != 0 {
            array(bytes, &mut at, header.vertex_count, SHADE_SIZE)?
        } else {
            at
        },
        #[cfg(feature = "textures")]
        textures: if flags & hf::TEXTURES != 0 {
            locate_textures(bytes, &mut at, header)?
        } else {
            TextureArrays::default()
        },
        #[cfg(feature = "transparency")]
        opacities: if flags & hf::TRANSPARENT != 0 {
            array(bytes, &mut at, header.polygon_count, OPACITY_SIZE)?
        } else {
            0
        },
        step: Vec3::new(
            layout::step(header.bounds_min.x, header.bounds_max.x),
            layout::step(header.bounds_min.y, header.bounds_max.y),
            layout::step(header.bounds_min.z, header.bounds_max.z),
        ),
        per_step: Vec3::new(
            layout::per_step(header.bounds_min.x, header.bounds_max.x),
            layout::per_step(header.bounds_min.y, header.bounds_max.y),
            layout::per_step(header.bounds_min.z, header.bounds_max.z),
        ),
        #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
        grid: (|| {
            let (lo, hi) = (header.bounds_min, header.bounds_max);
            Some([
                layout::Grid::of(lo.x, hi.x)?,
                layout::Grid::of(lo.y, hi.y)?,
                layout::Grid::of(lo.z, hi.z)?,
            ])
        })(),
        vertex_size,
        index_size,
        polygon_size,
        node_size,
        field_size,
        exterior: if flags & hf::TWO_COLOURS != 0 {
            field_size + 2 + colour_size(flags)
        } else {
            field_size + 2
        },
        steps16: &[],
        indices16: &[],
    };
    if at != bytes.len() {
        return Err(ReadError::TrailingBytes { offset: at });
    }
    // Both inside `bytes`: `array` checked them.
    let section = |start: usize, count: u32, size: usize| {
        bytes
            .get(start..start + count as usize * size)
            .unwrap_or(&[])
    };
    if vertex_size == 6 {
        scene.steps16 = section(scene.vertices, header.vertex_count, 6);
    }
    if index_size == 2 {
        scene.indices16 = section(scene.indices, header.index_count, 2);
    }
    Ok(scene)
}

#[cfg(feature = "textures")]
/// The texture arrays after the nodes and shades (see `formats/peel.md`, "Textures"): their
/// lengths and extents, not their records.
fn locate_textures(
    bytes: &[u8],
    at: &mut usize,
    header: Header,
) -> Result<TextureArrays, ReadError> {
    let uvs = array(bytes, at, header.vertex_count, UV_SIZE)?;
    let count_at = *at;
    let count = need(u64_at(bytes, count_at), count_at)?;
    if count == 0 || count > u64::from(MAX_TEXTURES) {
        return Err(bad(count_at));
    }
    let records = array(bytes, at, count as u32, TEXTURE_SIZE)?;
    let texels_at = *at;
    let texel_bytes = need(u64_at(bytes, texels_at), texels_at)?;
    let texel_bytes = u32::try_from(texel_bytes).map_err(|_| ReadError::Truncated {
        offset: texels_at + LENGTH_SIZE,
    })?;
    let texels = array(bytes, at, texel_bytes, 1)?;
    let polygons = array(bytes, at, header.polygon_count, 1)?;
    Ok(TextureArrays {
        uvs,
        records,
        count: count as u32,
        texels,
        texel_bytes: texel_bytes as usize,
        polygons,
    })
}

/// Every texture record well formed, the records' bytes following each other to the end of
/// `texels`, every palette index in its palette, every polygon's texture byte a texture or
/// [`NO_TEXTURE`].
#[cfg(feature = "textures")]
fn check_textures(scene: &Scene<'_>) -> Result<(), ReadError> {
    if !scene.has_textures() {
        return Ok(());
    }
    let t = scene.textures;
    let b = scene.bytes;
    let mut end = 0usize;
    for (_, at) in records(t.records, TEXTURE_SIZE, t.count) {
        let byte = |k: usize| u8_at(b, at + k).unwrap_or(u8::MAX);
        let (lw, lh, flags, colours) = (byte(0), byte(1), byte(2), byte(3));
        let palette = flags & texture_flags::PALETTE != 0;
        let ok = lw <= MAX_TEXTURE_LOG2
            && lh <= MAX_TEXTURE_LOG2
            && flags & !texture_flags::KNOWN == 0
            && (palette || colours == 0)
            && u32_at(b, at + 4).map(|o| o as usize) == Some(end);
        if !ok {
            return Err(bad(at));
        }
        let colours = u32::from(colours) + 1;
        let size = layout::texture_bytes(lw, lh, flags, colours);
        if end + size > t.texel_bytes {
            return Err(bad(t.texels - LENGTH_SIZE));
        }
        if palette {
            let first = t.texels + end + colours as usize * layout::TEXEL_SIZE;
            let indices = b.get(first..first + (size - colours as usize * layout::TEXEL_SIZE));
            if let Some(k) = indices
                .unwrap_or(&[])
                .iter()
                .position(|&i| u32::from(i) >= colours)
            {
                return Err(bad(first + k));
            }
        }
        end += size;
    }
    if end != t.texel_bytes {
        return Err(bad(t.texels - LENGTH_SIZE));
    }
    for (i, at) in records(t.polygons, 1, scene.header.polygon_count) {
        let _ = i;
        let k = u8_at(b, at).unwrap_or(0);
        if k != NO_TEXTURE && u32::from(k) >= t.count {
            return Err(bad(at));
        }
    }
    Ok(())
}

/// Every polygon's opacity agrees with its flag (below 255 exactly when
/// [`polygon_flags::TRANSPARENT`]), and a transparent polygon is neither smooth, nor a
/// solid's, nor textured.
#[cfg(feature = "transparency")]
fn check_opacities(scene: &Scene<'_>) -> Result<(), ReadError> {
    if !scene.has_transparency() {
        return Ok(());
    }
    let b = scene.bytes;
    let not_with =
        polygon_flags::SMOOTH | polygon_flags::INSIDE_INTERIOR | polygon_flags::INSIDE_EXTERIOR;
    let polygons = records(
        scene.polygons,
        scene.polygon_size,
        scene.header.polygon_count,
    );
    let opacities = records(scene.opacities, OPACITY_SIZE, scene.header.polygon_count);
    for ((i, polygon_at), (_, at)) in polygons.zip(opacities) {
        let flags = u8_at(b, polygon_at + scene.field_size() + 1).unwrap_or(0);
        let opacity = u8_at(b, at).unwrap_or(OPAQUE);
        let flagged = flags & polygon_flags::TRANSPARENT != 0;
        let textured = scene.polygon_texture(i).is_some();
        if flagged != (opacity < OPAQUE) || flagged && (flags & not_with != 0 || textured) {
            return Err(bad(at));
        }
    }
    Ok(())
}

/// Finite centre, finite bounds with `min <= max` and a finite extent `max - min` (which
/// decoding a vertex or box step multiplies).
fn check_header_values(bytes: &[u8]) -> Result<(), ReadError> {
    for k in 0..3 {
        let at = h::CENTRE + 8 * k;
        if !f64_at(bytes, at).is_some_and(f64::is_finite) {
            return Err(bad(at));
        }
        let (min_at, max_at) = (h::BOUNDS_MIN + 4 * k, h::BOUNDS_MAX + 4 * k);
        let min = f32_at(bytes, min_at)
            .filter(|v| v.is_finite())
            .ok_or(bad(min_at))?;
        let max = f32_at(bytes, max_at)
            .filter(|v| v.is_finite())
            .ok_or(bad(max_at))?;
        if min > max || !(max - min).is_finite() {
            return Err(bad(max_at));
        }
    }
    Ok(())
}

/// Record offsets `start, start + size, ...` of an array of `count` records.
fn records(start: usize, size: usize, count: u32) -> impl Iterator<Item = (u32, usize)> {
    (0..count).scan(start, move |at, i| {
        let here = *at;
        *at += size;
        Some((i, here))
    })
}

/// Every vertex finite and inside the header's bounds. Steps (without
/// [`hf::WIDE_VERTICES`]) always are: they decode between the bounds, whose extent is finite.
fn check_vertices(scene: &Scene<'_>) -> Result<(), ReadError> {
    if scene.header.flags & hf::WIDE_VERTICES == 0 {
        return Ok(());
    }
    let (min, max) = (scene.header.bounds_min, scene.header.bounds_max);
    for (_, at) in records(
        scene.vertices,
        scene.vertex_size(),
        scene.header.vertex_count,
    ) {
        for k in 0..3 {
            let inside = f32_at(scene.bytes, at + 4 * k)
                .is_some_and(|v| v.is_finite() && min[k] <= v && v <= max[k]);
            if !inside {
                return Err(bad(at));
            }
        }
    }
    Ok(())
}

/// Every plane coefficient finite.
fn check_planes(scene: &Scene<'_>) -> Result<(), ReadError> {
    for (_, at) in records(scene.planes, PLANE_SIZE, scene.header.plane_count) {
        if !(0..4).all(|k| f32_at(scene.bytes, at + 4 * k).is_some_and(f32::is_finite)) {
            return Err(bad(at));
        }
    }
    Ok(())
}

/// Every box, decoded, finite with `min <= max` (the header's bounds can be so wide that a
/// step in between overflows).
fn check_bounds(scene: &Scene<'_>) -> Result<(), ReadError> {
    for (_, at) in records(scene.bounds, BOUNDS_SIZE, scene.header.bounds_count) {
        let (lo, hi) = scene.box_at(at);
        let ok = (0..3).all(|k| lo[k].is_finite() && hi[k].is_finite() && lo[k] <= hi[k]);
        if !ok {
            return Err(bad(at));
        }
    }
    Ok(())
}

/// Every index names a vertex.
fn check_indices(scene: &Scene<'_>) -> Result<(), ReadError> {
    for (i, at) in records(scene.indices, scene.index_size(), scene.header.index_count) {
        let vertex = scene.index(i).unwrap_or(u32::MAX);
        if vertex >= scene.header.vertex_count {
            return Err(bad(at));
        }
    }
    Ok(())
}

/// Every polygon: palette indices in range (both colours with `TWO_COLOURS`), known flags
/// (`SMOOTH` only with `SHADES`, `INTERIOR_BACK` only with `SMOOTH`, one of `INSIDE_INTERIOR`
/// and `INSIDE_EXTERIOR` at most, only with `SOLID`),
/// `3 <= vertex_count <= max_polygon_vertices`, and
/// its vertex list right after the previous polygon's, the last one ending the index array.
fn check_polygons(scene: &Scene<'_>) -> Result<(), ReadError> {
    let header = &scene.header;
    let mut next_index: u64 = 0;
    let palette16 = header.flags & hf::PALETTE16 != 0;
    let colour_bytes = colour_size(header.flags);
    let w = scene.field_size();
    for (_, at) in records(scene.polygons, scene.polygon_size, header.polygon_count) {
        let b = scene.bytes;
        let colour_ok = |colour_at: usize| {
            if header.flags & hf::PALETTE == 0 {
                true
            } else if palette16 {
                u16_at(b, colour_at).is_some_and(|k| u32::from(k) < header.palette_count)
            } else {
                u8_at(b, colour_at).is_some_and(|k| u32::from(k) < header.palette_count)
            }
        };
        let colours_ok = colour_ok(at + w + 2)
            && (header.flags & hf::TWO_COLOURS == 0 || colour_ok(at + w + 2 + colour_bytes));
        let first_index = need(field_at(b, at, w, false), at)?;
        let vertex_count = need(u8_at(b, at + w), at)?;
        let flags = need(u8_at(b, at + w + 1), at)?;
        // Smooth only with shades, and the side of the shades only for a smooth polygon.
        let smooth = flags & polygon_flags::SMOOTH != 0;
        let inside = flags & (polygon_flags::INSIDE_INTERIOR | polygon_flags::INSIDE_EXTERIOR);
        let ok = colours_ok
            && flags & !polygon_flags::KNOWN == 0
            && (!smooth || header.flags & hf::SHADES != 0)
            && (smooth || flags & polygon_flags::INTERIOR_BACK == 0)
            && (inside == 0 || header.flags & hf::SOLID != 0)
            && (flags & polygon_flags::TRANSPARENT == 0 || header.flags & hf::TRANSPARENT != 0)
            && inside.count_ones() <= 1
            && vertex_count >= 3
            && u32::from(vertex_count) <= header.max_polygon_vertices
            && u64::from(first_index) == next_index;
        if !ok {
            return Err(bad(at));
        }
        next_index += u64::from(vertex_count);
    }
    if next_index != u64::from(header.index_count) {
        // Some indices belong to no polygon, or the last polygon runs past the array.
        return Err(bad(scene.indices - LENGTH_SIZE));
    }
    Ok(())
}

/// Every node: a known kind, fields in range, convex sets owning the polygons in node order
/// (each polygon exactly once), and child and parent links that answer each other.
fn check_nodes(scene: &Scene<'_>) -> Result<(), ReadError> {
    let header = &scene.header;
    let n = header.node_count;
    let mut next_polygon: u64 = 0;
    let with_bounds = header.flags & hf::BOUNDS != 0;
    for (i, at) in records(scene.nodes, scene.node_size, n) {
        let raw = need(scene.raw_node(i), at)?;
        if with_bounds {
            let w = scene.field_size();
            let k = need(field_at(scene.bytes, at + 1 + 3 * w, w, true), at)?;
            if k != NONE && k >= header.bounds_count {
                return Err(bad(at));
            }
        }
        match raw.kind {
            node_kind::CONVEX => {
                if raw.c == 0 || u64::from(raw.a) != next_polygon {
                    return Err(bad(at));
                }
                next_polygon += u64::from(raw.c);
            }
            node_kind::SPLIT if raw.a < header.plane_count => {}
            _ => return Err(bad(at)),
        }
        let [first, second] = raw.children();
        if first.is_some() && first == second {
            return Err(bad(at));
        }
        for child in [first, second].into_iter().flatten() {
            let answered =
                child > i && child < n && scene.raw_node(child).is_some_and(|c| c.parent == i);
            if !answered {
                return Err(bad(at));
            }
        }
        let parent_ok = if i == 0 {
            raw.parent == NONE
        } else {
            raw.parent < i
                && scene
                    .raw_node(raw.parent)
                    .is_some_and(|p| p.children().contains(&Some(i)))
        };
        if !parent_ok {
            return Err(bad(at));
        }
    }
    if next_polygon != u64::from(header.polygon_count) {
        // Some polygons belong to no convex node, or the last set runs past the array.
        return Err(bad(scene.polygons - LENGTH_SIZE));
    }
    Ok(())
}

/// The longest root-to-leaf path has at most `max_depth` nodes. Relies on [`check_nodes`]:
/// the links form one tree, so the walk ends after `2 * node_count` steps.
fn check_depth(scene: &Scene<'_>) -> Result<(), ReadError> {
    let max_depth = scene.header.max_depth;
    let too_deep = ReadError::TooDeep { max_depth };
    if scene.header.node_count == 0 {
        return Ok(());
    }
    let node = |i: u32| scene.raw_node(i).ok_or(bad(scene.nodes));
    let (mut current, mut depth) = (0u32, 1u32);
    if depth > max_depth {
        return Err(too_deep);
    }
    'walk: loop {
        let [first, second] = node(current)?.children();
        if let Some(child) = first.or(second) {
            current = child;
            depth += 1;
            if depth > max_depth {
                return Err(too_deep);
            }
            continue;
        }
        // A leaf: climb until an ancestor has a second child not yet visited.
        loop {
            let Some(parent) = super::node::link(node(current)?.parent) else {
                break 'walk;
            };
            if let [Some(first), Some(second)] = node(parent)?.children() {
                if first == current {
                    current = second;
                    continue 'walk;
                }
            }
            current = parent;
            depth -= 1;
        }
    }
    Ok(())
}
