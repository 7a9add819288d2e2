//! Hand-built command streams and the pictures they make; what the model refuses.

use super::*;

/// A command and its parameters, as mipidsi sends them: the command byte with the line low,
/// then the parameters with it high.
fn command(code: u8, parameters: &[u8]) -> Vec<Write> {
    vec![
        Write {
            data: false,
            bytes: vec![code],
        },
        Write {
            data: true,
            bytes: parameters.to_vec(),
        },
    ]
}

/// `CASET` or `RASET` of `first..=last`.
fn range(code: u8, first: u16, last: u16) -> Vec<Write> {
    let ([a, b], [c, d]) = (first.to_be_bytes(), last.to_be_bytes());
    command(code, &[a, b, c, d])
}

/// `RAMWR` of `pixels`, big-endian, in bursts of 7 bytes (a pixel split across two).
fn write(pixels: &[u16]) -> Vec<Write> {
    let bytes: Vec<u8> = pixels.iter().flat_map(|p| p.to_be_bytes()).collect();
    let mut w = command(RAMWR, &[]);
    w.extend(bytes.chunks(7).map(|c| Write {
        data: true,
        bytes: c.to_vec(),
    }));
    w
}

/// Out of sleep, display on, 16-bit pixels, `madctl`.
fn set_up(madctl: u8) -> Vec<Write> {
    [
        command(SLPOUT, &[]),
        command(MADCTL, &[madctl]),
        command(COLMOD, &[RGB565]),
        command(DISPON, &[]),
    ]
    .concat()
}

/// A glass that shows the controller's colours as they are.
const PLAIN: Glass = Glass {
    inverts: false,
    bgr: false,
    neutral: &[],
};

/// Every memory pixel written with `value`, in the memory's own addresses (`MADCTL` without
/// its mapping bits: `madctl` is 0 or [`BGR`]).
fn fill(madctl: u8, value: u16) -> Vec<Write> {
    [
        command(MADCTL, &[madctl]),
        range(CASET, 0, 239),
        range(RASET, 0, 319),
        write(&vec![value; COLUMNS * ROWS]),
    ]
    .concat()
}

fn at(picture: &[u16], x: usize, y: usize) -> u16 {
    picture[y * PICTURE_WIDTH + x]
}

#[test]
fn a_landscape_window_fills_the_picture_row_by_row() {
    // MX + MV, mipidsi's Deg90: the window's addresses are the picture's.
    let pixels: Vec<u16> = (0..PICTURE_WIDTH * PICTURE_HEIGHT)
        .map(|i| (i * 7) as u16)
        .collect();
    let stream = [
        set_up(MX | MV),
        range(CASET, 0, 319),
        range(RASET, 0, 239),
        write(&pixels),
    ]
    .concat();
    assert_eq!(decode(PLAIN, &stream).unwrap(), pixels);
}

#[test]
fn a_small_window_lands_where_its_addresses_say() {
    let stream = [
        set_up(0),
        fill(0, 0),
        command(MADCTL, &[MX | MV]),
        range(CASET, 10, 11),
        range(RASET, 5, 6),
        write(&[1, 2, 3, 4]),
    ]
    .concat();
    let picture = decode(PLAIN, &stream).unwrap();
    assert_eq!(
        [
            at(&picture, 10, 5),
            at(&picture, 11, 5),
            at(&picture, 10, 6),
            at(&picture, 11, 6)
        ],
        [1, 2, 3, 4]
    );
    assert_eq!(picture.iter().filter(|&&p| p != 0).count(), 4);
}

#[test]
fn the_memory_is_seen_a_quarter_turn_anticlockwise() {
    // Unmapped, the memory's last column of its first row is the picture's top-left pixel,
    // and its first column of its last row the bottom-right one.
    let stream = [
        set_up(0),
        fill(0, 0),
        range(CASET, 239, 239),
        range(RASET, 0, 0),
        write(&[9]),
        range(CASET, 0, 0),
        range(RASET, 319, 319),
        write(&[8]),
    ]
    .concat();
    let picture = decode(PLAIN, &stream).unwrap();
    assert_eq!(at(&picture, 0, 0), 9);
    assert_eq!(at(&picture, 319, 239), 8);
}

#[test]
fn the_mirror_bits_mirror_the_memory() {
    // MY: address row 0 is the memory's last row (the picture's right edge); MX: address
    // column 0 its last column (the picture's top edge).
    let stream = [
        set_up(0),
        fill(0, 0),
        command(MADCTL, &[MY]),
        range(CASET, 0, 0),
        range(RASET, 0, 0),
        write(&[5]),
        command(MADCTL, &[MX]),
        range(CASET, 0, 0),
        range(RASET, 0, 0),
        write(&[6]),
    ]
    .concat();
    let picture = decode(PLAIN, &stream).unwrap();
    assert_eq!(at(&picture, 319, 239), 5);
    assert_eq!(at(&picture, 0, 0), 6);
}

#[test]
fn inversion_and_colour_order_are_the_glass_against_the_controller() {
    let red = 0xF800;
    let shown = |glass: Glass, commands: Vec<Write>| {
        let stream = [set_up(0), commands, fill(0, red)].concat();
        at(&decode(glass, &stream).unwrap(), 0, 0)
    };
    assert_eq!(shown(PLAIN, vec![]), red);
    assert_eq!(shown(PLAIN, command(INVON, &[])), !red);
    assert_eq!(shown(ST7789_IPS, command(INVON, &[])), red);
    assert_eq!(shown(ST7789_IPS, command(INVOFF, &[])), !red);
    // `fill` leaves MADCTL 0: RGB order on a BGR glass swaps red and blue.
    assert_eq!(shown(ILI9341_BGR, vec![]), 0x001F);
    let bgr = [set_up(BGR), fill(BGR, red)].concat();
    assert_eq!(at(&decode(ILI9341_BGR, &bgr).unwrap(), 0, 0), red);
}

#[test]
fn a_software_reset_forgets_the_settings() {
    let stream = [set_up(0), command(SWRESET, &[]), fill(0, 0)].concat();
    let e = decode(PLAIN, &stream).unwrap_err();
    assert!(e.contains("COLMOD"), "{e}");
}

/// The error decoding `stream` after [`set_up`] gives.
fn refused(glass: Glass, stream: Vec<Write>) -> String {
    decode(glass, &[set_up(MX | MV), stream].concat()).unwrap_err()
}

#[test]
fn what_the_model_does_not_understand_is_an_error() {
    let cases: Vec<(Glass, Vec<Write>, &str)> = vec![
        (PLAIN, command(0xB0, &[1, 2]), "command 0xb0 is not one"),
        // INVCTR is neutral on the ILI9341 only.
        (ST7789_IPS, command(0xB4, &[0]), "command 0xb4 is not one"),
        (PLAIN, write(&[1]), "RAMWR without a window"),
        (
            PLAIN,
            [range(CASET, 0, 0), write(&[1])].concat(),
            "RAMWR without a window",
        ),
        (PLAIN, command(COLMOD, &[0x66]), "COLMOD 0x66"),
        (
            PLAIN,
            command(MADCTL, &[]),
            "takes 1 parameter bytes, got 0",
        ),
        (PLAIN, range(CASET, 5, 4), "first address 5 after the last"),
        (
            PLAIN,
            [range(CASET, 0, 319), range(RASET, 0, 240), write(&[1])].concat(),
            "outside the 320x240 addresses",
        ),
        (
            PLAIN,
            [range(CASET, 0, 0), range(RASET, 0, 0), write(&[1, 2])].concat(),
            "RAMWR past the end of its window",
        ),
    ];
    for (glass, stream, expected) in cases {
        let e = refused(glass, stream);
        assert!(e.contains(expected), "{e:?} should say {expected:?}");
    }
}

#[test]
fn half_a_pixel_data_before_a_command_and_an_unfinished_picture_are_errors() {
    let half = [
        range(CASET, 0, 0),
        range(RASET, 0, 0),
        command(RAMWR, &[0x12]),
    ]
    .concat();
    assert!(refused(PLAIN, half).contains("middle of a pixel"));
    let early = [Write {
        data: true,
        bytes: vec![1],
    }];
    assert!(decode(PLAIN, &early)
        .unwrap_err()
        .contains("before any command"));
    let unwritten = decode(PLAIN, &set_up(0)).unwrap_err();
    assert!(unwritten.contains("never written"), "{unwritten}");
    let dark = [command(SLPOUT, &[]), command(COLMOD, &[RGB565]), fill(0, 0)].concat();
    let dark = decode(PLAIN, &dark).unwrap_err();
    assert!(dark.contains("DISPON"), "{dark}");
}
