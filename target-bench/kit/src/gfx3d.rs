//! embedded-3dgfx's scene: the z-buffer baseline's mesh ([`crate::mesh`]) laid out as that
//! library's `Geometry` takes it, so the firmware hands it slices of code memory (its README's
//! advice for MCUs: no RAM for the mesh). Read in place like a `.peel` file.
//!
//! The library cuts a vertex's depth to whole world units before its depth test, so the
//! vertices are scaled by a power of two (exact in `f32`) that puts the scene's radius in
//! `RADIUS..2 * RADIUS`: in an OBJ's own units its depth buffer would have a handful of
//! levels. Its lit modes draw nothing without per-face normals, hence the normals; exactly
//! degenerate triangles, which cover nothing, are left out. The header keeps the `.peel`
//! scene's centre and bounds (unscaled), so the firmware frames the scene with the very same
//! [`peel_runtime::camera::Orbit`] pose as the other methods.
//!
//! | offset | field |
//! |---|---|
//! | 0 | magic `PTBG` |
//! | 4 | [`VERSION`] (u32) |
//! | 8, 12 | vertex count, face count (u32) |
//! | 16 | centre (3 x f64) |
//! | 40, 52 | bounds min, max relative to the centre, unscaled (3 x f32 each) |
//! | 64 | scale: library units per scene unit (f32, a power of two) |
//! | 68 | the mesh's one RGB565 colour (u16), then its flags (u16): [`VERTEX_NORMALS`], [`TEXTURED`] |
//! | 72 | vertices relative to the centre, scaled (3 x f32 each) |
//! | then | faces: three vertex indices (3 x u32 each: the target's `usize`) |
//! | then | unit face normals (3 x f32 each), one per face |
//! | then | with [`VERTEX_NORMALS`]: unit vertex normals (3 x f32 each), one per vertex |
//! | then | with [`TEXTURED`]: texture coordinates (2 x f32 each), one per vertex |
//! | then | with [`TEXTURED`]: the group count (u32), then [`GROUP`] bytes a group |
//! | then | with [`TEXTURED`]: texture count T and texel bytes D (u32 each), T texture records of the `.peel` format (8 bytes each), D texel bytes, zeros to a multiple of 4 |
//!
//! A smooth scene ([`encode_smooth`]) has vertex normals, for the library's Gouraud mode
//! (`GouraudLightDir`, one normal per vertex): a vertex is then a point with one of its
//! corners' normals, a point with several (a crease) being several vertices.
//!
//! A textured scene ([`encode_textured`]) is one mesh of the library per texture and colour (a
//! `Geometry` has one texture, a `K3dMesh` one colour): a **group**, whose vertices, faces and
//! normals are consecutive in their sections, its faces' indices counting from its first
//! vertex. A vertex is a point with one texture coordinate in one group. A group record is six
//! u32: first vertex, vertex count, first face, face count, texture (or [`NO_TEXTURE`]) and
//! the material's RGB565 colour. The textures are the `.peel` file's own records and bytes
//! (RGB565 texels, or a palette and `u8` indices), so they take the same flash.
//!
//! Every section starts at a multiple of 4 bytes, so a 4-aligned file is a set of aligned
//! `[f32; 3]`, `[f32; 2]` and `[u32; 3]` arrays (the texels 2-aligned).

use glam::Vec3;
use peel_runtime::camera::LocalView;
use peel_runtime::read::Header;

#[cfg(any(feature = "textures", test))]
use peel_runtime::read::layout::{texture_bytes, texture_flags, MAX_TEXTURE_LOG2, TEXTURE_SIZE};
#[cfg(any(feature = "textures", feature = "std", test))]
use peel_runtime::read::Texture;

use crate::bytes::{f32_at, f64_at, u16_at, u32_at};

/// Format version.
pub const VERSION: u32 = 2;
/// A flag of the header's second `u16`: vertex normals follow the face normals.
pub const VERTEX_NORMALS: u16 = 1;
/// A flag of the header's second `u16`: texture coordinates, groups and textures follow.
pub const TEXTURED: u16 = 2;
/// Bytes of a vertex's texture coordinates.
pub const UV: usize = 8;
/// Bytes of a group record.
pub const GROUP: usize = 24;
/// A group's texture when it has none.
pub const NO_TEXTURE: u32 = u32::MAX;
/// The file's first bytes.
pub const MAGIC: [u8; 4] = *b"PTBG";
/// Header size.
pub const HEADER: usize = 72;
/// Bytes per vertex, per face and per normal.
pub const ELEMENT: usize = 12;
/// The scaled scene's radius (half its bounds' diagonal) is at least this and under twice
/// it. The library's depth at a point `z` away is `far + 2 near - 2 far near / z`, which
/// [`Scene::camera`] keeps between the scene's nearest and farthest `z`: from 1.1 to 3.1
/// radii for the benchmark's orbit (2.1 radii away), 9,000 to 51,000 whole units, inside its
/// 16-bit depth buffer.
pub const RADIUS: f32 = 8192.0;
/// The unit direction towards the light for the library's per-face Lambert shading
/// (`SolidLightDir`): the compiler's default light, `(0.4, 0.8, 0.45)` normalised, so that
/// faces are lit from the same side as Peel's baked colours.
pub const LIGHT: [f32; 3] = [0.399_500_9, 0.799_001_8, 0.449_438_5];

/// Why scene bytes were refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gfx3dError {
    /// Not a scene of this version.
    Magic,
    /// Fewer bytes than the counts need.
    Truncated,
    /// No vertices (the library refuses such a mesh by panicking).
    Empty,
    /// A scale that is not a positive finite number.
    Scale,
    /// Face `0` names a vertex past the vertex count (of its group).
    Index(u32),
    /// Flags this version does not know.
    Flags(u16),
    /// Group `0` is not where the previous one ends, or names a missing texture.
    #[cfg(any(feature = "textures", test))]
    Group(u32),
    /// Texture record `0` is not of the `.peel` format, not where the previous one ends, or
    /// not 2-aligned.
    #[cfg(any(feature = "textures", test))]
    Texture(u32),
}

impl core::fmt::Display for Gfx3dError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Gfx3dError::Magic => write!(
                f,
                "not an embedded-3dgfx scene (magic PTBG, version {VERSION})"
            ),
            Gfx3dError::Truncated => write!(f, "embedded-3dgfx scene shorter than its counts say"),
            Gfx3dError::Empty => write!(f, "embedded-3dgfx scene without vertices"),
            Gfx3dError::Scale => write!(f, "embedded-3dgfx scene with an unusable scale"),
            Gfx3dError::Index(t) => {
                write!(f, "embedded-3dgfx scene face {t} names a missing vertex")
            }
            Gfx3dError::Flags(flags) => write!(f, "embedded-3dgfx scene flags {flags:#06x}"),
            #[cfg(any(feature = "textures", test))]
            Gfx3dError::Group(g) => write!(f, "embedded-3dgfx scene group {g} is malformed"),
            #[cfg(any(feature = "textures", test))]
            Gfx3dError::Texture(k) => {
                write!(f, "embedded-3dgfx scene texture {k} is malformed")
            }
        }
    }
}

/// What the library's `Camera` needs to see what a [`LocalView`] sees, in the scene's scaled
/// units: `set_position(eye)`, `set_target(target)`, `set_fovy(fov_y)`,
/// `set_near_far(near, far)`, with its fixed up `+y` and its aspect ratio `width / height`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSetup {
    /// Eye position relative to the centre.
    pub eye: [f32; 3],
    /// A point straight ahead.
    pub target: [f32; 3],
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
}

/// The flags a scene may have: [`TEXTURED`] only with the `textures` feature (the firmware
/// builds with textures), so that the other builds hold none of its code.
const KNOWN_FLAGS: u16 = if cfg!(any(feature = "textures", test)) {
    VERTEX_NORMALS | TEXTURED
} else {
    VERTEX_NORMALS
};

/// A textured scene's sections ([`TEXTURED`]): coordinates (one per vertex), group records,
/// texture records and texel bytes.
#[cfg(any(feature = "textures", test))]
#[derive(Debug, Clone, Copy, Default)]
struct Sections<'a> {
    uvs: &'a [u8],
    groups: &'a [u8],
    textures: &'a [u8],
    texels: &'a [u8],
    /// Where the texel bytes start in the file.
    texels_at: usize,
}

#[cfg(any(feature = "textures", test))]
impl<'a> Sections<'a> {
    /// The sections of `bytes` from `start` on, for `nv` vertices.
    fn parse(bytes: &'a [u8], start: usize, nv: usize) -> Result<Sections<'a>, Gfx3dError> {
        let take = |start: usize, len: Option<usize>| {
            let end = len
                .and_then(|n| n.checked_add(start))
                .ok_or(Gfx3dError::Truncated)?;
            Ok::<_, Gfx3dError>((bytes.get(start..end).ok_or(Gfx3dError::Truncated)?, end))
        };
        let count = |at| {
            u32_at(bytes, at)
                .map(|n| n as usize)
                .ok_or(Gfx3dError::Truncated)
        };
        let (uvs, end) = take(start, nv.checked_mul(UV))?;
        let (groups, end) = take(end + 4, count(end)?.checked_mul(GROUP))?;
        let (nt, nd) = (count(end)?, count(end + 4)?);
        let (textures, end) = take(end + 8, nt.checked_mul(TEXTURE_SIZE))?;
        let (texels, _) = take(end, Some(nd))?;
        Ok(Sections {
            uvs,
            groups,
            textures,
            texels,
            texels_at: end,
        })
    }
}

/// A validated scene over borrowed bytes.
#[derive(Debug, Clone, Copy)]
pub struct Scene<'a> {
    vertices: &'a [u8],
    faces: &'a [u8],
    normals: &'a [u8],
    /// One per vertex, or none.
    vertex_normals: &'a [u8],
    /// A textured scene's sections (empty for another).
    #[cfg(any(feature = "textures", test))]
    sections: Sections<'a>,
    centre: [f64; 3],
    bounds_min: Vec3,
    bounds_max: Vec3,
    scale: f32,
    colour: u16,
}

impl<'a> Scene<'a> {
    /// Check `bytes` once (header, lengths, every index); the accessors cannot fail after.
    ///
    /// # Errors
    /// [`Gfx3dError`] for anything else than a scene of this version.
    pub fn parse(bytes: &'a [u8]) -> Result<Scene<'a>, Gfx3dError> {
        if bytes.get(..4) != Some(&MAGIC[..]) || u32_at(bytes, 4) != Some(VERSION) {
            return Err(Gfx3dError::Magic);
        }
        let count = |at| {
            u32_at(bytes, at)
                .map(|n| n as usize)
                .ok_or(Gfx3dError::Truncated)
        };
        let (nv, nf) = (count(8)?, count(12)?);
        let section = |start: usize, n: usize| {
            let end = n
                .checked_mul(ELEMENT)
                .and_then(|len| len.checked_add(start))
                .ok_or(Gfx3dError::Truncated)?;
            Ok((bytes.get(start..end).ok_or(Gfx3dError::Truncated)?, end))
        };
        let (vertices, v_end) = section(HEADER, nv)?;
        let (faces, f_end) = section(v_end, nf)?;
        let (normals, n_end) = section(f_end, nf)?;
        let flags = u16_at(bytes, 70).ok_or(Gfx3dError::Truncated)?;
        if flags & !KNOWN_FLAGS != 0 {
            return Err(Gfx3dError::Flags(flags));
        }
        let (vertex_normals, _end) = if flags & VERTEX_NORMALS != 0 {
            section(n_end, nv)?
        } else {
            (&bytes[..0], n_end)
        };
        #[cfg(any(feature = "textures", test))]
        let sections = if flags & TEXTURED != 0 {
            Sections::parse(bytes, _end, nv)?
        } else {
            Sections::default()
        };
        if nv == 0 {
            return Err(Gfx3dError::Empty);
        }
        let f = |at| f64_at(bytes, at).unwrap_or(0.0);
        let v = |at: usize| {
            let g = |k: usize| f32_at(bytes, at + 4 * k).unwrap_or(0.0);
            Vec3::new(g(0), g(1), g(2))
        };
        let scale = f32_at(bytes, 64).unwrap_or(0.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Gfx3dError::Scale);
        }
        let scene = Scene {
            vertices,
            faces,
            normals,
            vertex_normals,
            #[cfg(any(feature = "textures", test))]
            sections,
            centre: [f(16), f(24), f(32)],
            bounds_min: v(40),
            bounds_max: v(52),
            scale,
            colour: u16_at(bytes, 68).unwrap_or(0),
        };
        #[cfg(any(feature = "textures", test))]
        if flags & TEXTURED != 0 {
            scene.check_textures()?;
            return Ok(scene);
        }
        for t in 0..scene.face_count() {
            if scene.face(t).iter().any(|&i| i as usize >= nv) {
                return Err(Gfx3dError::Index(t));
            }
        }
        Ok(scene)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> u32 {
        (self.vertices.len() / ELEMENT) as u32
    }

    /// Number of faces.
    pub fn face_count(&self) -> u32 {
        (self.faces.len() / ELEMENT) as u32
    }

    /// The vertices' bytes: `[f32; 3]` each, little-endian.
    pub fn vertex_bytes(&self) -> &'a [u8] {
        self.vertices
    }

    /// The faces' bytes: `[u32; 3]` each, little-endian.
    pub fn face_bytes(&self) -> &'a [u8] {
        self.faces
    }

    /// The normals' bytes: `[f32; 3]` each, little-endian, one per face.
    pub fn normal_bytes(&self) -> &'a [u8] {
        self.normals
    }

    /// The vertex normals' bytes: `[f32; 3]` each, little-endian, one per vertex; empty
    /// without them (a flat scene).
    pub fn vertex_normal_bytes(&self) -> &'a [u8] {
        self.vertex_normals
    }

    /// Whether the scene has vertex normals (a smooth scene, [`encode_smooth`]).
    pub fn smooth(&self) -> bool {
        !self.vertex_normals.is_empty()
    }

    /// Vertex `i`'s unit normal (zeros past the end, or without vertex normals).
    pub fn vertex_normal(&self, i: u32) -> [f32; 3] {
        triple(self.vertex_normals, i).map(f32::from_bits)
    }

    /// Whether the scene is textured ([`encode_textured`]): drawn as its groups.
    #[cfg(any(feature = "textures", test))]
    pub fn textured(&self) -> bool {
        !self.sections.uvs.is_empty()
    }

    /// Number of groups (0 for a scene that is not textured).
    #[cfg(any(feature = "textures", test))]
    pub fn group_count(&self) -> u32 {
        (self.sections.groups.len() / GROUP) as u32
    }

    /// Group `g` of a textured scene (`None` past the end).
    #[cfg(any(feature = "textures", test))]
    pub fn group(&self, g: u32) -> Option<Group<'a>> {
        let at = g as usize * GROUP;
        let field = |k: usize| u32_at(self.sections.groups, at + 4 * k).map(|n| n as usize);
        let (v0, nv, f0, nf) = (field(0)?, field(1)?, field(2)?, field(3)?);
        let texture = field(4)? as u32;
        Some(Group {
            vertices: self.vertices.get(v0 * ELEMENT..(v0 + nv) * ELEMENT)?,
            uvs: self.sections.uvs.get(v0 * UV..(v0 + nv) * UV)?,
            faces: self.faces.get(f0 * ELEMENT..(f0 + nf) * ELEMENT)?,
            normals: self.normals.get(f0 * ELEMENT..(f0 + nf) * ELEMENT)?,
            texture: (texture != NO_TEXTURE).then_some(texture),
            colour: field(5)? as u16,
        })
    }

    /// Number of textures.
    #[cfg(any(feature = "textures", test))]
    pub fn texture_count(&self) -> u32 {
        (self.sections.textures.len() / TEXTURE_SIZE) as u32
    }

    /// Texture `k`, its bytes in place, as the `.peel` file's reader gives it.
    #[cfg(any(feature = "textures", test))]
    pub fn texture(&self, k: u32) -> Option<Texture<'a>> {
        let at = k as usize * TEXTURE_SIZE;
        let record = self.sections.textures.get(at..at + TEXTURE_SIZE)?;
        let (log2_width, log2_height, flags) = (record[0], record[1], record[2]);
        let colours = if flags & texture_flags::PALETTE != 0 {
            u32::from(record[3]) + 1
        } else {
            0
        };
        let start = u32_at(record, 4)? as usize;
        let size = texture_bytes(log2_width, log2_height, flags, colours);
        let bytes = self.sections.texels.get(start..start.checked_add(size)?)?;
        let (colours, texels) = bytes.split_at(colours as usize * 2);
        Some(Texture {
            log2_width,
            log2_height,
            flags,
            colours,
            texels,
        })
    }

    /// A textured scene's groups and textures checked: each group where the previous one ends and its faces' indices
    /// within it, each texture record of the `.peel` format where the previous one ends, its
    /// RGB565 values 2-aligned in the file.
    #[cfg(any(feature = "textures", test))]
    fn check_textures(&self) -> Result<(), Gfx3dError> {
        let texels_at = self.sections.texels_at;
        let (mut vertices, mut faces) = (0, 0);
        for g in 0..self.group_count() {
            let at = g as usize * GROUP;
            let field = |k: usize| u32_at(self.sections.groups, at + 4 * k).unwrap_or(0) as usize;
            let texture = field(4) as u32;
            if field(0) != vertices
                || field(2) != faces
                || (texture != NO_TEXTURE && texture >= self.texture_count())
            {
                return Err(Gfx3dError::Group(g));
            }
            let group = self.group(g).ok_or(Gfx3dError::Group(g))?;
            for t in 0..group.face_count() {
                if group.face(t).iter().any(|&i| i >= group.vertex_count()) {
                    return Err(Gfx3dError::Index(faces as u32 + t));
                }
            }
            (vertices, faces) = (vertices + field(1), faces + field(3));
        }
        if vertices != self.vertex_count() as usize || faces != self.face_count() as usize {
            return Err(Gfx3dError::Group(self.group_count()));
        }
        let mut end = 0;
        for k in 0..self.texture_count() {
            let record = &self.sections.textures[k as usize * TEXTURE_SIZE..][..TEXTURE_SIZE];
            let (log2_width, log2_height, flags) = (record[0], record[1], record[2]);
            let palette = flags & texture_flags::PALETTE != 0;
            let offset = u32_at(record, 4).unwrap_or(0) as usize;
            let ok = log2_width <= MAX_TEXTURE_LOG2
                && log2_height <= MAX_TEXTURE_LOG2
                && flags & !texture_flags::KNOWN == 0
                && (palette || record[3] == 0)
                && offset == end
                && (texels_at + offset).is_multiple_of(2);
            let texture = self
                .texture(k)
                .filter(|_| ok)
                .ok_or(Gfx3dError::Texture(k))?;
            end += texture.colours.len() + texture.texels.len();
        }
        if end != self.sections.texels.len() {
            return Err(Gfx3dError::Texture(self.texture_count()));
        }
        Ok(())
    }

    /// Vertex `i`, scaled, relative to the centre (zeros past the end).
    pub fn vertex(&self, i: u32) -> [f32; 3] {
        triple(self.vertices, i).map(f32::from_bits)
    }

    /// Face `t`'s vertex indices (zeros past the end).
    pub fn face(&self, t: u32) -> [u32; 3] {
        triple(self.faces, t)
    }

    /// Face `t`'s unit normal (zeros past the end).
    pub fn normal(&self, t: u32) -> [f32; 3] {
        triple(self.normals, t).map(f32::from_bits)
    }

    /// Library units per scene unit.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The mesh's RGB565 colour.
    pub fn colour(&self) -> u16 {
        self.colour
    }

    /// Bounds of the scene (relative to the centre, unscaled), as the `.peel` header has them.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.bounds_min, self.bounds_max)
    }

    /// A header with the `.peel` scene's centre and bounds (the rest zero), as
    /// [`crate::mesh::Mesh::header`]: what the orbit camera reads.
    pub fn header(&self) -> Header {
        Header {
            vertex_count: self.vertex_count(),
            polygon_count: self.face_count(),
            max_polygon_vertices: 3,
            centre: self.centre,
            bounds_min: self.bounds_min,
            bounds_max: self.bounds_max,
            ..Header::default()
        }
    }

    /// The library's camera for `view`. Its camera has square pixels, the principal point at
    /// the image centre and `+y` up: it sees exactly what `view` sees when `view` has those
    /// too (every orbit view does), the focal length `fy` becoming the field of view.
    ///
    /// Near and far come from the scene's depth range in this view (its box in camera space,
    /// as the z-buffer baseline fits its depth range): far at the farthest point, near at half
    /// the nearest. The library's depth `far + 2 near - 2 far near / z` (cut to whole units,
    /// a negative one read as 0, the nearest) then runs from the nearest point's `z` to the
    /// farthest's, and no vertex falls outside near..far, which would drop its triangles.
    pub fn camera(&self, view: &LocalView) -> CameraSetup {
        let s = self.scale;
        let b = view.box_to_camera(self.bounds_min, self.bounds_max);
        let nearest = b.centre.z - b.extent.z - b.error;
        let farthest = b.centre.z + b.extent.z + b.error;
        // An eye inside the box (no orbit view): the view's near plane, whatever the depths.
        let near = (0.5 * nearest).max(view.near) * s;
        // A little past the farthest point: the library computes it in its own `f32` steps.
        let far = (farthest * s * (1.0 + 1.0 / 1024.0)).max(near * 2.0);
        // Straight ahead, as far as the box's centre (any positive distance looks the same).
        let ahead = b.centre.z.max(view.near);
        CameraSetup {
            eye: (view.eye * s).to_array(),
            target: ((view.eye + view.forward * ahead) * s).to_array(),
            fov_y: 2.0 * libm::atanf(0.5 * view.height as f32 / view.fy),
            near,
            far,
        }
    }
}

#[cfg(any(feature = "textures", test))]
/// One group of a textured scene: one mesh of the library, with one texture (or none) and one
/// colour; its faces' indices count from its first vertex.
#[derive(Debug, Clone, Copy)]
pub struct Group<'a> {
    /// Its vertices' bytes: `[f32; 3]` each, little-endian.
    pub vertices: &'a [u8],
    /// Its vertices' texture coordinates: `[f32; 2]` each, `(0, 0)` the image's top left.
    pub uvs: &'a [u8],
    /// Its faces' bytes: `[u32; 3]` each, indices into its vertices.
    pub faces: &'a [u8],
    /// Its faces' unit normals: `[f32; 3]` each.
    pub normals: &'a [u8],
    /// Its texture, or `None`.
    pub texture: Option<u32>,
    /// Its material's RGB565 colour.
    pub colour: u16,
}

#[cfg(any(feature = "textures", test))]
impl Group<'_> {
    /// Number of vertices.
    pub fn vertex_count(&self) -> u32 {
        (self.vertices.len() / ELEMENT) as u32
    }

    /// Number of faces.
    pub fn face_count(&self) -> u32 {
        (self.faces.len() / ELEMENT) as u32
    }

    /// Face `t`'s vertex indices (zeros past the end).
    pub fn face(&self, t: u32) -> [u32; 3] {
        triple(self.faces, t)
    }

    /// Vertex `i`'s texture coordinates (zeros past the end).
    pub fn uv(&self, i: u32) -> [f32; 2] {
        let at = i as usize * UV;
        [0, 4].map(|k| f32_at(self.uvs, at + k).unwrap_or(0.0))
    }
}

/// Element `i` of a section of 12-byte elements, as three words.
fn triple(section: &[u8], i: u32) -> [u32; 3] {
    let at = i as usize * ELEMENT;
    [0, 1, 2].map(|k| u32_at(section, at + 4 * k).unwrap_or(0))
}

/// The scene's bytes from the z-buffer baseline's mesh: vertices scaled (see [`RADIUS`]),
/// faces with their normals, exactly degenerate ones left out, and one colour: the brightest
/// of the faces' baked colours (red, green and blue summed at 8 bits each, the first of
/// equals), that of a face turned towards the light, so about the material's own colour for a
/// one-colour mesh. `None` when the mesh's bounds are not finite.
#[cfg(any(feature = "std", test))]
pub fn encode(mesh: &crate::mesh::Mesh<'_>) -> Option<std::vec::Vec<u8>> {
    encode_with(mesh, None)
}

/// As [`encode`], with vertex normals for the library's Gouraud mode: `corners[t]` the unit
/// normals of triangle `t`'s corners (e.g. the compiler's `corner_normals`, as its smooth files
/// are shaded). Each distinct point and corner normal is one vertex (a point whose corners
/// have several normals, on a crease, is several). `None` when the bounds are not finite, or
/// when `corners` is not one per triangle.
#[cfg(any(feature = "std", test))]
pub fn encode_smooth(
    mesh: &crate::mesh::Mesh<'_>,
    corners: &[[[f32; 3]; 3]],
) -> Option<std::vec::Vec<u8>> {
    if corners.len() != mesh.triangle_count() as usize {
        return None;
    }
    encode_with(mesh, Some(corners))
}

#[cfg(any(feature = "std", test))]
fn encode_with(
    mesh: &crate::mesh::Mesh<'_>,
    corners: Option<&[[[f32; 3]; 3]]>,
) -> Option<std::vec::Vec<u8>> {
    let scale = scale_of(mesh)?;
    let positions = scaled_positions(mesh, scale);
    // Smooth: one vertex per distinct point and normal, in order of first use.
    let mut vertices: std::vec::Vec<Vec3> = std::vec::Vec::new();
    let mut vertex_normals: std::vec::Vec<[f32; 3]> = std::vec::Vec::new();
    let mut index: std::collections::HashMap<(u16, [u32; 3]), u32> =
        std::collections::HashMap::new();
    if corners.is_none() {
        vertices.clone_from(&positions);
    }
    let mut faces = std::vec::Vec::new();
    let mut normals = std::vec::Vec::new();
    let mut colour: Option<u16> = None;
    for t in 0..mesh.triangle_count() {
        let (corner_ids, rgb) = mesh.triangle(t);
        let Some(n) = face_normal(&positions, corner_ids) else {
            continue;
        };
        if colour.is_none_or(|c| brightness(rgb) > brightness(c)) {
            colour = Some(rgb);
        }
        let face = match corners {
            None => corner_ids.map(u32::from),
            Some(corners) => {
                let mut k = 0;
                corner_ids.map(|i| {
                    let normal = corners[t as usize][k];
                    k += 1;
                    *index
                        .entry((i, normal.map(f32::to_bits)))
                        .or_insert_with(|| {
                            vertices.push(positions[usize::from(i)]);
                            vertex_normals.push(normal);
                            (vertices.len() - 1) as u32
                        })
                })
            }
        };
        faces.push(face);
        normals.push(n);
    }
    let flags = if corners.is_some() { VERTEX_NORMALS } else { 0 };
    let mut out = start(mesh, &vertices, &faces, scale, colour.unwrap_or(0), flags);
    end_with(&mut out, &normals, &vertex_normals);
    Some(out)
}

/// A triangle's texture for [`encode_textured`]: the texture (its index among the
/// `.peel` file's) and its corners' coordinates as the library takes them (`(0, 0)` the
/// image's top left, 1 a whole side: the file's `s` and `t` over `2^16`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerTexture {
    /// The texture.
    pub texture: u32,
    /// `(u, v)` per corner, in the order of the triangle's vertices.
    pub uv: [[f32; 2]; 3],
}

/// The textured scene's bytes ([`TEXTURED`]): the mesh's faces (exactly degenerate ones left
/// out, as in [`encode`]) in groups of one texture and colour, in order of first use:
/// `corners[t]` is triangle `t`'s texture (`None`: untextured) and `colours[t]` its material's
/// RGB565 colour (which the library lights), `textures` the `.peel` file's textures, stored as
/// that file stores them. `None` when the bounds are not finite, `corners` or `colours` is not
/// one per triangle, or a triangle names a texture past `textures`.
#[cfg(any(feature = "std", test))]
pub fn encode_textured(
    mesh: &crate::mesh::Mesh<'_>,
    corners: &[Option<CornerTexture>],
    colours: &[u16],
    textures: &[Texture<'_>],
) -> Option<std::vec::Vec<u8>> {
    use std::collections::HashMap;
    use std::vec::Vec;
    let n = mesh.triangle_count() as usize;
    if corners.len() != n || colours.len() != n {
        return None;
    }
    let scale = scale_of(mesh)?;
    let positions = scaled_positions(mesh, scale);
    /// A group being made: its key, vertices (with the point they are of), coordinates,
    /// faces and normals.
    #[derive(Default)]
    struct Making {
        key: (u32, u16),
        index: HashMap<(u16, [u32; 2]), u32>,
        vertices: Vec<Vec3>,
        uvs: Vec<[f32; 2]>,
        faces: Vec<[u32; 3]>,
        normals: Vec<Vec3>,
    }
    let mut groups: Vec<Making> = Vec::new();
    for t in 0..mesh.triangle_count() {
        let (corner_ids, _) = mesh.triangle(t);
        let Some(normal) = face_normal(&positions, corner_ids) else {
            continue;
        };
        let texture = corners[t as usize];
        let key = (
            texture.map_or(NO_TEXTURE, |c| c.texture),
            colours[t as usize],
        );
        if texture.is_some_and(|c| c.texture as usize >= textures.len()) {
            return None;
        }
        let g = match groups.iter().position(|g| g.key == key) {
            Some(g) => g,
            None => {
                groups.push(Making {
                    key,
                    ..Making::default()
                });
                groups.len() - 1
            }
        };
        let group = &mut groups[g];
        let mut k = 0;
        let face = corner_ids.map(|i| {
            let uv = texture.map_or([0.0; 2], |c| c.uv[k]);
            k += 1;
            *group
                .index
                .entry((i, uv.map(f32::to_bits)))
                .or_insert_with(|| {
                    group.vertices.push(positions[usize::from(i)]);
                    group.uvs.push(uv);
                    (group.vertices.len() - 1) as u32
                })
        });
        group.faces.push(face);
        group.normals.push(normal);
    }
    let vertices: Vec<Vec3> = groups.iter().flat_map(|g| g.vertices.clone()).collect();
    let faces: Vec<[u32; 3]> = groups.iter().flat_map(|g| g.faces.clone()).collect();
    let normals: Vec<Vec3> = groups.iter().flat_map(|g| g.normals.clone()).collect();
    let colour = groups.first().map_or(0, |g| g.key.1);
    let mut out = start(mesh, &vertices, &faces, scale, colour, TEXTURED);
    end_with(&mut out, &normals, &[]);
    for g in &groups {
        for uv in &g.uvs {
            for c in uv {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let word = |out: &mut Vec<u8>, w: usize| out.extend_from_slice(&(w as u32).to_le_bytes());
    word(&mut out, groups.len());
    let (mut first_vertex, mut first_face) = (0, 0);
    for g in &groups {
        for w in [
            first_vertex,
            g.vertices.len(),
            first_face,
            g.faces.len(),
            g.key.0 as usize,
            usize::from(g.key.1),
        ] {
            word(&mut out, w);
        }
        first_vertex += g.vertices.len();
        first_face += g.faces.len();
    }
    let texel_bytes: usize = textures
        .iter()
        .map(|t| t.colours.len() + t.texels.len())
        .sum();
    word(&mut out, textures.len());
    word(&mut out, texel_bytes);
    let mut offset = 0;
    for t in textures {
        let colours = t.colours.len() / 2;
        out.extend_from_slice(&[
            t.log2_width,
            t.log2_height,
            t.flags,
            colours.saturating_sub(1) as u8,
        ]);
        word(&mut out, offset);
        offset += t.colours.len() + t.texels.len();
    }
    for t in textures {
        out.extend_from_slice(t.colours);
        out.extend_from_slice(t.texels);
    }
    out.resize(out.len().next_multiple_of(4), 0);
    Some(out)
}

/// Library units per scene unit: a power of two that puts the scene's radius in
/// [`RADIUS`]`..2 * RADIUS`; `None` when the bounds are not finite.
#[cfg(any(feature = "std", test))]
fn scale_of(mesh: &crate::mesh::Mesh<'_>) -> Option<f32> {
    let (lo, hi) = mesh.bounds();
    let radius = (hi - lo).length() * 0.5;
    if !radius.is_finite() {
        return None;
    }
    // `radius = m 2^e` with `m` in 0.5..1, so `radius * 2^(14 - e)` lies in 8192..16384.
    Some(if radius > 0.0 {
        libm::ldexpf(1.0, 14 - libm::frexpf(radius).1)
    } else {
        1.0
    })
}

/// The mesh's vertices times `scale`.
#[cfg(any(feature = "std", test))]
fn scaled_positions(mesh: &crate::mesh::Mesh<'_>, scale: f32) -> std::vec::Vec<Vec3> {
    (0..mesh.header().vertex_count)
        .map(|i| mesh.vertex(i as u16) * scale)
        .collect()
}

/// The unit normal of the triangle `corners` of `positions`; `None` when it is exactly
/// degenerate.
#[cfg(any(feature = "std", test))]
fn face_normal(positions: &[Vec3], corners: [u16; 3]) -> Option<Vec3> {
    let [p, q, s] = corners.map(|i| positions[usize::from(i)].as_dvec3());
    let n = (q - p).cross(s - p);
    (n != glam::DVec3::ZERO).then(|| n.normalize().as_vec3())
}

/// Red, green and blue of an RGB565 colour summed at 8 bits each.
#[cfg(any(feature = "std", test))]
fn brightness(c: u16) -> u16 {
    ((c >> 11) << 3) + (((c >> 5) & 0x3f) << 2) + ((c & 0x1f) << 3)
}

/// The header, `vertices` and `faces` of a scene of `mesh` at `scale` with `colour` and
/// `flags`.
#[cfg(any(feature = "std", test))]
fn start(
    mesh: &crate::mesh::Mesh<'_>,
    vertices: &[Vec3],
    faces: &[[u32; 3]],
    scale: f32,
    colour: u16,
    flags: u16,
) -> std::vec::Vec<u8> {
    let header = mesh.header();
    let (lo, hi) = mesh.bounds();
    let mut out =
        std::vec::Vec::with_capacity(HEADER + ELEMENT * 3 * (vertices.len() + faces.len()));
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(vertices.len() as u32).to_le_bytes());
    out.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for c in header.centre {
        out.extend_from_slice(&c.to_le_bytes());
    }
    for v in [lo, hi] {
        words(&mut out, v.to_array().map(f32::to_bits));
    }
    out.extend_from_slice(&scale.to_le_bytes());
    out.extend_from_slice(&colour.to_le_bytes());
    out.extend_from_slice(&flags.to_le_bytes());
    for v in vertices {
        words(&mut out, v.to_array().map(f32::to_bits));
    }
    for &f in faces {
        words(&mut out, f);
    }
    out
}

/// The face normals and vertex normals after the faces.
#[cfg(any(feature = "std", test))]
fn end_with(out: &mut std::vec::Vec<u8>, normals: &[Vec3], vertex_normals: &[[f32; 3]]) {
    for n in normals {
        words(out, n.to_array().map(f32::to_bits));
    }
    for n in vertex_normals {
        words(out, n.map(f32::to_bits));
    }
}

/// Three little-endian words.
#[cfg(any(feature = "std", test))]
fn words(out: &mut std::vec::Vec<u8>, v: [u32; 3]) {
    for w in v {
        out.extend_from_slice(&w.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::OrbitAngles;
    use crate::mesh::{test_header, Mesh};
    use glam::DVec3;
    use std::vec::Vec;

    /// A tetrahedron around the origin (outward faces, three colours) and one degenerate
    /// triangle, as the z-buffer's mesh.
    fn mesh_bytes() -> Vec<u8> {
        let vertices = [
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let triangles = [
            ([0, 1, 2], 0xf800),
            ([0, 3, 1], 0x8410),
            ([0, 2, 3], 0x0400),
            ([1, 3, 2], 0x8410),
            ([0, 4, 0], 0xffff),
        ];
        let header = test_header([10.0, 20.0, 30.0], Vec3::splat(-1.0), Vec3::splat(1.0));
        crate::mesh::encode(&header, &vertices, &triangles).unwrap()
    }

    fn scene_bytes() -> Vec<u8> {
        encode(&Mesh::parse(&mesh_bytes()).unwrap()).unwrap()
    }

    #[test]
    fn round_trip() {
        let source = mesh_bytes();
        let mesh = Mesh::parse(&source).unwrap();
        let bytes = encode(&mesh).unwrap();
        let scene = Scene::parse(&bytes).unwrap();
        // Radius sqrt(3): scaled into 8192..16384 by a power of two.
        let s = scene.scale();
        assert_eq!(s, 8192.0);
        assert!((RADIUS..2.0 * RADIUS).contains(&(3f32.sqrt() * s)));
        assert_eq!(scene.vertex_count(), 5);
        for i in 0..5 {
            assert_eq!(scene.vertex(i), (mesh.vertex(i as u16) * s).to_array());
        }
        // The degenerate triangle is left out.
        assert_eq!(scene.face_count(), 4);
        assert_eq!(scene.face(1), [0, 3, 1]);
        for t in 0..4 {
            let [a, b, c] = scene.face(t).map(|i| Vec3::from_array(scene.vertex(i)));
            let n = Vec3::from_array(scene.normal(t));
            assert!((n.length() - 1.0).abs() < 1e-6);
            assert!(n.dot(b - a).abs() < 1e-2 && n.dot(c - a).abs() < 1e-2);
            // Outward: away from the centre.
            assert!(n.dot(a) > 0.0);
        }
        assert_eq!(scene.vertex_bytes().len(), 5 * ELEMENT);
        assert_eq!(scene.face_bytes().len(), 4 * ELEMENT);
        assert_eq!(scene.normal_bytes().len(), 4 * ELEMENT);
        assert_eq!(bytes.len(), HEADER + 13 * ELEMENT);
        // The brightest face's (the first of two), not the degenerate triangle's.
        assert_eq!(scene.colour(), 0x8410);
        let (h, m) = (scene.header(), mesh.header());
        assert_eq!(
            (h.centre, h.bounds_min, h.bounds_max),
            (m.centre, m.bounds_min, m.bounds_max)
        );
        assert_eq!(scene.bounds(), mesh.bounds());
    }

    #[test]
    fn smooth_scenes_have_a_vertex_per_point_and_normal() {
        let source = mesh_bytes();
        let mesh = Mesh::parse(&source).unwrap();
        assert!(!Scene::parse(&encode(&mesh).unwrap()).unwrap().smooth());
        // Every corner of point 0 one normal (+y) but in face 1 (+x): point 0 is two
        // vertices; the others one each (point 4 only in the degenerate triangle: none).
        let mut corners = std::vec![[[0.0, 1.0, 0.0]; 3]; 5];
        corners[1][0] = [1.0, 0.0, 0.0];
        assert!(encode_smooth(&mesh, &corners[..4]).is_none());
        let bytes = encode_smooth(&mesh, &corners).unwrap();
        let scene = Scene::parse(&bytes).unwrap();
        assert!(scene.smooth());
        assert_eq!((scene.vertex_count(), scene.face_count()), (5, 4));
        assert_eq!(scene.vertex_normal_bytes().len(), 5 * ELEMENT);
        assert_eq!(bytes.len(), HEADER + 18 * ELEMENT);
        // Faces in their order, vertices in order of first use: 0 1 2, then 0' 3 1.
        assert_eq!(scene.face(0), [0, 1, 2]);
        assert_eq!(scene.face(1), [3, 4, 1]);
        assert_eq!(scene.vertex(3), scene.vertex(0));
        assert_eq!(scene.vertex_normal(3), [1.0, 0.0, 0.0]);
        assert_eq!(scene.vertex_normal(4), [0.0, 1.0, 0.0]);
        let flat_bytes = scene_bytes();
        let flat = Scene::parse(&flat_bytes).unwrap();
        for t in 0..4 {
            // The same corners' points and face normals as the flat scene.
            let points = |s: &Scene, t| s.face(t).map(|i| s.vertex(i));
            assert_eq!(points(&scene, t), points(&flat, t));
            assert_eq!(scene.normal(t), flat.normal(t));
        }
        // Vertex normals cut short.
        assert_eq!(
            Scene::parse(&bytes[..bytes.len() - 1]).err(),
            Some(Gfx3dError::Truncated)
        );
    }

    #[test]
    fn textured_scenes_are_groups_of_one_texture_and_colour() {
        let source = mesh_bytes();
        let mesh = Mesh::parse(&source).unwrap();
        // Two textures of the `.peel` format: 2 x 2 RGB565 texels, and a palette of three
        // colours for 4 x 2 indices.
        let direct = [1u8, 0, 2, 0, 3, 0, 4, 0];
        let palette = [5u8, 0, 6, 0, 7, 0];
        let indices = [0u8, 1, 2, 0, 1, 2, 0, 1];
        let textures = [
            Texture {
                log2_width: 1,
                log2_height: 1,
                flags: 0,
                colours: &[],
                texels: &direct,
            },
            Texture {
                log2_width: 2,
                log2_height: 1,
                flags: texture_flags::PALETTE | texture_flags::CLAMP_S,
                colours: &palette,
                texels: &indices,
            },
        ];
        let uv = |t: f32| [[t, 0.0], [0.0, t], [t, t]];
        let corner = |texture, t| Some(CornerTexture { texture, uv: uv(t) });
        // Faces 0 and 2 under texture 1 (sharing two points, with other coordinates), face 1
        // under texture 0, face 3 untextured; the degenerate triangle left out.
        let corners = [corner(1, 0.5), corner(0, 0.25), corner(1, 0.75), None, None];
        let colours = [0xffff; 5];
        assert!(encode_textured(&mesh, &corners[..4], &colours, &textures).is_none());
        assert!(encode_textured(&mesh, &corners, &colours, &textures[..1]).is_none());
        let bytes = encode_textured(&mesh, &corners, &colours, &textures).unwrap();
        assert_eq!(bytes.len() % 4, 0);
        let scene = Scene::parse(&bytes).unwrap();
        assert!(scene.textured() && !scene.smooth());
        assert_eq!((scene.face_count(), scene.group_count()), (4, 3));
        let groups: Vec<Group> = (0..3).map(|g| scene.group(g).unwrap()).collect();
        assert!(scene.group(3).is_none());
        assert_eq!(
            groups.iter().map(|g| g.texture).collect::<Vec<_>>(),
            [Some(1), Some(0), None]
        );
        assert_eq!(
            groups
                .iter()
                .map(|g| (g.vertex_count(), g.face_count()))
                .collect::<Vec<_>>(),
            [(6, 2), (3, 1), (3, 1)]
        );
        let flat_bytes = scene_bytes();
        let flat = Scene::parse(&flat_bytes).unwrap();
        // Each face's corners, coordinates and normal as given, in group order: 0, 2, 1, 3.
        for (g, t, source) in [(0, 0, 0), (0, 1, 2), (1, 0, 1), (2, 0, 3)] {
            let group = groups[g];
            let at = |i: u32| triple(group.vertices, i).map(f32::from_bits);
            assert_eq!(
                group.face(t).map(at),
                flat.face(source).map(|i| flat.vertex(i))
            );
            let want = corners[source as usize].map_or([[0.0; 2]; 3], |c| c.uv);
            assert_eq!(group.face(t).map(|i| group.uv(i)), want);
            assert_eq!(
                triple(group.normals, t).map(f32::from_bits),
                flat.normal(source)
            );
            assert_eq!(group.colour, 0xffff);
        }
        for (k, t) in textures.iter().enumerate() {
            assert_eq!(scene.texture(k as u32), Some(*t));
        }
        assert_eq!(scene.texture(2), None);
        let corrupt = |at: usize, value: &[u8]| {
            let mut b = bytes.clone();
            b[at..at + value.len()].copy_from_slice(value);
            Scene::parse(&b).err()
        };
        assert_eq!(corrupt(70, &6u16.to_le_bytes()), Some(Gfx3dError::Flags(6)));
        let groups_at = HEADER + 20 * ELEMENT + 12 * UV + 4;
        // Group 1's first vertex, texture; a face index past its group.
        assert_eq!(
            corrupt(groups_at + GROUP, &4u32.to_le_bytes()),
            Some(Gfx3dError::Group(1))
        );
        assert_eq!(
            corrupt(groups_at + GROUP + 16, &2u32.to_le_bytes()),
            Some(Gfx3dError::Group(1))
        );
        let face_1 = HEADER + 12 * ELEMENT + ELEMENT;
        assert_eq!(
            corrupt(face_1, &6u32.to_le_bytes()),
            Some(Gfx3dError::Index(1))
        );
        // Texture 1's offset, and an unknown flag.
        let records = groups_at + 3 * GROUP + 8;
        assert_eq!(
            corrupt(records + TEXTURE_SIZE + 4, &9u32.to_le_bytes()),
            Some(Gfx3dError::Texture(1))
        );
        assert_eq!(corrupt(records + 2, &[8]), Some(Gfx3dError::Texture(0)));
        for len in [bytes.len() - 4, groups_at] {
            assert_eq!(
                Scene::parse(&bytes[..len]).err(),
                Some(Gfx3dError::Truncated)
            );
        }
    }

    #[test]
    fn light_is_the_compilers_default_normalised() {
        let l = DVec3::new(0.4, 0.8, 0.45).normalize().as_vec3();
        assert!((Vec3::from_array(LIGHT) - l).length() < 1e-6);
    }

    #[test]
    fn refusals() {
        let bytes = scene_bytes();
        assert!(Scene::parse(&bytes).is_ok());
        for len in 0..bytes.len() {
            let e = Scene::parse(&bytes[..len]).err();
            let expected = if len < 8 {
                Gfx3dError::Magic
            } else {
                Gfx3dError::Truncated
            };
            assert_eq!(e, Some(expected), "{len} bytes");
        }
        let corrupt = |at: usize, value: &[u8]| {
            let mut b = bytes.clone();
            b[at..at + value.len()].copy_from_slice(value);
            Scene::parse(&b).err()
        };
        assert_eq!(corrupt(0, b"PTBM"), Some(Gfx3dError::Magic));
        assert_eq!(corrupt(4, &1u32.to_le_bytes()), Some(Gfx3dError::Magic));
        assert_eq!(corrupt(8, &6u32.to_le_bytes()), Some(Gfx3dError::Truncated));
        assert_eq!(
            corrupt(12, &u32::MAX.to_le_bytes()),
            Some(Gfx3dError::Truncated)
        );
        for bad in [0.0f32, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(corrupt(64, &bad.to_le_bytes()), Some(Gfx3dError::Scale));
        }
        // Face 2's last index: vertex 5 of 5.
        let at = HEADER + 5 * ELEMENT + 2 * ELEMENT + 8;
        assert_eq!(corrupt(at, &5u32.to_le_bytes()), Some(Gfx3dError::Index(2)));
        // No vertices (and so no faces).
        let mut empty = bytes[..HEADER].to_vec();
        empty[8..16].fill(0);
        assert_eq!(Scene::parse(&empty).err(), Some(Gfx3dError::Empty));
        // Unusable bounds.
        let header = test_header([0.0; 3], Vec3::splat(-1.0), Vec3::splat(f32::INFINITY));
        let m = crate::mesh::encode(&header, &[Vec3::X], &[]).unwrap();
        assert!(encode(&Mesh::parse(&m).unwrap()).is_none());
    }

    /// The library's projection, written out: `look_at_rh(eye, target, +y)`, then
    /// `Perspective3(width / height, fov_y, near, far)`, then its viewport and depth maps.
    fn library_projection(c: &CameraSetup, w: u32, h: u32, p: [f32; 3]) -> (f64, f64, f64) {
        let d = |v: [f32; 3]| DVec3::from_array(v.map(f64::from));
        let (eye, target) = (d(c.eye), d(c.target));
        let z_axis = (eye - target).normalize();
        let x_axis = DVec3::Y.cross(z_axis).normalize();
        let y_axis = z_axis.cross(x_axis);
        let v = d(p) - eye;
        let (x, y, depth) = (v.dot(x_axis), v.dot(y_axis), -v.dot(z_axis));
        let t = (f64::from(c.fov_y) * 0.5).tan();
        let aspect = f64::from(w) / f64::from(h);
        let (n, f) = (f64::from(c.near), f64::from(c.far));
        let ndc_z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * depth);
        (
            (1.0 + x / (depth * aspect * t)) * 0.5 * f64::from(w),
            (1.0 - y / (depth * t)) * 0.5 * f64::from(h),
            ndc_z * (f - n) + n,
        )
    }

    #[test]
    fn camera_sees_what_the_view_sees() {
        let bytes = scene_bytes();
        let scene = Scene::parse(&bytes).unwrap();
        let s = scene.scale();
        for (az, el) in [(0.0, 20.0), (45.0, 20.0), (200.0, -30.0)] {
            let angles = OrbitAngles {
                azimuth_deg: az,
                elevation_deg: el,
            };
            let (w, h) = (320, 240);
            let view = crate::orbit_view(&scene.header(), angles, 60.0, w, h).unwrap();
            let c = scene.camera(&view);
            assert!(0.0 < c.near && c.near < c.far);
            for i in 0..scene.vertex_count() {
                let p = scene.vertex(i);
                let (x, y, depth) = library_projection(&c, w, h, p);
                let camera = view.to_camera(Vec3::from_array(p) / s);
                let expected = view.project(camera);
                assert!((x - f64::from(expected.x)).abs() < 1e-3, "{x} {expected}");
                assert!((y - f64::from(expected.y)).abs() < 1e-3, "{y} {expected}");
                // Between the nearest point's distance (twice near) and far, inside 16 bits.
                let (n, f) = (f64::from(c.near), f64::from(c.far));
                assert!(
                    2.0 * n * (1.0 - 1e-6) <= depth && depth <= f,
                    "{depth} {n} {f}"
                );
                assert!((1.0..65535.0).contains(&depth));
            }
        }
    }
}
