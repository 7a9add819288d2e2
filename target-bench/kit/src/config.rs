//! The config block: what one firmware run draws (image size, band height, span memory,
//! background, camera path). The runner writes it to a file that QEMU loads at
//! [`crate::layout::CONFIG_ADDR`]; a fixed size and little-endian fields, so the firmware reads
//! it in place with no parser state.
//!
//! | offset | field |
//! |---|---|
//! | 0 | magic `PTBC` |
//! | 4 | [`VERSION`] (u32) |
//! | 8 | [`Variant`] code (u32): the build it was written for |
//! | 12, 16 | width, height (u32) |
//! | 20 | band rows (u32; 0 for whole frames) |
//! | 24 | span-memory intervals per row (u32) |
//! | 28 | asset length in bytes (u32) |
//! | 32 | background `0x00RRGGBB` (u32) |
//! | 36 | flags (u32): bit 0 = write each frame's panel memory to a host file |
//! | 40 | vertical field of view in degrees (f64) |
//! | 48 | camera count (u32), then 4 bytes of padding |
//! | 56 | [`MAX_CAMERAS`] x (azimuth, elevation) in degrees (f64, f64) |
//! | 312 | the scanline z-buffer's active edges (u32) |
//! | 316 | the scanline z-buffer's clipped points (u32) |
//! | 320 | scan memory nodes (u32; scan order) |
//! | 324 | pending-pixel records (u32; anti-aliased) |
//! | 328 | composite runs (u32; 0 for none: the streamed build with transparency) |

use crate::bytes::{f64_at, u32_at};

/// Format version.
pub const VERSION: u32 = 5;
/// The block's first bytes.
pub const MAGIC: [u8; 4] = *b"PTBC";
/// Cameras a block holds.
pub const MAX_CAMERAS: usize = 16;
/// Size of the block in bytes.
pub const SIZE: usize = LISTS + 20;
/// Offset of the scanline z-buffer's list sizes.
const LISTS: usize = 56 + 16 * MAX_CAMERAS;
/// Flag: write each frame's panel memory to the host file `frame-<k>.rgb565`.
pub const WRITE_FRAMES: u32 = 1;

/// A firmware build: the method and how its frame reaches the display. One cargo feature of
/// the firmware each (the feature is [`Variant::name`]), so each build holds only its own code
/// and memory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Variant {
    /// Peel front to back into a full RGB565 framebuffer, sent in one transfer.
    FtbFramebuffer,
    /// Peel front to back, each span sent to the display as it is drawn: no framebuffer.
    FtbStream,
    /// As [`Variant::FtbStream`], anti-aliased (`Renderer::antialias`): partly covered pixels
    /// wait in a pool of pending-pixel records and reach the display when finished.
    StreamAa,
    /// Peel front to back in bands of rows, each band sent when done.
    FtbBands,
    /// Peel front to back into scan memory (each covered interval with its colour), the frame
    /// then sent in scan order as one window: no framebuffer.
    ScanOrder,
    /// As [`Variant::ScanOrder`], anti-aliased: the pending pixels stay in their pool and the
    /// read-out merges them into the scan memory's gaps.
    ScanAa,
    /// Peel back to front (painter's algorithm) into a full framebuffer.
    B2fFramebuffer,
    /// Peel back to front in bands of rows.
    B2fBands,
    /// The integer z-buffer baseline over the source triangles, full framebuffer.
    Zbuffer,
    /// embedded-3dgfx, a `no_std` 3D engine a firmware engineer would pick: its z-buffer path
    /// (full framebuffer, 16-bit depth buffer, command buffer).
    Gfx3d,
    /// The survey's scanline z-buffer: one row of depth and colour, each row sent when done.
    ScanlineZbuffer,
    /// The z-buffer in bands of rows: the mesh submitted again for each band, with a
    /// band-sized colour and 16-bit depth buffer.
    TiledZbuffer,
}

impl Variant {
    /// Every variant, in table order.
    pub const ALL: [Variant; 12] = [
        Variant::FtbFramebuffer,
        Variant::FtbStream,
        Variant::StreamAa,
        Variant::FtbBands,
        Variant::ScanOrder,
        Variant::ScanAa,
        Variant::B2fFramebuffer,
        Variant::B2fBands,
        Variant::Zbuffer,
        Variant::Gfx3d,
        Variant::ScanlineZbuffer,
        Variant::TiledZbuffer,
    ];

    /// The variant's name, which is also its firmware feature.
    pub const fn name(self) -> &'static str {
        match self {
            Variant::FtbFramebuffer => "ftb-framebuffer",
            Variant::FtbStream => "ftb-stream",
            Variant::StreamAa => "stream-aa",
            Variant::FtbBands => "ftb-bands",
            Variant::ScanOrder => "scan-order",
            Variant::ScanAa => "scan-aa",
            Variant::B2fFramebuffer => "b2f-framebuffer",
            Variant::B2fBands => "b2f-bands",
            Variant::Zbuffer => "zbuffer",
            Variant::Gfx3d => "embedded-3dgfx",
            Variant::ScanlineZbuffer => "scanline-zbuffer",
            Variant::TiledZbuffer => "tiled-zbuffer",
        }
    }

    /// The method it measures (the `method` of a result record).
    pub const fn method(self) -> &'static str {
        match self {
            Variant::FtbFramebuffer
            | Variant::FtbStream
            | Variant::FtbBands
            | Variant::ScanOrder => "peel-front-to-back",
            Variant::StreamAa | Variant::ScanAa => "peel-front-to-back-aa",
            Variant::B2fFramebuffer | Variant::B2fBands => "peel-back-to-front",
            Variant::Zbuffer => "zbuffer-int",
            Variant::Gfx3d => "embedded-3dgfx",
            Variant::ScanlineZbuffer => "scanline-zbuffer",
            Variant::TiledZbuffer => "tiled-zbuffer",
        }
    }

    /// Whether it draws in bands (the config's band rows must then be positive).
    pub const fn banded(self) -> bool {
        matches!(
            self,
            Variant::FtbBands | Variant::B2fBands | Variant::TiledZbuffer
        )
    }

    /// Whether it draws the z-buffer's mesh ([`crate::mesh`]) rather than the `.peel` scene.
    pub const fn draws_mesh(self) -> bool {
        matches!(
            self,
            Variant::Zbuffer | Variant::ScanlineZbuffer | Variant::TiledZbuffer
        )
    }

    /// Whether it needs span memory.
    pub const fn front_to_back(self) -> bool {
        matches!(
            self,
            Variant::FtbFramebuffer | Variant::FtbStream | Variant::StreamAa | Variant::FtbBands
        )
    }

    /// Whether it draws anti-aliased frames (and needs pending-pixel records).
    pub const fn antialiased(self) -> bool {
        matches!(self, Variant::StreamAa | Variant::ScanAa)
    }

    /// Whether it needs scan memory.
    pub const fn scan_order(self) -> bool {
        matches!(self, Variant::ScanOrder | Variant::ScanAa)
    }

    /// The variant of a code, as the block stores it.
    pub const fn from_code(code: u32) -> Option<Variant> {
        match code {
            1 => Some(Variant::FtbFramebuffer),
            2 => Some(Variant::FtbStream),
            3 => Some(Variant::FtbBands),
            4 => Some(Variant::B2fFramebuffer),
            5 => Some(Variant::B2fBands),
            6 => Some(Variant::Zbuffer),
            7 => Some(Variant::Gfx3d),
            8 => Some(Variant::ScanlineZbuffer),
            9 => Some(Variant::TiledZbuffer),
            10 => Some(Variant::ScanOrder),
            11 => Some(Variant::StreamAa),
            12 => Some(Variant::ScanAa),
            _ => None,
        }
    }

    /// Its code in the block.
    pub const fn code(self) -> u32 {
        match self {
            Variant::FtbFramebuffer => 1,
            Variant::FtbStream => 2,
            Variant::FtbBands => 3,
            Variant::B2fFramebuffer => 4,
            Variant::B2fBands => 5,
            Variant::Zbuffer => 6,
            Variant::Gfx3d => 7,
            Variant::ScanlineZbuffer => 8,
            Variant::TiledZbuffer => 9,
            Variant::ScanOrder => 10,
            Variant::StreamAa => 11,
            Variant::ScanAa => 12,
        }
    }
}

/// One orbit camera: `peel render --orbit=azimuth,elevation` at the CLI's default distance.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OrbitAngles {
    /// Degrees around the vertical axis, from `+z` towards `+x`.
    pub azimuth_deg: f64,
    /// Degrees above the horizontal plane.
    pub elevation_deg: f64,
}

/// The decoded block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// The build it is for.
    pub variant: Variant,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Rows per band (banded variants; 0 otherwise).
    pub band_rows: u32,
    /// Span-memory intervals per row (front to back).
    pub spans_per_row: u32,
    /// Bytes of the asset at [`crate::layout::ASSET_ADDR`].
    pub asset_len: u32,
    /// Background colour, `0x00RRGGBB`.
    pub background: u32,
    /// [`WRITE_FRAMES`] or 0.
    pub flags: u32,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Cameras used: the first `camera_count` of `cameras`.
    pub camera_count: u32,
    /// The camera path.
    pub cameras: [OrbitAngles; MAX_CAMERAS],
    /// The scanline z-buffer's active edge list: the most edges active at once over the
    /// camera path (measured on the host).
    pub active_edges: u32,
    /// The scanline z-buffer's points of clipped polygons, the most over the camera path.
    pub clipped_points: u32,
    /// Scan memory nodes (scan order): what the builder measures over an orbit.
    pub scan_nodes: u32,
    /// Pending-pixel records (anti-aliased): what the builder measures over an orbit
    /// (`PENDING_PIXELS`).
    pub pending_pixels: u32,
    /// Composite runs (`peel_runtime::composite`, 12 bytes each) for the transparent surfaces
    /// of a streamed frame: what the runner measures over the orbit on the host; 0 gives the
    /// renderer no composite memory (an opaque scene needs none).
    pub composite_runs: u32,
}

/// Why a block was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigError {
    /// No magic: nothing (or something else) was loaded at the block's address.
    Magic,
    /// Another format version.
    Version(u32),
    /// An unknown variant code.
    Variant(u32),
    /// More cameras than the block holds, or none.
    Cameras(u32),
    /// A zero or too large size, a banded variant without band rows, or a variant without
    /// the span memory, scan memory or pending-pixel records it needs.
    Size,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ConfigError::Magic => write!(f, "no config block (magic PTBC missing)"),
            ConfigError::Version(v) => write!(f, "config version {v}, expected {VERSION}"),
            ConfigError::Variant(v) => write!(f, "unknown variant code {v}"),
            ConfigError::Cameras(n) => write!(f, "{n} cameras: 1..={MAX_CAMERAS} expected"),
            ConfigError::Size => write!(f, "bad image size, band rows or span memory"),
        }
    }
}

impl Config {
    /// The cameras used.
    pub fn cameras(&self) -> &[OrbitAngles] {
        &self.cameras[..(self.camera_count as usize).min(MAX_CAMERAS)]
    }

    /// The background as a colour.
    pub fn background_colour(&self) -> peel_runtime::display::Colour {
        let b = self.background;
        peel_runtime::display::Colour::new((b >> 16) as u8, (b >> 8) as u8, b as u8)
    }

    /// Decode and check a block.
    ///
    /// # Errors
    /// [`ConfigError`] when the bytes are not a block of this version, or its values are
    /// unusable.
    pub fn decode(b: &[u8]) -> Result<Config, ConfigError> {
        if b.get(..4) != Some(&MAGIC[..]) || b.len() < SIZE {
            return Err(ConfigError::Magic);
        }
        let u = |at| u32_at(b, at).unwrap_or(0);
        let f = |at| f64_at(b, at).unwrap_or(0.0);
        if u(4) != VERSION {
            return Err(ConfigError::Version(u(4)));
        }
        let variant = Variant::from_code(u(8)).ok_or(ConfigError::Variant(u(8)))?;
        let camera_count = u(48);
        if camera_count == 0 || camera_count as usize > MAX_CAMERAS {
            return Err(ConfigError::Cameras(camera_count));
        }
        let mut cameras = [OrbitAngles::default(); MAX_CAMERAS];
        for (k, c) in cameras.iter_mut().enumerate() {
            let at = 56 + 16 * k;
            *c = OrbitAngles {
                azimuth_deg: f(at),
                elevation_deg: f(at + 8),
            };
        }
        let config = Config {
            variant,
            width: u(12),
            height: u(16),
            band_rows: u(20),
            spans_per_row: u(24),
            asset_len: u(28),
            background: u(32),
            flags: u(36),
            fov_y_deg: f(40),
            camera_count,
            cameras,
            active_edges: u(LISTS),
            clipped_points: u(LISTS + 4),
            scan_nodes: u(LISTS + 8),
            pending_pixels: u(LISTS + 12),
            composite_runs: u(LISTS + 16),
        };
        let (w, h) = (config.width, config.height);
        let sized = (1..=4096).contains(&w) && (1..=4096).contains(&h);
        let bands = !variant.banded() || (1..=h).contains(&config.band_rows);
        let spans = (!variant.front_to_back() || config.spans_per_row > 0)
            && (!variant.scan_order() || config.scan_nodes > 0)
            && (!variant.antialiased() || config.pending_pixels > 0);
        if !(sized && bands && spans) || config.asset_len > crate::layout::MAX_ASSET {
            return Err(ConfigError::Size);
        }
        Ok(config)
    }

    /// The block's bytes.
    #[cfg(any(feature = "std", test))]
    pub fn encode(&self) -> [u8; SIZE] {
        let mut b = [0u8; SIZE];
        b[..4].copy_from_slice(&MAGIC);
        let mut put = |at: usize, v: &[u8]| b[at..at + v.len()].copy_from_slice(v);
        put(4, &VERSION.to_le_bytes());
        put(8, &self.variant.code().to_le_bytes());
        put(12, &self.width.to_le_bytes());
        put(16, &self.height.to_le_bytes());
        put(20, &self.band_rows.to_le_bytes());
        put(24, &self.spans_per_row.to_le_bytes());
        put(28, &self.asset_len.to_le_bytes());
        put(32, &self.background.to_le_bytes());
        put(36, &self.flags.to_le_bytes());
        put(40, &self.fov_y_deg.to_le_bytes());
        put(48, &self.camera_count.to_le_bytes());
        for (k, c) in self.cameras.iter().enumerate() {
            put(56 + 16 * k, &c.azimuth_deg.to_le_bytes());
            put(64 + 16 * k, &c.elevation_deg.to_le_bytes());
        }
        put(LISTS, &self.active_edges.to_le_bytes());
        put(LISTS + 4, &self.clipped_points.to_le_bytes());
        put(LISTS + 8, &self.scan_nodes.to_le_bytes());
        put(LISTS + 12, &self.pending_pixels.to_le_bytes());
        put(LISTS + 16, &self.composite_runs.to_le_bytes());
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Config {
        let mut cameras = [OrbitAngles::default(); MAX_CAMERAS];
        cameras[1] = OrbitAngles {
            azimuth_deg: 45.0,
            elevation_deg: 20.0,
        };
        Config {
            variant: Variant::FtbBands,
            width: 320,
            height: 240,
            band_rows: 16,
            spans_per_row: 16,
            asset_len: 9498,
            background: 0x18_1a20,
            flags: WRITE_FRAMES,
            fov_y_deg: 60.0,
            camera_count: 2,
            cameras,
            active_edges: 300,
            clipped_points: 17,
            scan_nodes: 2000,
            pending_pixels: 1714,
            composite_runs: 300,
        }
    }

    #[test]
    fn round_trip() {
        let c = sample();
        assert_eq!(Config::decode(&c.encode()), Ok(c));
        assert_eq!(c.cameras().len(), 2);
        assert_eq!(
            c.background_colour(),
            peel_runtime::display::Colour::new(0x18, 0x1a, 0x20)
        );
    }

    #[test]
    fn refusals() {
        let good = sample().encode();
        assert_eq!(Config::decode(&good[..SIZE - 1]), Err(ConfigError::Magic));
        assert_eq!(Config::decode(&[0u8; SIZE]), Err(ConfigError::Magic));
        let mut b = good;
        b[4] = 9;
        assert_eq!(Config::decode(&b), Err(ConfigError::Version(9)));
        let mut b = good;
        b[8] = 99;
        assert_eq!(Config::decode(&b), Err(ConfigError::Variant(99)));
        let mut c = sample();
        c.camera_count = 17;
        assert_eq!(Config::decode(&c.encode()), Err(ConfigError::Cameras(17)));
        let mut c = sample();
        c.band_rows = 0;
        assert_eq!(Config::decode(&c.encode()), Err(ConfigError::Size));
        // Bands are only required of banded variants.
        c.variant = Variant::FtbFramebuffer;
        assert!(Config::decode(&c.encode()).is_ok());
        c.spans_per_row = 0;
        assert_eq!(Config::decode(&c.encode()), Err(ConfigError::Size));
        // Pending records are only required of anti-aliased variants.
        let mut c = sample();
        c.variant = Variant::StreamAa;
        assert!(Config::decode(&c.encode()).is_ok());
        c.pending_pixels = 0;
        assert_eq!(Config::decode(&c.encode()), Err(ConfigError::Size));
    }

    #[test]
    fn codes_and_names() {
        for v in Variant::ALL {
            assert_eq!(Variant::from_code(v.code()), Some(v));
        }
        assert_eq!(Variant::from_code(0), None);
        assert_eq!(Variant::FtbStream.method(), "peel-front-to-back");
        assert_eq!(Variant::B2fBands.method(), "peel-back-to-front");
        assert_eq!(Variant::StreamAa.method(), "peel-front-to-back-aa");
        assert!(Variant::StreamAa.front_to_back() && Variant::StreamAa.antialiased());
        assert_eq!(Variant::Zbuffer.name(), "zbuffer");
    }
}
