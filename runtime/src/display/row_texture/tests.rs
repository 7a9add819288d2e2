extern crate std;

use std::boxed::Box;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::display::SHADE_FRACTION_BITS;

/// A 4 x 4 texture whose texel `(c, r)` is `r * 4 + c + 1` (RGB565 values, all distinct).
const TEXELS: [u8; 32] = {
    let mut b = [0u8; 32];
    let mut i = 0;
    while i < 16 {
        b[2 * i] = (i + 1) as u8;
        i += 1;
    }
    b
};

fn texture(flags: u8) -> Texture<'static> {
    Texture {
        log2_width: 2,
        log2_height: 2,
        flags,
        colours: &[],
        texels: &TEXELS,
    }
}

/// [`texture`] through a palette of 3 colours (a small palette: lit once a span).
fn palette_texture() -> Texture<'static> {
    const INDICES: [u8; 16] = [0, 1, 2, 1, 2, 0, 0, 1, 1, 1, 2, 2, 0, 2, 1, 0];
    const COLOURS: [u8; 6] = [0x1f, 0x00, 0xe0, 0x07, 0x34, 0x92];
    Texture {
        flags: texture_flags::PALETTE,
        colours: &COLOURS,
        texels: &INDICES,
        ..texture(0)
    }
}

/// The texel value at `(c, r)` of [`texture`].
fn value(c: u32, r: u32) -> u16 {
    (r * 4 + c + 1) as u16
}

/// A row whose `s / w` and `t / w` are `(a_s + b_s x) / (a_w + b_w x)` and so on, with
/// `w` scaled by `2^20`.
fn row(
    w: (f64, f64),
    s: (f64, f64),
    t: (f64, f64),
    span: (u32, u32),
    flags: u8,
) -> RowTexture<'static> {
    let scale = (1u32 << 20) as f64;
    let shift = 17u8;
    let to = |v: f64| v.round() as i32;
    RowTexture {
        texture: texture(flags),
        base: [
            to(w.0 * scale),
            to(s.0 * scale / (1u32 << shift) as f64),
            to(t.0 * scale / (1u32 << shift) as f64),
        ],
        step: [
            to(w.1 * scale),
            to(s.1 * scale / (1u32 << shift) as f64),
            to(t.1 * scale / (1u32 << shift) as f64),
        ],
        shift: [shift; 2],
        first: span.0,
        end: span.1,
        modulation: Modulation::None,
        filter: Filter::Nearest,
    }
}

#[test]
fn rgb565_expands_rounded_and_back_exactly() {
    for c in 0..=u16::MAX {
        let x = rgb565_colour(c);
        let (r, g, b) = ((c >> 11) as f64, ((c >> 5) & 63) as f64, (c & 31) as f64);
        assert_eq!(x.r, (r * 255.0 / 31.0).round() as u8, "{c:#x}");
        assert_eq!(x.g, (g * 255.0 / 63.0).round() as u8, "{c:#x}");
        assert_eq!(x.b, (b * 255.0 / 31.0).round() as u8, "{c:#x}");
        assert_eq!(x.to_rgb565(), c, "{c:#x} back");
    }
}

#[test]
fn modulation_rounds_each_channel() {
    for x in (0..=255u8).step_by(3) {
        for k in 0..=255u8 {
            let m = modulate(Colour::new(x, 255, 0), Colour::new(k, k, k));
            let exact = (f64::from(x) * f64::from(k) / 255.0).round() as u8;
            assert_eq!((m.r, m.g, m.b), (exact, k, 0), "{x} {k}");
        }
    }
}

/// Without perspective (`w` constant) every pixel's texel is the one its exact coordinates
/// fall in, and any piece of the span gives the whole span's pixels.
#[test]
fn an_affine_row_gives_each_pixel_its_texel_whatever_the_piece() {
    // s = (x + 0.6) / 10 of the texture: a texel every 2.5 pixels, no pixel on a texel's
    // edge; t fixed in row 1.
    let r = row(
        (1.0, 0.0),
        (65536.0 * 0.06, 65536.0 * 0.1),
        (65536.0 * 0.3, 0.0),
        (3, 77),
        0,
    );
    let whole: Vec<u16> = r.texels(3).take(74).collect();
    for (x, &texel) in (3..77u32).zip(&whole) {
        let s = (f64::from(x) + 0.6) * 0.1;
        let column = ((s * 4.0).floor() as u32) % 4;
        assert_eq!(texel, value(column, 1), "pixel {x}");
    }
    for start in [3, 10, 15, 16, 17, 40, 76] {
        let piece: Vec<u16> = r.texels(start).take((77 - start) as usize).collect();
        assert_eq!(piece[..], whole[(start - 3) as usize..], "from {start}");
    }
}

/// With perspective: exact at runs' ends, and every pixel within a texel of its exact one.
#[test]
fn a_perspective_row_is_exact_at_runs_ends_and_close_between() {
    // w falls from 1 to 0.1 across 200 pixels; s and t over several repeats.
    let w = (1.0, -0.9 / 200.0);
    let s = (0.0, 65536.0 * 3.0 / 200.0 * 0.5);
    let t = (65536.0 * 0.25, 65536.0 * 1.0 / 200.0 * 0.3);
    let r = row(w, s, t, (0, 200), 0);
    let texels: Vec<u16> = r.texels(0).take(200).collect();
    let mut adjacent = 0;
    for (x, &texel) in (0..200u32).zip(&texels) {
        let [qs, qt] = r.exact(x);
        let place = |q: i32| ((q >> 14) & 3) as u32;
        let exact = value(place(qs), place(qt));
        if x % RUN == 0 || x == 199 {
            assert_eq!(texel, exact, "run end {x}");
        } else if texel != exact {
            adjacent += 1;
            let near = (0..3).any(|dc| {
                (0..3).any(|dr| texel == value((place(qs) + dc + 3) % 4, (place(qt) + dr + 3) % 4))
            });
            assert!(near, "pixel {x}: {texel} against {exact}");
        }
    }
    assert!(adjacent < 10, "{adjacent} pixels off by a texel");
}

#[test]
fn clamped_axes_take_the_edge_texels() {
    // s from -1 to 2 textures across 30 pixels: clamped, the first pixels show column 0 and
    // the last column 3; repeated, they wrap.
    let s = (-65536.0, 65536.0 * 3.0 / 30.0);
    let t = (65536.0 * 0.6, 0.0);
    let clamped = row((1.0, 0.0), s, t, (0, 30), texture_flags::CLAMP_S);
    let texels: Vec<u16> = clamped.texels(0).take(30).collect();
    assert!(texels[..9].iter().all(|&v| v == value(0, 2)), "{texels:?}");
    assert!(texels[21..].iter().all(|&v| v == value(3, 2)), "{texels:?}");
    let repeated = row((1.0, 0.0), s, t, (0, 30), 0);
    let texels: Vec<u16> = repeated.texels(0).take(30).collect();
    // Pixel 2 at -0.8 of a texture, column 0 of the repeat; pixel 3 at -0.7, column 1.
    assert_eq!(texels[2], value(0, 2));
    assert_eq!(texels[3], value(1, 2));
}

#[test]
fn colours_are_the_texels_times_the_lighting() {
    let mut r = row((1.0, 0.0), (0.0, 65536.0 / 8.0), (0.0, 0.0), (0, 8), 0);
    let plain: Vec<Colour> = r.colours(0).take(8).collect();
    assert!(plain
        .iter()
        .zip(r.texels(0))
        .all(|(&c, t)| c == rgb565_colour(t)));
    let k = Colour::new(200, 100, 50);
    r.modulation = Modulation::Colour(k);
    let lit: Vec<Colour> = r.colours(0).take(8).collect();
    assert!(lit.iter().zip(&plain).all(|(&l, &p)| l == modulate(p, k)));
    let shade = RowShade {
        base: 100 << SHADE_FRACTION_BITS,
        step: 10 << SHADE_FRACTION_BITS,
        colour: k,
    };
    r.modulation = Modulation::Shade(shade);
    for (x, (c, &p)) in (0..8u32).zip(r.colours(0).zip(&plain)) {
        assert_eq!(c, modulate(p, shade.at(x)), "{x}");
        assert_eq!(r.at(x), c);
    }
}

/// Bilinear: at a texel's centre its own colour, halfway between two centres their average,
/// a quarter of the way three parts to one; clamped past the edge.
#[test]
fn bilinear_weighs_the_four_texels_around_the_centre() {
    // s = x / 16 of the texture: texel centres (4 texels) at x = 2, 6, 10, 14.
    let mut r = row(
        (1.0, 0.0),
        (0.0, 65536.0 / 16.0),
        (65536.0 * (0.5 / 4.0), 0.0),
        (0, 16),
        texture_flags::CLAMP_S,
    );
    r.filter = Filter::Bilinear;
    let colours: Vec<Colour> = r.colours(0).take(16).collect();
    let at = |c: u32| rgb565_colour(value(c, 0));
    assert_eq!(colours[2], at(0));
    assert_eq!(colours[6], at(1));
    let mix = |a: Colour, b: Colour, w: u32| {
        let m = |x: u8, y: u8| ((u32::from(x) * (16 - w) + u32::from(y) * w) * 16 + 128) >> 8;
        Colour::new(m(a.r, b.r) as u8, m(a.g, b.g) as u8, m(a.b, b.b) as u8)
    };
    assert_eq!(colours[4], mix(at(0), at(1), 8), "halfway");
    assert_eq!(colours[3], mix(at(0), at(1), 4), "a quarter");
    // Left of the first centre, clamped: the first texel alone.
    assert_eq!(colours[0], at(0));
    assert_eq!(colours[15], at(3));
    // Nearest takes one texel where bilinear mixes.
    r.filter = Filter::Nearest;
    assert_eq!(r.at(4), at(1));
}

/// `fill` gives the iterator's texels, from any pixel, over runs, repeating and clamped,
/// direct and through a palette.
#[test]
fn fill_is_the_walk() {
    let palette_texels: Vec<u8> = (0..16u8).map(|i| (i * 7) % 5).collect();
    let colours: Vec<u8> = [0x1111u16, 0x2222, 0x3333, 0x4444, 0x5555]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    for flags in [0, texture_flags::CLAMP_S, texture_flags::CLAMP_T] {
        for palette in [false, true] {
            let mut r = row(
                (1.0, -0.004),
                (-65536.0 * 0.3, 65536.0 * 0.021),
                (65536.0 * 0.2, 65536.0 * 0.013),
                (2, 150),
                flags,
            );
            if palette {
                r.texture.flags |= texture_flags::PALETTE;
                r.texture.texels = Box::leak(palette_texels.clone().into_boxed_slice());
                r.texture.colours = Box::leak(colours.clone().into_boxed_slice());
            }
            for start in [2u32, 9, 16, 33, 140] {
                let n = (150 - start) as usize;
                let walked: Vec<u16> = r.texels(start).take(n).collect();
                let mut filled = vec![0u16; n];
                r.texels(start).fill(&mut filled);
                assert_eq!(
                    filled, walked,
                    "flags {flags}, palette {palette}, from {start}"
                );
            }
        }
    }
}

/// `rgb565_into` is each pixel's colour in RGB565, unlit, lit by a colour and by a shade, and
/// bilinear.
#[test]
fn rgb565_into_is_each_pixels_colour() {
    let mut r = row(
        (1.0, -0.003),
        (65536.0 * 0.1, 65536.0 * 0.01),
        (65536.0 * 0.2, 65536.0 * 0.004),
        (0, 100),
        0,
    );
    let shade = RowShade {
        base: 90 << SHADE_FRACTION_BITS,
        step: 1 << (SHADE_FRACTION_BITS - 1),
        colour: Colour::new(250, 200, 100),
    };
    for modulation in [
        Modulation::None,
        Modulation::Colour(Colour::new(200, 128, 30)),
        Modulation::Shade(shade),
    ] {
        for filter in [Filter::Nearest, Filter::Bilinear] {
            r.modulation = modulation;
            r.filter = filter;
            for palette in [false, true] {
                r.texture = if palette {
                    palette_texture()
                } else {
                    texture(0)
                };
                for start in [0u32, 7, 50] {
                    let mut out = vec![0u16; (100 - start) as usize];
                    r.rgb565_into(start, &mut out);
                    let expected: Vec<u16> = r
                        .colours(start)
                        .take(out.len())
                        .map(|c| c.to_rgb565())
                        .collect();
                    assert_eq!(
                        out, expected,
                        "{modulation:?} {filter:?} palette {palette} from {start}"
                    );
                }
            }
        }
    }
}

/// A row whose chord strays little is one run: exact at its span's ends, within a texel of
/// the exact coordinates between, and any piece gives the whole span's texels. A row that
/// bends much is not.
#[test]
fn a_straight_span_is_one_run() {
    // w from 1 to 0.98 over 100 pixels; s over two repeats.
    let r = row(
        (1.0, -0.0002),
        (65536.0 * 0.1, 65536.0 * 0.02),
        (65536.0 * 0.6, 65536.0 * 0.001),
        (10, 110),
        0,
    );
    let ends = |r: &RowTexture<'_>, a: u32, b: u32| {
        let (wa, qa) = r.exact_with_w(a);
        let (wb, qb) = r.exact_with_w(b);
        TexelWalk::new(r, a).straight(wa, wb, qa, qb, b - a)
    };
    assert!(ends(&r, 10, 109));
    let whole: Vec<u16> = r.texels(10).take(100).collect();
    let place = |q: i32| ((q >> 14) & 3) as u32;
    // A texel is 2^14 file units: a pixel whose exact coordinates lie further than the
    // stray (1/16 texel) from a texel's edge keeps its texel.
    let from_edge = |q: i32| {
        let within = q & ((1 << 14) - 1);
        within.min((1 << 14) - within)
    };
    let mut off = 0;
    for (x, &texel) in (10..110u32).zip(&whole) {
        let [qs, qt] = r.exact(x);
        if x == 10 || x == 109 {
            assert_eq!(texel, value(place(qs), place(qt)), "span end {x}");
        } else if texel != value(place(qs), place(qt)) {
            off += 1;
            let near_edge = from_edge(qs).min(from_edge(qt)) <= 1 << 10;
            assert!(near_edge, "pixel {x}: {texel} off, far from an edge");
        }
    }
    // (Some are: one chord, not a division a pixel.)
    assert!(off > 0 && off <= 12, "{off} pixels off");
    for start in [11, 16, 50, 109] {
        let piece: Vec<u16> = r.texels(start).take((110 - start) as usize).collect();
        assert_eq!(piece[..], whole[(start - 10) as usize..], "from {start}");
    }
    let bent = row(
        (1.0, -0.9 / 200.0),
        (0.0, 65536.0 * 0.0075),
        (0.0, 0.0),
        (0, 200),
        0,
    );
    assert!(!ends(&bent, 0, 199));
}

/// A repeating axis wraps however many periods its coordinate spans, and a one-texel axis
/// shows its only texel.
#[test]
fn repeats_wrap_over_many_periods() {
    // s from -40.07 textures by 1.025 a pixel (four texels a pixel and a tenth), t anywhere
    // on a one-texel-high texture.
    let mut r = row(
        (1.0, 0.0),
        (-65536.0 * 40.07, 65536.0 * (1.0 + 1.0 / 40.0)),
        (65536.0 * 7.3, 65536.0 * 0.37),
        (0, 80),
        0,
    );
    r.texture.log2_height = 0;
    let texels: Vec<u16> = r.texels(0).take(80).collect();
    for (x, &texel) in (0..80u32).zip(&texels) {
        let s = -40.07 + f64::from(x) * (1.0 + 1.0 / 40.0);
        let column = ((s * 4.0).floor() as i64).rem_euclid(4) as u32;
        assert_eq!(texel, value(column, 0), "pixel {x}");
    }
}
