//! [`RowTexture`]: one row of a textured polygon, what a sink receives with a textured span
//! ([`SpanSink::textured_span`](super::SpanSink::textured_span)). The fill's
//! [`TextureMap`](crate::fill::texture::TextureMap) makes one per row.
//!
//! # Perspective
//! On a polygon's plane, `1/z`, `s/z` and `t/z` are affine on the screen: the row holds them
//! at pixel 0 (`w`, `s`, `t`, scaled so that `w` is at most `2^30` on the polygon and `s`,
//! `t` at most `2^30` in magnitude) and their steps a pixel, wrapping `i32`s as a
//! [`RowShade`]'s are. A pixel's coordinates are the quotients `s / w` and `t / w` (times
//! `2^shift`), exact at the ends of runs, one `f32` division each (`1/w`, then a multiply a
//! coordinate, rounded alike on every core), and stepped in integers in between, as Quake's
//! span drawer steps its texture coordinates. A run is the polygon's whole span on the row
//! where its chord strays from the perspective by at most 1/16 pixel or 1/16 texel; else
//! runs of [`RUN`] pixels aligned to the screen's columns (`x = 16 k`, their ends taken
//! inside the span, whose pixels they are), shorter where a block's chord strays more, aligned
//! likewise, down to single pixels. A pixel's texel therefore depends on its column and on the
//! polygon's span on its row, never on the piece of the span a sink is given.

use super::{shaded, Colour, RowShade};
use crate::read::layout::texture_flags;
use crate::read::rgb565_at;
use crate::read::Texture;

/// Pixels between two exact divisions: the run's ends are its first pixel and the next run's.
pub const RUN: u32 = 16;

/// A chord stands for the perspective where it strays by at most `1 / STRAY_PIXELS` of a
/// pixel (a robust pixel keeps its texel) or else `1 / STRAY_TEXELS` of a texel.
const STRAY_PIXELS: u64 = 16;
/// See [`STRAY_PIXELS`].
const STRAY_TEXELS: u64 = 16;

/// Palettes up to this many colours are lit once a span ([`RowTexture::rgb565_into`]).
const SMALL_PALETTE: usize = 16;

/// Fraction bits of a texture coordinate between runs' ends (beyond its own 16).
const STEP_BITS: u32 = 8;

/// The largest quotient kept, `2^30` (file units: `2^14` textures).
const QUOTIENT_LIMIT: i32 = 1 << 30;

/// A clamped axis's coordinate past this is past the edge anyway.
const CLAMP_REACH: i32 = 1 << 17;

/// How a pixel takes its colour from the texels around its centre's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filter {
    /// The texel the centre falls in (the default): exact, as the accuracy rule counts it.
    #[default]
    Nearest,
    /// The four texels around the centre, weighted by its distance to theirs (1/16 texel
    /// steps): smoother when a texel spans several pixels, four loads a pixel.
    Bilinear,
}

/// What a row's texels are multiplied by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Modulation {
    /// Nothing: an unlit white material shows its texels as they are.
    None,
    /// One colour over the polygon: a faceted or unlit polygon's colour on the side seen.
    Colour(Colour),
    /// A smooth polygon's shade: its material times the pixel's intensity.
    Shade(RowShade),
}

/// One pixel row of a textured polygon (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RowTexture<'a> {
    /// The texture.
    pub texture: Texture<'a>,
    /// `[w, s, t]` at the centre of pixel 0 of the row, modulo `2^32`.
    pub base: [i32; 3],
    /// Their change from a pixel to the next on the right, modulo `2^32`.
    pub step: [i32; 3],
    /// `s / w` times `2^shift[0]` is the pixel's `s` in the file's units (`2^16` the
    /// texture's width); likewise `t`.
    pub shift: [u8; 2],
    /// The polygon's pixels on this row: `first .. end` (runs' ends are taken inside).
    pub first: u32,
    /// See `first`.
    pub end: u32,
    /// What the texels are multiplied by.
    pub modulation: Modulation,
    /// How a pixel takes its texels.
    pub filter: Filter,
}

impl RowTexture<'_> {
    /// The file coordinates `[s, t]` at the centre of pixel `x` (of the polygon's span),
    /// exactly: the quotients, each clamped to `±2^30`.
    #[inline]
    pub fn exact(&self, x: u32) -> [i32; 2] {
        self.exact_with_w(x).1
    }

    /// [`Self::exact`] with `w` there (at least 1). One `f32` division, `1 / w`, and a
    /// multiply a coordinate, each rounded as IEEE 754 says (on every core alike: a soft-float
    /// core's library rounds as an FPU does), so the host and the target agree bit for bit;
    /// the quotient errs by about `2^-22` of itself, far below a texel.
    #[inline]
    fn exact_with_w(&self, x: u32) -> (i32, [i32; 2]) {
        let at = |k: usize| self.base[k].wrapping_add(self.step[k].wrapping_mul(x as i32));
        let w = at(0).max(1);
        let r = 1.0 / w as f32;
        let [shift_s, shift_t] = self.shift;
        let q = |k: usize, shift: u8| {
            // `r 2^shift` by its exponent (`r` is normal, in `[2^-30, 1]`): exact, so the
            // product rounds as `(s r) 2^shift` would, without a second multiply.
            let scaled = f32::from_bits(r.to_bits() + (u32::from(shift).min(127) << 23));
            // (`as` saturates, and the clamp in integers is the clamp in `f32`.)
            ((at(k) as f32 * scaled) as i32).clamp(-QUOTIENT_LIMIT, QUOTIENT_LIMIT)
        };
        (w, [q(1, shift_s), q(2, shift_t)])
    }

    /// The colour of pixel `x`.
    #[inline]
    pub fn at(&self, x: u32) -> Colour {
        self.colours(x).next().unwrap_or_default()
    }

    /// The colours of pixels `x, x + 1, ...`, each as [`Self::at`] gives it. The iterator
    /// never ends: zip it with the pixels of a span.
    #[inline]
    pub fn colours(&self, x: u32) -> TexelColours<'_, '_> {
        TexelColours {
            walk: TexelWalk::new(self, x),
            shade: match self.modulation {
                Modulation::Shade(shade) => Some(shade.colours(x)),
                _ => None,
            },
        }
    }

    /// The RGB565 colours of pixels `x_start .. x_start + out.len()` into `out`, each
    /// [`Self::at`]'s `to_rgb565()`: the texels a run at a time ([`TexelWalk::fill`]), then,
    /// lit by one colour, each texel multiplied once for a run of equal ones (a magnified
    /// texel covers several pixels, a picture has areas of one colour).
    pub fn rgb565_into(&self, x_start: u32, out: &mut [u16]) {
        if self.filter != Filter::Nearest {
            for (slot, colour) in out.iter_mut().zip(self.colours(x_start)) {
                *slot = colour.to_rgb565();
            }
            return;
        }
        let t = &self.texture;
        let lit = |texel: u16| match self.modulation {
            Modulation::Colour(k) => modulate(rgb565_colour(texel), k).to_rgb565(),
            _ => texel,
        };
        let colours = t.colours.len() / 2;
        let by_colour = !matches!(self.modulation, Modulation::Shade(_));
        if by_colour && t.flags & texture_flags::PALETTE != 0 && colours <= SMALL_PALETTE {
            // A small palette is lit once for the span, not once a texel.
            let mut palette = [0u16; SMALL_PALETTE];
            for (i, slot) in palette.iter_mut().enumerate().take(colours) {
                *slot = lit(rgb565_at(t.colours, i));
            }
            let texels = t.texels;
            // (A parsed file's indices are below its colours' count.)
            self.texels(x_start).fill_by(out, |i| {
                let k = texels.get(i).copied().unwrap_or(0);
                palette[usize::from(k) % SMALL_PALETTE]
            });
            return;
        }
        self.texels(x_start).fill(out);
        match self.modulation {
            Modulation::None => {}
            Modulation::Colour(_) => {
                let mut last: Option<(u16, u16)> = None;
                for slot in out.iter_mut() {
                    let texel = *slot;
                    *slot = match last {
                        Some((t, c)) if t == texel => c,
                        _ => {
                            let c = lit(texel);
                            last = Some((texel, c));
                            c
                        }
                    };
                }
            }
            Modulation::Shade(shade) => {
                for (slot, k) in out.iter_mut().zip(shade.colours(x_start)) {
                    *slot = modulate(rgb565_colour(*slot), k).to_rgb565();
                }
            }
        }
    }

    /// The RGB565 texels of pixels `x, x + 1, ...` (before any modulation), nearest.
    #[inline]
    pub fn texels(&self, x: u32) -> TexelWalk<'_, '_> {
        TexelWalk::new(self, x)
    }
}

/// The 8-bit channels of an RGB565 colour, each `round(c * 255 / max)`.
#[inline]
pub const fn rgb565_colour(c: u16) -> Colour {
    let (r, g, b) = ((c >> 11) as u32, ((c >> 5) & 63) as u32, (c & 31) as u32);
    Colour::new(
        ((r * 527 + 23) >> 6) as u8,
        ((g * 259 + 33) >> 6) as u8,
        ((b * 527 + 23) >> 6) as u8,
    )
}

/// `x` times `k` a channel, each `round(x * k / 255)` ([`shaded`]'s rounding).
#[inline]
pub const fn modulate(x: Colour, k: Colour) -> Colour {
    Colour::new(
        shaded(Colour::grey(x.r), k.r).r,
        shaded(Colour::grey(x.g), k.g).r,
        shaded(Colour::grey(x.b), k.b).r,
    )
}

/// The texels of a row's pixels from one on, left to right ([`RowTexture::texels`]): per
/// pixel two adds, two shifts and a load; per run one division.
///
/// A repeating axis's coordinate is kept with the texture's period as `2^32`, so that the
/// wrapping of `i32` arithmetic is the repeat and its texel the top bits; a clamped axis's
/// keeps `STEP_BITS` more fraction bits than the file's units.
#[derive(Debug, Clone)]
pub struct TexelWalk<'r, 'a> {
    row: &'r RowTexture<'a>,
    /// The next pixel.
    x: u32,
    /// Where the current run ends (its last pixel plus one).
    run_end: u32,
    /// `[s, t]` at the next pixel and their steps.
    value: [i32; 2],
    step: [i32; 2],
    /// A coordinate's texel is `value >> shift` (logical where it repeats), masked or clamped
    /// to `max`.
    shift: [u32; 2],
    max: [i32; 2],
    /// Whether each axis clamps.
    clamps: [bool; 2],
    /// The last two run ends computed (column, `w`, coordinates): a run starts where the last
    /// one ended, and a block's first run where the block was decided.
    end: Exact,
    begin: Exact,
    /// The block of [`RUN`] pixels last decided, and the length of its runs.
    block: Option<(u32, u32)>,
}

/// A run end's column, `w` and coordinates ([`RowTexture::exact_with_w`]).
type Exact = (u32, i32, [i32; 2]);

impl<'r, 'a> TexelWalk<'r, 'a> {
    // (Always inlined: returned, the walk would be copied.)
    #[inline(always)]
    fn new(row: &'r RowTexture<'a>, x: u32) -> Self {
        let t = &row.texture;
        let sides = [t.log2_width, t.log2_height].map(u32::from);
        let clamps = [texture_flags::CLAMP_S, texture_flags::CLAMP_T].map(|f| t.flags & f != 0);
        let shift = |k: usize| match (clamps[k], sides[k]) {
            (true, log2) => STEP_BITS + 16 - log2,
            // (A one-texel axis keeps its coordinate 0: see `start_run`.)
            (false, 0) => 31,
            (false, log2) => 32 - log2,
        };
        let mut walk = TexelWalk {
            row,
            x,
            run_end: x,
            value: [0; 2],
            step: [0; 2],
            shift: [shift(0), shift(1)],
            max: sides.map(|log2| (1i32 << log2) - 1),
            clamps,
            end: (u32::MAX, 0, [0; 2]),
            begin: (u32::MAX, 0, [0; 2]),
            block: None,
        };
        if !walk.start_span() {
            walk.start_run();
        }
        walk
    }

    /// The exact values at column `x`, from the last two computed where one was there.
    #[inline]
    fn exact(&self, x: u32) -> (i32, [i32; 2]) {
        match (self.end, self.begin) {
            ((e, w, q), _) | (_, (e, w, q)) if e == x => (w, q),
            _ => self.row.exact_with_w(x),
        }
    }

    /// Draw the whole span as one run where its chord stays close enough to the perspective
    /// ([`Self::straight`]): two divisions a span. Whether it does depends on the span alone,
    /// so a piece of it decides alike.
    #[inline]
    fn start_span(&mut self) -> bool {
        let row = self.row;
        let (a, b) = (row.first, row.end.saturating_sub(1).max(row.first));
        let (wa, qa) = row.exact_with_w(a);
        let (wb, qb) = row.exact_with_w(b);
        if !self.straight(wa, wb, qa, qb, b - a) {
            self.begin = (a, wa, qa);
            self.end = (b, wb, qb);
            return false;
        }
        self.run_end = u32::MAX;
        self.set_run(a, b, qa, qb);
        true
    }

    /// Set up the run holding pixel `self.x`: its ends' exact coordinates, inside the
    /// polygon's span, and the steps between them. Runs are the aligned blocks of [`RUN`]
    /// pixels, or where a block's chord would stray too far from the perspective
    /// ([`Self::run_length`], decided on the block's ends alone, so a piece of a span decides
    /// alike) aligned parts of it, down to single pixels, each exact.
    #[inline(never)]
    fn start_run(&mut self) {
        let row = self.row;
        let last = row.end.saturating_sub(1).max(row.first);
        let inside = |x: u32| x.max(row.first).min(last);
        let block = self.x & !(RUN - 1);
        let len = match self.block {
            Some((start, len)) if start == block => len,
            _ => {
                let (a, b) = (inside(block), inside(block + RUN));
                let (wa, qa) = self.exact(a);
                let (wb, qb) = self.exact(b);
                let len = self.run_length(wa, wb, qa, qb);
                self.block = Some((block, len));
                self.begin = (a, wa, qa);
                self.end = (b, wb, qb);
                len
            }
        };
        let start = self.x & !(len - 1);
        let (a, b) = (inside(start), inside(start + len));
        let (_, qa) = self.exact(a);
        let (wb, qb) = self.exact(b);
        self.run_end = start + len;
        if self.end.0 != b {
            self.begin = self.end;
            self.end = (b, wb, qb);
        }
        self.set_run(a, b, qa, qb);
    }

    /// The coordinates at pixel `self.x` and their steps, on the chord from `qa` at column `a`
    /// to `qb` at column `b`.
    #[inline]
    fn set_run(&mut self, a: u32, b: u32, qa: [i32; 2], qb: [i32; 2]) {
        let n = b - a;
        // From `a` to pixel `x`.
        let offset = self.x.saturating_sub(a) as i32;
        for k in 0..2 {
            let (from, to) = (qa[k], qb[k]);
            let (value, step) = if self.clamps[k] {
                let from = from.clamp(-CLAMP_REACH, CLAMP_REACH);
                let to = to.clamp(-CLAMP_REACH, CLAMP_REACH);
                let change = (to - from) << STEP_BITS;
                (from << STEP_BITS, divide(change, n))
            } else if self.max[k] == 0 {
                (0, 0)
            } else {
                // The period is `2^16` file units, `2^32` here: a shift by 16 wraps the
                // coordinate into it, and the change's low 32 bits are all a step needs.
                let change = to.wrapping_sub(from);
                let step = if n.is_power_of_two() && n <= 1 << 16 {
                    change << (16 - n.trailing_zeros())
                } else if change.unsigned_abs() < 1 << 15 {
                    divide(change << 16, n)
                } else {
                    // (More than half a texture: in 64 bits.)
                    (i64::from(change) << 16)
                        .checked_div(i64::from(n))
                        .unwrap_or(0) as i32
                };
                (from << 16, step)
            };
            self.value[k] = value.wrapping_add(step.wrapping_mul(offset));
            self.step[k] = step;
        }
    }

    /// How far a chord between `w` = `wa` and `wb`, coordinates `qa` and `qb`, may stray from
    /// the perspective: `(bend, near, change)`, with the chord's change in 1/256 texel (plus
    /// one). Where `w` changes by the ratio `r = far / near >= 1` over a chord of `L` pixels,
    /// a point strays from it by at most `L (r - 1) / 4` pixels, and `(r - 1) / 4` of the
    /// chord's change in texels.
    #[inline]
    fn bend(&self, wa: i32, wb: i32, qa: [i32; 2], qb: [i32; 2]) -> (u64, u64, u64) {
        let (near, far) = (wa.min(wb).max(1) as u64, wa.max(wb).max(1) as u64);
        let t = &self.row.texture;
        let change = |k: usize, log2: u8| {
            let q = (i64::from(qb[k]) - i64::from(qa[k])).unsigned_abs();
            (q << log2 >> 8) + 1
        };
        let change = change(0, t.log2_width).max(change(1, t.log2_height));
        (far - near, near, change)
    }

    /// Whether a chord of `len` pixels strays by at most [`STRAY_PIXELS`] of a pixel or
    /// [`STRAY_TEXELS`] of a texel ([`Self::bend`]).
    #[inline]
    fn straight(&self, wa: i32, wb: i32, qa: [i32; 2], qb: [i32; 2], len: u32) -> bool {
        let (bend, near, change) = self.bend(wa, wb, qa, qb);
        // `len bend / (4 near) <= 1 / STRAY_PIXELS`.
        let pixels = product(u64::from(len), bend) * STRAY_PIXELS <= 4 * near;
        // `change bend / (4 near) <= 256 / STRAY_TEXELS` (`change` in 1/256 texel).
        let texels = product(change, bend).saturating_mul(STRAY_TEXELS) <= 1024 * near;
        pixels || texels
    }

    /// The length of the runs a block of [`RUN`] pixels is drawn in, from its ends (as
    /// [`Self::straight`] takes them): the longest power of two whose chord stays close
    /// enough to the perspective. Over a run of `L` pixels of the block, `r - 1` and the
    /// run's change are both about `L / 16` of the block's, so the stray goes as `L^2`. A
    /// pixel whose centre and the points 1/16 pixel around it lie in one texel (a robust
    /// pixel, as the accuracy rule counts them) keeps its texel when the run strays by at most
    /// 1/16 pixel; failing that, a stray of 1/16 texel moves few of the pixels into a texel
    /// next to theirs.
    #[inline]
    fn run_length(&self, wa: i32, wb: i32, qa: [i32; 2], qb: [i32; 2]) -> u32 {
        let (bend, near, change) = self.bend(wa, wb, qa, qb);
        // With `L = 2^k`, the run's stray is `L^2 / 256` of the block's whole chord's: in
        // pixels `L^2 bend STRAY_PIXELS <= 64 near`, in texels `L^2 change bend STRAY_TEXELS
        // <= 2^18 near` (`X L^2 <= Y` taken as `X <= Y >> 2k`, the same for integers).
        let pixels = bend * STRAY_PIXELS;
        let texels = product(change, bend).saturating_mul(STRAY_TEXELS);
        let (pixel_room, texel_room) = (64 * near, (1 << 18) * near);
        for k in [4u32, 3, 2, 1] {
            if pixels <= pixel_room >> (2 * k) || texels <= texel_room >> (2 * k) {
                return 1 << k;
            }
        }
        1
    }

    /// Coordinate `k` of `v` in units of `2^-fraction` texel, not yet repeated or clamped.
    #[inline]
    fn coordinate(&self, k: usize, v: i32, fraction: u32) -> i32 {
        let shift = self.shift[k] - fraction;
        if self.clamps[k] {
            v >> shift
        } else {
            ((v as u32) >> shift) as i32
        }
    }

    /// Texel `v` on axis `k`, repeated or clamped.
    #[inline]
    fn place(&self, k: usize, v: i32) -> i32 {
        if self.clamps[k] {
            // (`max` and `min`: `clamp` checks its bounds, a panic the proof would see.)
            v.max(0).min(self.max[k])
        } else {
            v & self.max[k]
        }
    }

    /// The next pixel's texel: its index in the texture's texels.
    #[inline]
    fn texel_index(&self) -> usize {
        let place = |k: usize| self.place(k, self.coordinate(k, self.value[k], 0));
        ((place(1) << self.row.texture.log2_width) | place(0)) as usize
    }

    /// The RGB565 texel at index `i`.
    #[inline]
    fn texel(&self, i: usize) -> u16 {
        self.row.texture.texel_at(i)
    }

    /// Step to the next pixel.
    #[inline]
    fn advance(&mut self) {
        self.value[0] = self.value[0].wrapping_add(self.step[0]);
        self.value[1] = self.value[1].wrapping_add(self.step[1]);
        self.x += 1;
    }

    /// The next pixel's colour filtered bilinearly: the four texels around its coordinates
    /// (texel centres at half a texel), weighted in 1/16 of a texel.
    fn next_bilinear(&mut self) -> Colour {
        if self.x >= self.run_end {
            self.start_run();
        }
        // Coordinates in 1/16 texel from the first texel's centre.
        let at = |k: usize| self.coordinate(k, self.value[k], 4) - 8;
        let (s, t) = (at(0), at(1));
        let (fs, ft) = ((s & 15) as u32, (t & 15) as u32);
        let (c0, r0) = (s >> 4, t >> 4);
        let log2 = self.row.texture.log2_width;
        let index = |c: i32, r: i32| ((self.place(1, r) << log2) | self.place(0, c)) as usize;
        let corners = [
            (index(c0, r0), (16 - fs) * (16 - ft)),
            (index(c0 + 1, r0), fs * (16 - ft)),
            (index(c0, r0 + 1), (16 - fs) * ft),
            (index(c0 + 1, r0 + 1), fs * ft),
        ];
        let mut sum = [128u32; 3];
        for (i, weight) in corners {
            let c = rgb565_colour(self.texel(i));
            sum[0] += u32::from(c.r) * weight;
            sum[1] += u32::from(c.g) * weight;
            sum[2] += u32::from(c.b) * weight;
        }
        self.advance();
        Colour::new(
            (sum[0] >> 8) as u8,
            (sum[1] >> 8) as u8,
            (sum[2] >> 8) as u8,
        )
    }
}

/// `a b`, saturated: in 32 bits where both are below `2^16`, the usual case (a core without a
/// 64-bit multiply, the Cortex-M0+, calls a library for one).
#[inline]
fn product(a: u64, b: u64) -> u64 {
    match (u16::try_from(a), u16::try_from(b)) {
        (Ok(a), Ok(b)) => u64::from(u32::from(a) * u32::from(b)),
        _ => a.saturating_mul(b),
    }
}

/// `change / n` (0 where `n` is 0), by a shift where `n` is a power of two.
#[inline]
fn divide(change: i32, n: u32) -> i32 {
    match n {
        0 => 0,
        n if n.is_power_of_two() => change >> n.trailing_zeros(),
        n => change.checked_div(n as i32).unwrap_or(0),
    }
}

impl TexelWalk<'_, '_> {
    /// The texels of the next `out.len()` pixels into `out`, a run at a time: the run's end,
    /// the palette and the clamps tested once a run, not once a pixel (Quake's span drawer's
    /// inner loop).
    pub fn fill(&mut self, out: &mut [u16]) {
        let t = self.row.texture;
        if t.flags & texture_flags::PALETTE != 0 {
            self.fill_by(out, |i| t.texel_at(i));
        } else {
            // (The palette tested once a fill, not once a texel.)
            self.fill_by(out, |i| rgb565_at(t.texels, i));
        }
    }

    /// [`Self::fill`] with `colour(i)` the colour of texel `i`.
    #[inline]
    fn fill_by(&mut self, out: &mut [u16], colour: impl Fn(usize) -> u16) {
        let mut out = out;
        while !out.is_empty() {
            if self.x >= self.run_end {
                self.start_run();
            }
            let n = ((self.run_end - self.x) as usize).min(out.len());
            let Some((run, rest)) = out.split_at_mut_checked(n) else {
                return;
            };
            if self.clamps[0] || self.clamps[1] {
                for slot in run.iter_mut() {
                    let i = self.texel_index();
                    self.advance();
                    *slot = colour(i);
                }
            } else {
                let [mut s, mut v] = self.value;
                let [ds, dt] = self.step;
                let [shift_s, shift_t] = self.shift;
                let log2 = u32::from(self.row.texture.log2_width);
                for slot in run.iter_mut() {
                    let i = ((((v as u32) >> shift_t) << log2) | ((s as u32) >> shift_s)) as usize;
                    *slot = colour(i);
                    s = s.wrapping_add(ds);
                    v = v.wrapping_add(dt);
                }
                self.value = [s, v];
                self.x += n as u32;
            }
            out = rest;
        }
    }
}

impl Iterator for TexelWalk<'_, '_> {
    type Item = u16;

    #[inline]
    fn next(&mut self) -> Option<u16> {
        if self.x >= self.run_end {
            self.start_run();
        }
        let i = self.texel_index();
        self.advance();
        Some(self.texel(i))
    }
}

/// The colours of a row's pixels from one on ([`RowTexture::colours`]).
#[derive(Debug, Clone)]
pub struct TexelColours<'r, 'a> {
    walk: TexelWalk<'r, 'a>,
    shade: Option<super::RowColours>,
}

impl Iterator for TexelColours<'_, '_> {
    type Item = Colour;

    #[inline]
    fn next(&mut self) -> Option<Colour> {
        let x = match self.walk.row.filter {
            Filter::Nearest => rgb565_colour(self.walk.next()?),
            Filter::Bilinear => self.walk.next_bilinear(),
        };
        Some(match (&self.walk.row.modulation, self.shade.as_mut()) {
            (_, Some(shade)) => modulate(x, shade.next()?),
            (Modulation::Colour(k), None) => modulate(x, *k),
            _ => x,
        })
    }
}

#[cfg(test)]
mod tests;
