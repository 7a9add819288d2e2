//! Texture check: a rendered frame's textured pixels against the exact texel under each pixel
//! centre ([`texels`](super::reference::texels())), on the reference's robust pixels. There a
//! correct renderer shows the texel itself, or one of the 8 around it: the file's 16-bit
//! coordinates, the compiler's quantisation and the runtime's 16-pixel steps may move a pixel
//! near a texel boundary to the other side, so those are counted apart from the wrong ones.
//! Colours tell texels apart only where neighbours differ: under
//! [`numbered_texture`](super::scenes::numbered_texture) every texel has its own colour.

use super::reference::{TexelHit, Texels};
use crate::load::Mesh;

/// How many offenders a check keeps, the worst first.
pub const WORST: usize = 8;

/// How far from the right texel (in texels, on either axis) an offender's colour is looked for.
pub const SEARCH: u32 = 4;

/// A pixel that does not show its texel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offender {
    /// Column of the pixel.
    pub x: u32,
    /// Row of the pixel.
    pub y: u32,
    /// The colour the frame shows there.
    pub shows: [u8; 3],
    /// The texel under the pixel centre.
    pub texel: TexelHit,
    /// Its colour ([`TexelHit::colour`]).
    pub wants: [u8; 3],
    /// How far the nearest texel of the colour shown is from `texel`: the larger of the column
    /// and row steps, repeated or clamped as the texture is; `None` beyond [`SEARCH`].
    pub away: Option<u32>,
}

impl std::fmt::Display for Offender {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let hex = |c: [u8; 3]| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
        let t = &self.texel;
        write!(
            f,
            "({}, {}) shows {} for texel ({}, {}) of texture {} on triangle {} ({}): ",
            self.x,
            self.y,
            hex(self.shows),
            t.column,
            t.row,
            t.texture,
            t.id,
            hex(self.wants)
        )?;
        match self.away {
            Some(1) => write!(f, "a neighbour's colour"),
            Some(k) => write!(f, "the colour of a texel {k} away"),
            None => write!(f, "no texel within {SEARCH} has that colour"),
        }
    }
}

/// How a frame's robust textured pixels compare with their texels.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TextureCheck {
    /// Robust pixels whose triangle is textured.
    pub pixels: usize,
    /// Those showing their texel's colour.
    pub exact: usize,
    /// Those showing, instead, the colour of one of the 8 texels around it.
    pub adjacent: usize,
    /// The others.
    pub wrong: usize,
    /// Up to [`WORST`] of the pixels not exact, the worst first: wrong before adjacent, then
    /// the farther texel, then the larger colour difference, then by position.
    pub worst: Vec<Offender>,
}

impl TextureCheck {
    /// The counts and the worst offenders, for a test's message.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "{} robust textured pixels: {} exact, {} a neighbouring texel, {} wrong",
            self.pixels, self.exact, self.adjacent, self.wrong
        );
        for o in &self.worst {
            s.push_str(&format!("\n  {o}"));
        }
        s
    }
}

/// The colour of an XRGB8888 pixel (`0x00RRGGBB`, as [`super::raster::Frame::pixels`]).
pub fn xrgb(pixel: u32) -> [u8; 3] {
    [(pixel >> 16) as u8, (pixel >> 8) as u8, pixel as u8]
}

/// Check `frame` (XRGB8888 pixels, row-major, as [`super::raster::Frame::pixels`]) against
/// `reference`, the [`texels`](super::reference::texels()) of `mesh` for the same shot, unlit.
/// Panics if the frame's size is not the reference's.
pub fn check(reference: &Texels, mesh: &Mesh, frame: &[u32]) -> TextureCheck {
    let width = reference.width as usize;
    assert_eq!(
        frame.len(),
        width * reference.height as usize,
        "the frame and the reference differ in size"
    );
    let mut out = TextureCheck::default();
    let mut offenders = Vec::new();
    for (k, &pixel) in frame.iter().enumerate() {
        let Some(texel) = reference.texels[k].filter(|_| reference.robust[k]) else {
            continue;
        };
        out.pixels += 1;
        let (shows, wants) = (xrgb(pixel), texel.colour(mesh));
        if shows == wants {
            out.exact += 1;
            continue;
        }
        let away = distance(mesh, texel, shows);
        if away == Some(1) {
            out.adjacent += 1;
        } else {
            out.wrong += 1;
        }
        offenders.push(Offender {
            x: (k % width) as u32,
            y: (k / width) as u32,
            shows,
            texel,
            wants,
            away,
        });
    }
    let difference = |o: &Offender| (0..3).map(|c| o.shows[c].abs_diff(o.wants[c])).max();
    offenders.sort_by_key(|o| {
        (
            std::cmp::Reverse((o.away.unwrap_or(u32::MAX), difference(o))),
            (o.y, o.x),
        )
    });
    offenders.truncate(WORST);
    out.worst = offenders;
    out
}

/// The smallest step (the larger of the column and row steps) from `texel` to a texel whose
/// colour is `shows`, up to [`SEARCH`].
fn distance(mesh: &Mesh, texel: TexelHit, shows: [u8; 3]) -> Option<u32> {
    let texture = &mesh.textures[texel.texture as usize];
    let s = i64::from(SEARCH);
    (1..=s)
        .find(|&r| {
            (-r..=r).any(|dc| {
                (-r..=r).any(|dr| {
                    (dc.abs() == r || dr.abs() == r)
                        && texel.step(texture, dc, dr).colour(mesh) == shows
                })
            })
        })
        .map(|r| r as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::reference::texels;
    use crate::tools::scenes::{numbered_texture, textured_floor};
    use crate::tools::shot::Shot;
    use glam::DVec3;

    fn pack(c: [u8; 3]) -> u32 {
        u32::from(c[0]) << 16 | u32::from(c[1]) << 8 | u32::from(c[2])
    }

    /// A floor under a 16 x 16 numbered texture seen from above (texels of 3 to 4 pixels), a
    /// colour of its own (the check multiplies by it), its reference and the frame of its
    /// exact colours.
    fn scene() -> (Mesh, Texels, Vec<u32>) {
        let mut mesh = textured_floor(1.0, 1.0);
        mesh.textures[0] = numbered_texture(4, 4);
        for t in &mut mesh.triangles {
            t.colour = [250, 240, 230];
        }
        let s = Shot::new(DVec3::new(0.0, 2.0, 0.5), DVec3::ZERO, 64, 64);
        let seen = texels(&mesh, &s, 0.01);
        let frame = (seen.colours(&mesh).into_iter())
            .map(|c| c.map_or(0, pack))
            .collect();
        (mesh, seen, frame)
    }

    /// The `n`th robust textured pixel.
    fn robust(seen: &Texels, n: usize) -> (usize, TexelHit) {
        (0..seen.texels.len())
            .filter_map(|k| Some((k, seen.texels[k].filter(|_| seen.robust[k])?)))
            .nth(n)
            .unwrap()
    }

    #[test]
    fn a_correct_frame_is_exact() {
        let (mesh, seen, frame) = scene();
        let c = check(&seen, &mesh, &frame);
        assert!(c.pixels > 1500, "{}", c.summary());
        assert_eq!((c.exact, c.adjacent, c.wrong), (c.pixels, 0, 0));
        assert!(c.worst.is_empty());
        // Pixels the check leaves out: the background, and those not robust.
        let mut other = frame.clone();
        let background = seen.ids.iter().position(|&id| id == 0).unwrap();
        let shaky = (0..frame.len()).find(|&k| seen.ids[k] > 0 && !seen.robust[k]);
        for k in [Some(background), shaky].into_iter().flatten() {
            other[k] = 0x123456;
        }
        assert_eq!(check(&seen, &mesh, &other), c);
    }

    /// A pixel one texel off is adjacent; two texels off, or a colour of no texel near, wrong;
    /// the worst come first, with their places.
    #[test]
    fn pixels_off_by_one_texel_are_adjacent_and_farther_ones_wrong() {
        let (mesh, seen, mut frame) = scene();
        let texture = &mesh.textures[0];
        let w = seen.width as usize;
        let (one, t1) = robust(&seen, 100);
        frame[one] = pack(t1.step(texture, 1, -1).colour(&mesh));
        let c = check(&seen, &mesh, &frame);
        assert_eq!((c.exact, c.adjacent, c.wrong), (c.pixels - 1, 1, 0));
        assert_eq!(c.worst.len(), 1);
        let o = c.worst[0];
        assert_eq!(
            ((o.x as usize, o.y as usize), o.away),
            ((one % w, one / w), Some(1))
        );
        assert_eq!((o.texel, o.wants), (t1, t1.colour(&mesh)));
        let (two, t2) = robust(&seen, 900);
        frame[two] = pack(t2.step(texture, 0, 2).colour(&mesh));
        let c = check(&seen, &mesh, &frame);
        assert_eq!((c.exact, c.adjacent, c.wrong), (c.pixels - 2, 1, 1));
        let at = |o: &Offender| (o.y as usize * w + o.x as usize, o.away);
        assert_eq!(
            c.worst.iter().map(at).collect::<Vec<_>>(),
            [(two, Some(2)), (one, Some(1))]
        );
        let (far, _) = robust(&seen, 500);
        frame[far] = pack([1, 2, 3]);
        let c = check(&seen, &mesh, &frame);
        assert_eq!((c.exact, c.adjacent, c.wrong), (c.pixels - 3, 1, 2));
        assert_eq!(c.worst.iter().map(at).collect::<Vec<_>>()[0], (far, None));
        let summary = c.summary();
        let place = format!("({}, {}) shows #010203", far % w, far / w);
        assert!(
            summary.contains("1 a neighbouring texel, 2 wrong"),
            "{summary}"
        );
        assert!(summary.contains(&place), "{summary}");
    }

    #[test]
    #[should_panic(expected = "differ in size")]
    fn a_frame_of_another_size_is_refused() {
        let (mesh, seen, frame) = scene();
        check(&seen, &mesh, &frame[1..]);
    }
}
