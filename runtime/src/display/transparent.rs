//! [`Transparent`]: a transparent polygon's paint, its one colour and its opacity, and
//! [`screen_door`], the pattern a sink that cannot read its pixels back draws it with.
//!
//! Back to front, a transparent span goes to [`SpanSink::transparent_span`]: the framebuffers
//! blend it "over" the pixels already there, exactly; any other sink draws its screen door
//! (the pixels whose [`BAYER_4X4`] threshold is below the opacity). Front to back, the frame's
//! composite memory keeps it instead ([`crate::composite`]), and no sink sees it.

use super::{Colour, Paint, SpanPaint, SpanSink, BAYER_4X4};

/// A transparent span's paint: `colour` at `opacity` (of 255; 255 is opaque).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transparent {
    /// The colour of the side seen.
    pub colour: Colour,
    /// Its opacity, `alpha = opacity / 255`.
    pub opacity: u8,
}

impl SpanPaint for Transparent {
    /// Its colour: a store that keeps colours (scan memory) never takes a transparent span
    /// (the renderer refuses such frames).
    #[inline]
    fn kind(&self) -> Paint<'_> {
        Paint::Colour(self.colour)
    }

    #[inline]
    fn paint<S: SpanSink + ?Sized>(&self, sink: &mut S, y: u32, x_start: u32, x_end: u32) {
        sink.transparent_span(y, x_start, x_end, self.colour, self.opacity);
    }

    #[inline]
    fn runs(&self, x_start: u32, x_end: u32, mut run: impl FnMut(u32, u32, Colour)) {
        if x_start < x_end {
            run(x_start, x_end, self.colour);
        }
    }
}

/// Whether pixel `(x, y)` shows a surface of `opacity` in its screen door: its
/// [`BAYER_4X4`] entry `t` has `16 t + 8 < opacity`, so a 4 x 4 block shows it at
/// `round(16 opacity / 255)` of its 16 pixels, near `opacity / 255` of them.
#[inline]
pub fn screen_door_shows(x: u32, y: u32, opacity: u8) -> bool {
    let t = BAYER_4X4[(y & 3) as usize][(x & 3) as usize];
    u32::from(t) * 16 + 8 < u32::from(opacity)
}

/// The runs of pixels of `x_start .. x_end` on row `y` that a surface of `opacity` shows in
/// its screen door ([`screen_door_shows`]), left to right, as `run(start, end)`.
pub fn screen_door(y: u32, x_start: u32, x_end: u32, opacity: u8, mut run: impl FnMut(u32, u32)) {
    let mut start = None;
    for x in x_start..x_end {
        match (screen_door_shows(x, y, opacity), start) {
            (true, None) => start = Some(x),
            (false, Some(s)) => {
                run(s, x);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        run(s, x_end);
    }
}

/// `colour` at `opacity` over `below`, per channel `round((a c + (255 - a) b) / 255)`.
#[inline]
pub const fn over(colour: Colour, opacity: u8, below: Colour) -> Colour {
    Colour::new(
        mix(colour.r, opacity, below.r),
        mix(colour.g, opacity, below.g),
        mix(colour.b, opacity, below.b),
    )
}

/// One channel of [`over`].
const fn mix(c: u8, opacity: u8, below: u8) -> u8 {
    let a = opacity as u32;
    ((a * c as u32 + (255 - a) * below as u32 + 127) / 255) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_screen_door_shows_about_the_opacity() {
        for opacity in [0u8, 1, 64, 128, 200, 254, 255] {
            let mut shown = 0;
            for y in 0..4 {
                screen_door(y, 0, 4, opacity, |a, b| shown += b - a);
            }
            let expected = (16 * u32::from(opacity) + 127) / 255;
            assert!(shown.abs_diff(expected) <= 1, "{opacity}: {shown}");
        }
        let mut all = 0;
        screen_door(1, 3, 11, 255, |a, b| all += b - a);
        assert_eq!(all, 8);
    }

    #[test]
    fn over_blends_and_rounds() {
        let red = Colour::new(255, 0, 0);
        let blue = Colour::new(0, 0, 255);
        assert_eq!(over(red, 255, blue), red);
        assert_eq!(over(red, 0, blue), blue);
        assert_eq!(over(red, 128, blue), Colour::new(128, 0, 127));
    }
}
