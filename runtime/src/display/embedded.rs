//! Adapter from [`SpanSink`] to an `embedded_graphics_core` [`DrawTarget`] (feature
//! `embedded-graphics`). Each span is one `fill_solid` call, which display drivers turn into a
//! single window-and-burst transfer, instead of one call per pixel.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

use super::framebuffer::{Framebuffer, Gray8, PixelFormat, Rgb565, Xrgb8888};
use super::{Colour, RowShade, SpanSink};

/// Forwards spans to a [`DrawTarget`] whose colour converts from `Rgb888` (all of
/// embedded-graphics' RGB and grey types do). `SpanSink::span` cannot fail, so the first draw
/// error is kept, later spans are skipped, and [`Self::finish`] reports it.
#[derive(Debug)]
pub struct DrawTargetSink<'a, D: DrawTarget> {
    target: &'a mut D,
    error: Option<D::Error>,
    /// The last colour converted, to convert once per polygon rather than once per span.
    last: Option<(Colour, D::Color)>,
    /// Shaded spans dithered to RGB565 ([`super::dither_rgb565`]).
    dither: bool,
}

impl<'a, D> DrawTargetSink<'a, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    /// A sink drawing into `target`. It streams spans straight to a display, so frames drawn
    /// into it are front to back or refused ([`SpanSink::write_once`]); without the runtime's
    /// `front-to-back` feature it does not compile (the error names the feature).
    pub fn new(target: &'a mut D) -> Self {
        #[cfg(not(feature = "front-to-back"))]
        let () = NeedsFrontToBack::<D>::CHECK;
        DrawTargetSink {
            target,
            error: None,
            last: None,
            dither: is_rgb565::<D::Color>(),
        }
    }

    /// Whether shaded spans are dithered: on by default for a target whose colour has 5, 6
    /// and 5 bits (as its conversion from `Rgb888` shows), so that a gradient does not band;
    /// off for any other. Flat spans are never dithered.
    pub fn set_dithering(&mut self, on: bool) {
        self.dither = on;
    }

    /// Whether shaded spans are dithered ([`Self::set_dithering`]).
    pub fn dithering(&self) -> bool {
        self.dither
    }

    /// The first error the target returned, if any.
    ///
    /// # Errors
    /// That error; the spans after it were not drawn.
    pub fn finish(self) -> Result<(), D::Error> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// Whether `C` keeps 5 bits of red and blue and 6 of green: the 8-bit levels that round to
/// 0 and to the first step at those depths, and at no other, tell them apart from its
/// conversion alone.
fn is_rgb565<C: From<Rgb888> + PartialEq>() -> bool {
    let c = |r, g, b| C::from(Rgb888::new(r, g, b));
    let black = c(0, 0, 0);
    // embedded-graphics rounds: 8-bit 4 and 5 are 5-bit 0 and 1, 8-bit 2 and 3 6-bit 0 and 1.
    c(4, 0, 0) == black
        && c(5, 0, 0) != black
        && c(0, 2, 0) == black
        && c(0, 3, 0) != black
        && c(0, 0, 4) == black
        && c(0, 0, 5) != black
}

/// An RGB565 value as the `Rgb888` whose conversion back gives it: each channel's bits
/// repeated into the low ones (the nearest 8-bit level to the 5- or 6-bit one).
fn expanded(raw: u16) -> Rgb888 {
    let (r, g, b) = (
        (raw >> 11) as u8,
        ((raw >> 5) & 0x3f) as u8,
        (raw & 0x1f) as u8,
    );
    Rgb888::new(r << 3 | r >> 2, g << 2 | g >> 4, b << 3 | b >> 2)
}

/// The compile error of [`DrawTargetSink::new`] without the `front-to-back` feature.
#[cfg(not(feature = "front-to-back"))]
struct NeedsFrontToBack<D>(core::marker::PhantomData<D>);

#[cfg(not(feature = "front-to-back"))]
impl<D> NeedsFrontToBack<D> {
    const CHECK: () = panic!(
        "DrawTargetSink streams spans to a display, which needs frames drawn front to back: \
         enable peel-runtime's `front-to-back` feature (or draw into a Framebuffer band)"
    );
}

impl<D> SpanSink for DrawTargetSink<'_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    fn write_once(&self) -> bool {
        true
    }

    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        if self.error.is_some() || x_start >= x_end {
            return;
        }
        let (Ok(x), Ok(y)) = (i32::try_from(x_start), i32::try_from(y)) else {
            return;
        };
        let c = match self.last {
            Some((k, c)) if k == colour => c,
            _ => {
                let c = D::Color::from(Rgb888::new(colour.r, colour.g, colour.b));
                self.last = Some((colour, c));
                c
            }
        };
        let area = Rectangle::new(Point::new(x, y), Size::new(x_end - x_start, 1));
        if let Err(e) = self.target.fill_solid(&area, c) {
            self.error = Some(e);
        }
    }

    /// One `fill_contiguous` call per span, its pixels' colours computed as the driver takes
    /// them: one window and one burst, as a flat span's `fill_solid`.
    fn shaded_span(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) {
        if self.error.is_some() || x_start >= x_end {
            return;
        }
        let (Ok(x), Ok(y)) = (i32::try_from(x_start), i32::try_from(y)) else {
            return;
        };
        let area = Rectangle::new(Point::new(x, y), Size::new(x_end - x_start, 1));
        let colours = shade.colours(x_start).take((x_end - x_start) as usize);
        let result = if self.dither {
            let thresholds = super::dither::row_thresholds(y as u32);
            let dithered = (x_start..).zip(colours).map(|(x, c)| {
                let raw = super::dither::dithered(c, thresholds[(x & 3) as usize]);
                D::Color::from(expanded(raw))
            });
            self.target.fill_contiguous(&area, dithered)
        } else {
            let plain = colours.map(|c| D::Color::from(Rgb888::new(c.r, c.g, c.b)));
            self.target.fill_contiguous(&area, plain)
        };
        if let Err(e) = result {
            self.error = Some(e);
        }
    }
}

/// A [`PixelFormat`] whose stored pixels are an embedded-graphics colour as they are: a
/// framebuffer of it goes to a display without conversion ([`Framebuffer::draw_to`]).
pub trait DisplayFormat: PixelFormat {
    /// The embedded-graphics colour.
    type Color: embedded_graphics_core::pixelcolor::PixelColor;
    /// A stored pixel as that colour.
    fn color(raw: Self::Raw) -> Self::Color;
}

impl DisplayFormat for Rgb565 {
    type Color = embedded_graphics_core::pixelcolor::Rgb565;
    #[inline]
    fn color(raw: u16) -> Self::Color {
        embedded_graphics_core::pixelcolor::raw::RawU16::new(raw).into()
    }
}

impl DisplayFormat for Gray8 {
    type Color = embedded_graphics_core::pixelcolor::Gray8;
    #[inline]
    fn color(raw: u8) -> Self::Color {
        embedded_graphics_core::pixelcolor::Gray8::new(raw)
    }
}

impl DisplayFormat for Xrgb8888 {
    type Color = Rgb888;
    #[inline]
    fn color(raw: u32) -> Self::Color {
        Rgb888::new((raw >> 16) as u8, (raw >> 8) as u8, raw as u8)
    }
}

impl<P: DisplayFormat> Framebuffer<'_, P> {
    /// Send the image, or the band, to `display` at its frame rows: one `fill_contiguous`,
    /// which display drivers turn into one address window and one burst.
    ///
    /// # Errors
    /// The display's.
    pub fn draw_to<D: DrawTarget<Color = P::Color>>(
        &self,
        display: &mut D,
    ) -> Result<(), D::Error> {
        let Ok(y) = i32::try_from(self.rows().start) else {
            return Ok(());
        };
        let stride = self.stride();
        let (w, h) = (self.width(), self.height());
        let area = Rectangle::new(Point::new(0, y), Size::new(w, h));
        let rows = self.as_slice().chunks(stride.max(1)).take(h as usize);
        let pixels = rows.flat_map(|row| row.iter().take(w as usize).map(|&raw| P::color(raw)));
        display.fill_contiguous(&area, pixels)
    }
}

// `DrawTargetSink` does not compile without `front-to-back` (its purpose).
#[cfg(all(test, feature = "front-to-back"))]
mod tests {
    use super::*;
    use crate::fill::{fill_polygon, FixedPoint};
    use embedded_graphics_core::geometry::{Dimensions, OriginDimensions};
    use embedded_graphics_core::pixelcolor::{Gray8, PixelColor, Rgb565};
    use embedded_graphics_core::Pixel;

    /// Counts calls; keeps what was filled in a small grid.
    struct Counting<C> {
        fills: usize,
        contiguous: usize,
        pixel_calls: usize,
        grid: [[Option<C>; 8]; 8],
        fail_after: usize,
    }

    impl<C: PixelColor> OriginDimensions for Counting<C> {
        fn size(&self) -> Size {
            Size::new(8, 8)
        }
    }

    impl<C: PixelColor> DrawTarget for Counting<C> {
        type Color = C;
        type Error = u8;

        fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, pixels: I) -> Result<(), u8> {
            self.pixel_calls += pixels.into_iter().count();
            Ok(())
        }

        fn fill_solid(&mut self, area: &Rectangle, color: C) -> Result<(), u8> {
            if self.fills == self.fail_after {
                return Err(7);
            }
            self.fills += 1;
            assert_eq!(area.size.height, 1);
            let area = area.intersection(&self.bounding_box());
            let (x0, y) = (area.top_left.x as usize, area.top_left.y as usize);
            for cell in &mut self.grid[y][x0..x0 + area.size.width as usize] {
                assert!(cell.is_none());
                *cell = Some(color);
            }
            Ok(())
        }

        fn fill_contiguous<I: IntoIterator<Item = C>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), u8> {
            self.contiguous += 1;
            assert_eq!(area.size.height, 1);
            let (x0, y) = (area.top_left.x as usize, area.top_left.y as usize);
            let cells = &mut self.grid[y][x0..x0 + area.size.width as usize];
            let mut colors = colors.into_iter();
            for cell in cells {
                assert!(cell.is_none());
                *cell = colors.next();
            }
            assert!(colors.next().is_none(), "as many colours as pixels");
            Ok(())
        }
    }

    /// RGB565 targets are told apart by their conversion, and dither shaded spans by default:
    /// each pixel `dither_rgb565` of its colour, as the RGB565 framebuffer stores it; the
    /// switch turns it off; other targets get the plain colours.
    #[test]
    fn rgb565_targets_dither_shaded_spans() {
        use embedded_graphics_core::pixelcolor::raw::{RawData, RawU16};
        use embedded_graphics_core::pixelcolor::{Bgr565, Rgb555};
        assert!(is_rgb565::<Rgb565>() && is_rgb565::<Bgr565>());
        assert!(!is_rgb565::<Rgb888>() && !is_rgb565::<Rgb555>() && !is_rgb565::<Gray8>());
        for raw in 0..=u16::MAX {
            let back = RawU16::from(Rgb565::from(expanded(raw))).into_inner();
            assert_eq!(back, raw);
        }
        let shade = RowShade {
            base: 90 << 21,
            step: (3 << 21) / 5,
            colour: Colour::new(250, 170, 60),
        };
        for dither in [true, false] {
            let mut t = counting::<Rgb565>(usize::MAX);
            let mut sink = DrawTargetSink::new(&mut t);
            assert!(sink.dithering());
            sink.set_dithering(dither);
            sink.shaded_span(3, 0, 8, &shade);
            assert_eq!(sink.finish(), Ok(()));
            for x in 0..8u32 {
                let c = shade.at(x);
                let raw = if dither {
                    crate::display::dither_rgb565(x, 3, c)
                } else {
                    RawU16::from(Rgb565::from(Rgb888::new(c.r, c.g, c.b))).into_inner()
                };
                assert_eq!(t.grid[3][x as usize], Some(Rgb565::from(RawU16::new(raw))));
            }
        }
        let mut t = counting::<Rgb888>(usize::MAX);
        assert!(!DrawTargetSink::new(&mut t).dithering());
    }

    /// A shaded span is one `fill_contiguous` call with each pixel's colour.
    #[test]
    fn one_fill_contiguous_per_shaded_span() {
        let mut t = counting::<Rgb888>(usize::MAX);
        let mut sink = DrawTargetSink::new(&mut t);
        let shade = RowShade {
            base: 10 << 21,
            step: 20 << 21,
            colour: Colour::new(255, 200, 100),
        };
        sink.shaded_span(2, 1, 7, &shade);
        assert_eq!(sink.finish(), Ok(()));
        assert_eq!((t.fills, t.contiguous, t.pixel_calls), (0, 1, 0));
        for x in 0..8u32 {
            let expected = (1..7).contains(&x).then(|| {
                let c = shade.at(x);
                Rgb888::new(c.r, c.g, c.b)
            });
            assert_eq!(t.grid[2][x as usize], expected, "pixel {x}");
        }
        assert_ne!(t.grid[2][1], t.grid[2][6]);
    }

    fn counting<C: PixelColor>(fail_after: usize) -> Counting<C> {
        Counting {
            fills: 0,
            contiguous: 0,
            pixel_calls: 0,
            grid: [[None; 8]; 8],
            fail_after,
        }
    }

    #[test]
    fn one_fill_solid_per_span() {
        let mut t = counting::<Rgb565>(usize::MAX);
        let mut sink = DrawTargetSink::new(&mut t);
        // Square (1,1)-(6,5) at SUB = 0: 4 rows of 5 pixels.
        let square = [(1, 1), (6, 1), (6, 5), (1, 5)].map(|(x, y)| FixedPoint::new(x, y));
        let n = fill_polygon::<0, _>(&square, 8, 8, Colour::new(255, 0, 0), &mut sink).unwrap();
        assert_eq!(sink.finish(), Ok(()));
        assert_eq!((n, t.fills, t.pixel_calls), (20, 4, 0));
        assert_eq!(t.grid[1][1], Some(Rgb565::new(31, 0, 0)));
        assert_eq!(t.grid[4][5], Some(Rgb565::new(31, 0, 0)));
        assert_eq!(t.grid[5][5], None);
        assert_eq!(t.grid[1][6], None);
    }

    #[test]
    fn colours_match_the_framebuffer_encodings() {
        let mut t = counting::<Gray8>(usize::MAX);
        let c = Colour::new(10, 200, 30);
        let mut sink = DrawTargetSink::new(&mut t);
        sink.span(0, 0, 1, c);
        sink.finish().unwrap();
        assert_eq!(t.grid[0][0], Some(Gray8::new(c.luma())));
        for v in 0..=255u8 {
            let c = Colour::new(v, v.wrapping_mul(7), 255 - v);
            let eg = Rgb565::from(Rgb888::new(c.r, c.g, c.b));
            let raw = embedded_graphics_core::pixelcolor::IntoStorage::into_storage(eg);
            assert_eq!(raw, c.to_rgb565(), "{c:?}");
        }
    }

    /// Keeps the last `fill_contiguous` call.
    #[derive(Default)]
    struct Panel {
        area: Option<Rectangle>,
        pixels: [u16; 12],
    }

    impl OriginDimensions for Panel {
        fn size(&self) -> Size {
            Size::new(3, 8)
        }
    }

    impl DrawTarget for Panel {
        type Color = Rgb565;
        type Error = core::convert::Infallible;

        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            _: I,
        ) -> Result<(), Self::Error> {
            panic!("a band goes as one fill_contiguous");
        }

        fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Self::Error>
        where
            I: IntoIterator<Item = Rgb565>,
        {
            self.area = Some(*area);
            for (slot, c) in self.pixels.iter_mut().zip(colors) {
                *slot = embedded_graphics_core::pixelcolor::IntoStorage::into_storage(c);
            }
            Ok(())
        }
    }

    #[test]
    fn a_band_goes_to_its_rows_in_one_call() {
        let mut buf = [0u16; 6];
        let mut band = crate::display::Rgb565Framebuffer::band(&mut buf, 3, 5..7).unwrap();
        band.span(5, 1, 3, Colour::new(255, 0, 0));
        band.span(6, 0, 1, Colour::new(0, 0, 255));
        let mut panel = Panel::default();
        band.draw_to(&mut panel).unwrap();
        assert_eq!(
            panel.area,
            Some(Rectangle::new(Point::new(0, 5), Size::new(3, 2)))
        );
        assert_eq!(panel.pixels[..6], [0, 0xf800, 0xf800, 0x001f, 0, 0]);
    }

    #[test]
    fn first_error_is_kept_and_stops_drawing() {
        let mut t = counting::<Rgb565>(1);
        let mut sink = DrawTargetSink::new(&mut t);
        sink.span(0, 0, 2, Colour::default());
        sink.span(1, 0, 2, Colour::default());
        sink.span(2, 0, 2, Colour::default());
        assert_eq!(sink.finish(), Err(7));
        assert_eq!(t.fills, 1);
    }
}
