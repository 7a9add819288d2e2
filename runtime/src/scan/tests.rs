//! Scan order: the memory against a pixel model, frames against the framebuffer's, rows in
//! order, running out as an error.

extern crate std;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::camera::{Camera, Pose};
use crate::coverage::Coverage;
use crate::display::{Rgb565Framebuffer, SpanSink};
use crate::read::Node;
use crate::render::{Renderer, Source, Workspace};
use crate::traverse::testing::{box_faces, TestTree};

const W: u32 = 48;
const H: u32 = 36;
const BACKGROUND: Colour = Colour::new(0xab, 0xcd, 0xef);

/// The first colour written to each pixel (front to back: the one that shows).
struct Model {
    width: usize,
    pixels: Vec<Option<u16>>,
}

impl Model {
    fn new(w: u32, h: u32) -> Self {
        Model {
            width: w as usize,
            pixels: vec![None; (w * h) as usize],
        }
    }

    fn span(&mut self, y: u32, a: u32, b: u32, c: Colour) -> u64 {
        let mut n = 0;
        for x in a..b.min(self.width as u32) {
            let p = &mut self.pixels[y as usize * self.width + x as usize];
            if p.is_none() {
                *p = Some(c.to_rgb565());
                n += 1;
            }
        }
        n
    }

    fn image(&self, background: u16) -> Vec<u16> {
        self.pixels
            .iter()
            .map(|p| p.unwrap_or(background))
            .collect()
    }
}

/// Every row's list sorted, disjoint, and touching intervals of one colour merged.
fn well_formed(m: &ScanMemory<'_>) -> bool {
    (0..m.height()).all(|y| {
        let mut i = m.head(y);
        let mut last: Option<ScanNode> = None;
        while i != NIL {
            let n = m.node(i);
            if n.start >= n.end || u32::from(n.end) > m.width() {
                return false;
            }
            if let Some(l) = last {
                if l.end > n.start || (l.end == n.start && l.colour == n.colour) {
                    return false;
                }
            }
            last = Some(n);
            i = n.next;
        }
        true
    })
}

#[test]
fn intervals_merge_by_colour_and_answer_coverage() {
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 8], [0u16; 2]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 10, 2).unwrap();
    let (red, blue) = (Colour::new(255, 0, 0), Colour::new(0, 0, 255));
    assert_eq!(m.span(0, 2, 4, red), 2);
    assert_eq!(m.span(0, 6, 8, red), 2);
    assert_eq!(m.nodes_used(), 2);
    // Bridges the two red intervals: one node, the other freed.
    assert_eq!(m.span(0, 3, 7, red), 2);
    assert!(well_formed(&m));
    assert!(m.covers(2, 0, 8, 1) && !m.covers(1, 0, 8, 1) && !m.covers(2, 0, 9, 1));
    // Another colour beside it: its own node, still one covered run.
    assert_eq!(m.span(0, 0, 10, blue), 4);
    assert!(m.covers(0, 0, 10, 1) && !m.covers(0, 0, 10, 2));
    assert!(m.is_full(1) && !m.is_full(2));
    let frame: Vec<u16> = m.pixels(7).collect();
    let (r, b) = (red.to_rgb565(), blue.to_rgb565());
    assert_eq!(frame[..10], [b, b, r, r, r, r, r, r, b, b]);
    assert!(frame[10..].iter().all(|&p| p == 7));
    assert_eq!(frame.len(), 20);
    // Spent: a span that needs a node is refused and the memory says so.
    let (mut nodes, mut heads) = ([ScanNode::EMPTY; 1], [0u16; 1]);
    let mut m = ScanMemory::new(&mut nodes, &mut heads, 10, 1).unwrap();
    assert_eq!(m.span(0, 0, 2, red), 2);
    assert_eq!(m.span(0, 2, 3, red), 1, "merged: no node needed");
    assert_eq!(m.span(0, 5, 6, red), 0);
    assert!(m.exhausted());
    assert!(ScanMemory::new(&mut [], &mut [0; 1], 10, 2).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random spans in random colours: the frame read out is the first colour written to
    /// each pixel, rows are well formed, coverage answers as the pixels do.
    #[test]
    fn spans_match_a_pixel_model(
        spans in proptest::collection::vec((0u32..6, 0u32..20, 0u32..22, 0u8..3), 0..80),
        query in (0u32..20, 0u32..6, 0u32..22, 0u32..7),
    ) {
        let (w, h) = (20, 6);
        let mut nodes = vec![ScanNode::EMPTY; 200];
        let mut heads = vec![0u16; h as usize];
        let mut m = ScanMemory::new(&mut nodes, &mut heads, w, h).unwrap();
        let mut model = Model::new(w, h);
        for &(y, a, b, c) in &spans {
            let colour = Colour::grey(c * 100);
            let want = if a < b { model.span(y, a, b, colour) } else { 0 };
            prop_assert_eq!(m.span(y, a, b, colour), want);
        }
        prop_assert!(well_formed(&m));
        prop_assert!(!m.exhausted());
        prop_assert_eq!(m.pixels(3).collect::<Vec<_>>(), model.image(3));
        let mut row = vec![0u16; w as usize];
        for y in 0..h {
            m.row_into(y, 3, &mut row);
            prop_assert_eq!(&row[..], &model.image(3)[(y * w) as usize..((y + 1) * w) as usize]);
        }
        let (x0, y0, x1, y1) = query;
        let covered = (y0..y1.min(h)).all(|y| {
            (x0..x1.min(w)).all(|x| model.pixels[(y * w + x) as usize].is_some()) && x1 <= w
        }) || x0 >= x1;
        prop_assert_eq!(m.covers(x0, y0, x1, y1), covered);
    }
}

/// Boxes along x, each a convex node, split planes between them, a colour per face.
fn boxes(items: &[(Vec3, f32)]) -> TestTree {
    let mut t = TestTree::default();
    fn build(t: &mut TestTree, items: &[(Vec3, f32)], base: u8) -> u32 {
        let (c, r) = items[0];
        let (lo, hi) = (c - Vec3::splat(r), c + Vec3::splat(r));
        if items.len() == 1 {
            let (first, count) = box_faces(t, lo, hi, Colour::default());
            for (k, p) in t.polygons[first as usize..].iter_mut().enumerate() {
                p.colour = Colour::new(base, 40 * k as u8, 255 - base);
            }
            return t.add_node(Node::Convex {
                first,
                count,
                child: None,
            });
        }
        let x = (hi.x + (items[1].0.x - items[1].1)) * 0.5;
        let plane = t.add_plane(Vec3::X, x);
        let i = t.add_node(Node::Convex {
            first: 0,
            count: 0,
            child: None,
        });
        let back = build(t, &items[..1], base);
        let front = build(t, &items[1..], base.wrapping_add(30));
        t.nodes[i as usize] = Node::Split {
            plane,
            front: Some(front),
            back: Some(back),
        };
        i
    }
    let mut sorted = items.to_vec();
    let mut x = -6.0f32;
    for item in &mut sorted {
        item.0.x = x + item.1;
        x += 2.0 * item.1 + 0.3;
    }
    build(&mut t, &sorted, 20);
    t
}

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(Pose::new(eye, DVec3::ZERO), 70.0, W, H, 0.05).unwrap()
}

/// The front-to-back frame into an RGB565 framebuffer with the background.
fn framebuffer_frame(t: &TestTree, cam: &Camera) -> Vec<u16> {
    let mut pixels = vec![0u16; (W * H) as usize];
    let mut fb = Rgb565Framebuffer::new(&mut pixels, W, H).unwrap();
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 32 * H as usize], vec![0u16; H as usize]);
    let mut ws = Workspace::<16, 12>::new();
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let stats = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND)
        .draw(t, &cam.view(t.centre()), &mut fb)
        .unwrap();
    assert!(!stats.fallback);
    pixels
}

/// Rows in order, each once, each `W` pixels: panics otherwise.
struct Rows {
    next: u32,
    image: Vec<u16>,
}

impl Rows {
    fn row(&mut self, y: u32, pixels: &[u16]) {
        assert_eq!(y, self.next, "rows out of order");
        assert_eq!(pixels.len(), W as usize);
        self.image.extend_from_slice(pixels);
        self.next += 1;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Random boxes and eyes: the scan-order frame is the framebuffer's, pixel for pixel,
    /// read as one run or row by row.
    #[test]
    fn scan_order_is_the_framebuffer_frame(
        sizes in proptest::collection::vec((0.3f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 1..5),
        eye in (-9.0f64..9.0, -6.0f64..6.0, 3.0f64..12.0),
    ) {
        let items: Vec<(Vec3, f32)> =
            sizes.iter().map(|&(r, y, z)| (Vec3::new(0.0, y, z), r)).collect();
        let t = boxes(&items);
        let cam = camera(DVec3::new(eye.0, eye.1, eye.2));
        let reference = framebuffer_frame(&t, &cam);
        let mut nodes = vec![ScanNode::EMPTY; 2048];
        let mut heads = vec![0u16; H as usize];
        let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut renderer = Renderer::new(&mut ws).scan_memory(memory).background(BACKGROUND);
        for _ in 0..2 {
            // Twice: the memory is cleared between frames.
            let frame = renderer.draw_scan(&t, &cam.view(t.centre())).unwrap();
            prop_assert!(!frame.stats().fallback);
            prop_assert_eq!(frame.pixels().collect::<Vec<_>>(), reference.clone());
            let mut rows = Rows { next: 0, image: Vec::new() };
            let mut buffer = [0u16; W as usize];
            for y in 0..frame.height() {
                frame.row_into(y, &mut buffer);
                rows.row(y, &buffer);
            }
            prop_assert_eq!(&rows.image, &reference);
            let used = frame.nodes_used();
            // Exactly that much memory is enough; one node less is an error.
            let mut nodes = vec![ScanNode::EMPTY; used];
            let mut heads = vec![0u16; H as usize];
            let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
            let mut ws = Workspace::<16, 12>::new();
            let mut exact = Renderer::new(&mut ws).scan_memory(memory).background(BACKGROUND);
            let pixels: Vec<u16> = exact.draw_scan(&t, &cam.view(t.centre())).unwrap().pixels().collect();
            prop_assert_eq!(pixels, reference.clone());
            if used > 0 {
                let mut nodes = vec![ScanNode::EMPTY; used - 1];
                let mut heads = vec![0u16; H as usize];
                let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
                let mut ws = Workspace::<16, 12>::new();
                let mut short = Renderer::new(&mut ws).scan_memory(memory);
                prop_assert_eq!(
                    short.draw_scan(&t, &cam.view(t.centre())).err(),
                    Some(RenderError::ScanMemoryFull { nodes: used as u32 - 1 })
                );
            }
        }
    }
}

#[test]
fn never_back_to_front() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5)]);
    let view = camera(DVec3::new(0.5, 2.0, 9.0)).view(t.centre());
    let mut ws = Workspace::<16, 12>::new();
    // No scan memory.
    let mut r = Renderer::new(&mut ws);
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::NotFrontToBack)
    );
    // Back to front asked for.
    let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
    let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory).back_to_front();
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::NotFrontToBack)
    );
    // Memory of another size.
    let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
    let memory = ScanMemory::new(&mut nodes, &mut heads, W - 1, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory);
    assert_eq!(r.draw_scan(&t, &view).err(), Some(RenderError::SpanMemory));
    // No nodes at all.
    let mut heads = vec![0u16; H as usize];
    let memory = ScanMemory::new(&mut [], &mut heads, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).scan_memory(memory);
    assert_eq!(
        r.draw_scan(&t, &view).err(),
        Some(RenderError::ScanMemoryFull { nodes: 0 })
    );
}

/// A sink that must be written once per pixel, streamed.
struct Display {
    written: Vec<bool>,
}

impl SpanSink for Display {
    fn span(&mut self, y: u32, a: u32, b: u32, _: Colour) {
        for x in a..b {
            let p = &mut self.written[(y * W + x) as usize];
            assert!(!*p, "overdraw at ({x}, {y})");
            *p = true;
        }
    }

    fn write_once(&self) -> bool {
        true
    }
}

#[test]
fn a_streamed_display_is_never_painted_back_to_front() {
    let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5), (Vec3::ZERO, 0.7)]);
    let view = camera(DVec3::new(0.5, 2.0, 9.0)).view(t.centre());
    let mut display = Display {
        written: vec![false; (W * H) as usize],
    };
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws).background(BACKGROUND);
    assert_eq!(
        r.draw(&t, &view, &mut display).err(),
        Some(RenderError::NotFrontToBack)
    );
    assert!(
        display.written.iter().all(|&w| !w),
        "refused before any pixel"
    );
    // Too little span memory: it stops where it ran out, with no overdraw.
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); H as usize], vec![0u16; H as usize]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND);
    assert_eq!(
        r.draw(&t, &view, &mut display).err(),
        Some(RenderError::SpanMemoryFull)
    );
    // Enough: every pixel once.
    display.written.fill(false);
    let (mut intervals, mut counts) = (vec![(0u16, 0u16); 16 * H as usize], vec![0u16; H as usize]);
    let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
    let mut ws = Workspace::<16, 12>::new();
    let mut r = Renderer::new(&mut ws)
        .span_memory(coverage)
        .background(BACKGROUND);
    r.draw(&t, &view, &mut display).unwrap();
    assert!(display.written.iter().all(|&w| w));
}

#[cfg(feature = "embedded-graphics")]
mod embedded {
    use super::*;
    use embedded_graphics_core::draw_target::DrawTarget;
    use embedded_graphics_core::geometry::{OriginDimensions, Size};
    use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565};
    use embedded_graphics_core::primitives::Rectangle;
    use embedded_graphics_core::Pixel;

    /// A panel that takes exactly one window, the whole screen, and panics on anything else.
    struct Panel {
        windows: usize,
        pixels: Vec<u16>,
    }

    impl OriginDimensions for Panel {
        fn size(&self) -> Size {
            Size::new(W, H)
        }
    }

    impl DrawTarget for Panel {
        type Color = Rgb565;
        type Error = core::convert::Infallible;

        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            _: I,
        ) -> Result<(), Self::Error> {
            panic!("a scan-order frame is one window, not pixels");
        }

        fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
            &mut self,
            area: &Rectangle,
            colours: I,
        ) -> Result<(), Self::Error> {
            self.windows += 1;
            assert_eq!(self.windows, 1, "one window a frame");
            assert_eq!(*area, self.bounding_box_of());
            self.pixels
                .extend(colours.into_iter().map(|c| c.into_storage()));
            Ok(())
        }
    }

    impl Panel {
        fn bounding_box_of(&self) -> Rectangle {
            Rectangle::new(Default::default(), self.size())
        }
    }

    #[test]
    fn one_window_in_scan_order() {
        let t = boxes(&[(Vec3::ZERO, 1.0), (Vec3::ZERO, 1.5)]);
        let cam = camera(DVec3::new(-7.0, 1.0, 3.0));
        let reference = framebuffer_frame(&t, &cam);
        let (mut nodes, mut heads) = (vec![ScanNode::EMPTY; 512], vec![0u16; H as usize]);
        let memory = ScanMemory::new(&mut nodes, &mut heads, W, H).unwrap();
        let mut ws = Workspace::<16, 12>::new();
        let mut r = Renderer::new(&mut ws)
            .scan_memory(memory)
            .background(BACKGROUND);
        let frame = r.draw_scan(&t, &cam.view(t.centre())).unwrap();
        let mut panel = Panel {
            windows: 0,
            pixels: Vec::new(),
        };
        frame.draw_to(&mut panel).unwrap();
        assert_eq!(panel.pixels, reference);
    }
}
