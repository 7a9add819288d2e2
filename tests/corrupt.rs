//! Corrupt files: compiled fixtures (with ids) mutated at random — bit flips, truncation,
//! `u32`/`u64` fields overwritten with random or boundary values, splices of two files — then
//! read by the runtime and, when the reader accepts them, rendered from three cameras in both
//! orders. Nothing may panic; the reader must reject what is broken with a typed error, and a
//! file it accepts must render or be refused with a typed error that names a real limit.

use std::cell::Cell;
use std::path::Path;

use glam::{DVec3, Vec3};
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::load_obj;
use peel_runtime::camera::{Camera, Pose};
use peel_runtime::coverage::Coverage;
use peel_runtime::display::{Colour, SpanSink};
use peel_runtime::read::layout::{HEADER_SIZE, MAGIC};
use peel_runtime::read::{Node, Scene};
use peel_runtime::render::{Paint, Renderer, Workspace};
use peel_runtime::traverse::Order;
use peel_runtime::vertices::{CachedVertex, VertexCache};
use peel_runtime::{ReadError, RenderError};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestCaseError, TestRunner};

const W: u32 = 32;
const H: u32 = 24;
/// Traversal stack of the test's workspace (the fixtures need at most 25).
const STACK: usize = 64;
/// Clip buffer vertices (the fill's maximum).
const VERTS: usize = 64;
/// Mutated files per run (about a second in release).
const CASES: u32 = 30_000;

/// The fixtures compiled with ids: every encoding the writer picks for small scenes (RGB
/// colours, `u8` palette, node bounds, `u16` indices) and trees with and without splits.
fn fixtures() -> Vec<Vec<u8>> {
    let options = CompileOptions {
        ids: true,
        ..CompileOptions::default()
    };
    [
        "triangle.obj",
        "cube.obj",
        "interpenetrating_boxes.obj",
        "demo.obj",
    ]
    .iter()
    .map(|name| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fixtures")
            .join(name);
        let mesh = load_obj(&path).expect("load fixture");
        let bytes = compile_mesh(&mesh, &options, &|_| {}).expect("compile").1;
        Scene::parse(&bytes).expect("a compiled fixture parses");
        bytes
    })
    .collect()
}

/// Values that sit on the edges of what a count, an index, a depth or a length can be.
fn boundary_u64() -> impl Strategy<Value = u64> {
    prop_oneof![
        Just(0u64),
        Just(1),
        Just(2),
        Just(0xff),
        Just(0xffff),
        Just(0x1_0000),
        Just(u64::from(u32::MAX) - 1),
        Just(u64::from(u32::MAX)),
        Just(1 << 32),
        Just(i64::MAX as u64),
        Just(u64::MAX),
        0u64..300,
        any::<u64>(),
    ]
}

/// One change to a file.
#[derive(Debug, Clone)]
enum Mutation {
    /// Flip bit `bit` of the byte at `at`.
    FlipBit { at: Index, bit: u8 },
    /// Keep only the first `len` bytes (fewer than the file has).
    Truncate { len: Index },
    /// Overwrite the (possibly unaligned) `u32` at `at`, `in_header` choosing the header.
    U32 {
        at: Index,
        in_header: bool,
        value: u32,
    },
    /// Overwrite the `u64` at `at` (array lengths and the centre's `f64`s are `u64`-sized).
    U64 { at: Index, value: u64 },
    /// The first `head` bytes of this file followed by the bytes of fixture `other` from
    /// `tail` on.
    Splice {
        head: Index,
        other: Index,
        tail: Index,
    },
    /// Copy `len` bytes of the file from `from` over the bytes at `to`.
    CopyWithin { from: Index, to: Index, len: u8 },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<Index>(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        2 => any::<Index>().prop_map(|len| Mutation::Truncate { len }),
        3 => (any::<Index>(), any::<bool>(), boundary_u64())
            .prop_map(|(at, in_header, v)| Mutation::U32 { at, in_header, value: v as u32 }),
        2 => (any::<Index>(), boundary_u64()).prop_map(|(at, value)| Mutation::U64 { at, value }),
        1 => (any::<Index>(), any::<Index>(), any::<Index>())
            .prop_map(|(head, other, tail)| Mutation::Splice { head, other, tail }),
        1 => (any::<Index>(), any::<Index>(), 1u8..32)
            .prop_map(|(from, to, len)| Mutation::CopyWithin { from, to, len }),
    ]
}

fn put(bytes: &mut [u8], at: usize, value: &[u8]) {
    let at = at.min(bytes.len());
    let end = (at + value.len()).min(bytes.len());
    let n = end - at;
    bytes[at..end].copy_from_slice(&value[..n]);
}

/// Apply `m` to `bytes`; `all` holds every fixture (splices take from them).
fn apply(bytes: &mut Vec<u8>, m: &Mutation, all: &[Vec<u8>]) {
    let len = bytes.len();
    if len == 0 && !matches!(m, Mutation::Splice { .. }) {
        return;
    }
    match *m {
        Mutation::FlipBit { at, bit } => bytes[at.index(len)] ^= 1 << bit,
        Mutation::Truncate { len: keep } => bytes.truncate(keep.index(len)),
        Mutation::U32 {
            at,
            in_header,
            value,
        } => {
            let at = if in_header {
                // The header's fields are `u32`-aligned from byte 8.
                8 + 4 * at.index((HEADER_SIZE - 8) / 4)
            } else {
                at.index(len)
            };
            put(bytes, at, &value.to_le_bytes());
        }
        Mutation::U64 { at, value } => put(bytes, at.index(len), &value.to_le_bytes()),
        Mutation::Splice { head, other, tail } => {
            let other = &all[other.index(all.len())];
            bytes.truncate(head.index(len + 1));
            bytes.extend_from_slice(&other[tail.index(other.len() + 1)..]);
        }
        Mutation::CopyWithin { from, to, len: n } => {
            let from = from.index(len);
            let n = usize::from(n).min(len - from);
            let to = to.index(len - n + 1);
            bytes.copy_within(from..from + n, to);
        }
    }
}

/// A framebuffer that checks every span is inside the image and not empty, and counts
/// writes per pixel (no colour limit: id images have many).
struct Frame {
    pixels: Vec<Colour>,
    writes: Vec<u32>,
}

impl Frame {
    fn new() -> Self {
        let n = (W * H) as usize;
        Frame {
            pixels: vec![Colour::default(); n],
            writes: vec![0; n],
        }
    }
    fn total_writes(&self) -> u64 {
        self.writes.iter().map(|&w| u64::from(w)).sum()
    }
    fn distinct(&self) -> u64 {
        self.writes.iter().filter(|&&w| w > 0).count() as u64
    }
}

impl SpanSink for Frame {
    fn span(&mut self, y: u32, x_start: u32, x_end: u32, colour: Colour) {
        assert!(
            y < H && x_start < x_end && x_end <= W,
            "span y={y} x={x_start}..{x_end} outside the {W}x{H} image or empty"
        );
        for x in x_start..x_end {
            let i = (y * W + x) as usize;
            self.pixels[i] = colour;
            self.writes[i] += 1;
        }
    }
}

/// The refusals a validated file may still earn, checked to be true.
fn check_refusal(e: RenderError, scene: &Scene<'_>, paint: Paint) -> Result<(), TestCaseError> {
    let h = scene.header();
    match e {
        RenderError::StackTooSmall { needed, available } => {
            prop_assert_eq!(available as usize, STACK);
            prop_assert!(needed > available && needed <= h.max_depth, "{:?}", e);
        }
        RenderError::PolygonTooLarge { needed, available } => {
            prop_assert!(needed > available, "{:?}", e);
            prop_assert!(
                h.max_polygon_vertices as usize + 5 > VERTS,
                "{:?} {:?}",
                e,
                h
            );
        }
        RenderError::NoIds => prop_assert_eq!(paint, Paint::Ids),
        other => prop_assert!(false, "a validated file refused with {:?}", other),
    }
    prop_assert!(!e.to_string().is_empty());
    Ok(())
}

/// Every accessor over every record of an accepted file (they must not panic either).
fn read_everything(scene: &Scene<'_>) {
    let h = scene.header();
    let _ = scene.root();
    for i in 0..h.node_count {
        let _ = scene.parent(i);
        let _ = scene.node_bounds(i);
        if let Node::Split { plane, .. } = scene.node(i) {
            let _ = scene.plane(plane);
        }
    }
    for i in 0..h.polygon_count {
        let p = scene.polygon(i);
        let _ = scene.eye_side(&p, &scene.side_eye(Vec3::new(0.5, -1.0, 2.0)));
        let _ = scene.id(i);
        for k in 0..u32::from(p.vertex_count) {
            let _ = scene.polygon_vertex(&p, k);
        }
    }
    for i in 0..h.vertex_count {
        let _ = scene.vertex(i);
    }
}

/// Render `scene` from three cameras: back to front and front to back without culling (the
/// same image: one order is the exact reverse of the other), front to back with culling, and
/// an id image. Returns how many frames were drawn.
fn render_all(scene: &Scene<'_>) -> Result<usize, TestCaseError> {
    let h = scene.header();
    let centre = DVec3::from_array(h.centre);
    let (lo, hi) = (h.bounds_min.as_dvec3(), h.bounds_max.as_dvec3());
    let size = (hi - lo).length();
    let size = if size.is_finite() && size > 1e-6 {
        size.min(1e12)
    } else {
        1.0
    };
    let mid = centre + (lo + hi) * 0.5;
    let mid = if mid.is_finite() { mid } else { centre };
    // `Camera::default_near` of the clamped size: bounds of a subnormal extent are valid
    // (16-bit vertices always lie inside them) but would give a near distance of zero in f32.
    let near = size * 1e-3;
    let mut workspace: Box<Workspace<STACK, VERTS>> = Box::default();
    let mut intervals = vec![(0u16, 0u16); 16 * H as usize];
    let mut counts = vec![0u16; H as usize];
    let mut drawn = 0;
    for (k, offset) in [
        DVec3::new(1.3, 0.9, 2.1),
        DVec3::new(-0.2, 0.05, 0.1),
        DVec3::new(0.4, -1.7, -0.6),
    ]
    .into_iter()
    .enumerate()
    {
        let Ok(camera) = Camera::look_at(
            Pose::new(
                mid + offset * size,
                mid + DVec3::new(0.01, 0.02, 0.0) * size,
            ),
            60.0,
            W,
            H,
            near,
        ) else {
            // Only absurd (corrupt) centres or bounds make the camera unusable.
            continue;
        };
        let mut images = Vec::new();
        let mut memory =
            vec![CachedVertex::EMPTY; (scene.header().vertex_count as usize).min(1 << 20)];
        for (order, cull, paint) in [
            (Order::BackToFront, false, Paint::Colours),
            (Order::FrontToBack, false, Paint::Colours),
            (Order::FrontToBack, true, Paint::Colours),
            (Order::BackToFront, true, Paint::Ids),
        ] {
            let coverage = Coverage::new(&mut intervals, &mut counts, W, H).unwrap();
            let mut frame = Frame::new();
            let options = (order, paint, cull);
            let mut renderer = Renderer::new(&mut workspace)
                .span_memory(coverage)
                .vertex_memory(VertexCache::new(&mut memory));
            if order == Order::BackToFront {
                renderer = renderer.back_to_front();
            }
            if paint == Paint::Ids {
                renderer = renderer.ids();
            }
            if !cull {
                renderer = renderer.without_culling();
            }
            let result = renderer.draw(scene, &camera.view(scene.header().centre), &mut frame);
            match result {
                Ok(stats) => {
                    drawn += 1;
                    prop_assert_eq!(stats.pixels_written, frame.total_writes());
                    prop_assert!(stats.polygons_drawn <= stats.polygons_visited);
                    if let Some(d) = stats.distinct_pixels {
                        prop_assert_eq!(d, frame.distinct(), "camera {} {:?}", k, options);
                    }
                    if order == Order::FrontToBack && !stats.fallback {
                        prop_assert!(
                            frame.writes.iter().all(|&w| w <= 1),
                            "front to back wrote a pixel twice: camera {} {:?}",
                            k,
                            stats
                        );
                    }
                    if !cull {
                        images.push(frame.pixels);
                    }
                }
                Err(e) => {
                    prop_assert!(frame.total_writes() == 0, "{:?} after drawing", e);
                    check_refusal(e, scene, paint)?;
                }
            }
        }
        if let [a, b] = &images[..] {
            let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
            prop_assert_eq!(differ, 0, "camera {}: the two orders disagree", k);
        }
    }
    Ok(drawn)
}

/// Found by the mutation test: bounds collapsed to a subnormal extent. The file is valid (its
/// 16-bit vertices decode inside any bounds); it must read and draw like any other.
#[test]
fn bounds_of_a_subnormal_extent_read_and_draw() {
    let mut bytes = fixtures().swap_remove(0);
    let at = 60; // bounds_min, then bounds_max (formats/peel.md, "Header")
    let corners = [0.0, 0.0, 0.0, 0.0, 0.0, f32::from_bits(256)]; // 3.6e-43
    for (k, c) in corners.iter().enumerate() {
        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&c.to_le_bytes());
    }
    let scene = Scene::parse(&bytes).expect("valid");
    read_everything(&scene);
    render_all(&scene).expect("drawn or refused for a true reason");
}

#[test]
fn mutated_files_are_rejected_or_render_without_panicking() {
    let files = fixtures();
    let rejected = Cell::new(0usize);
    let accepted = Cell::new(0usize);
    let frames = Cell::new(0usize);
    let mut runner = TestRunner::new(Config {
        cases: CASES,
        failure_persistence: None,
        ..Config::default()
    });
    let strategy = (any::<Index>(), prop::collection::vec(mutation(), 1..4));
    runner
        .run(&strategy, |(which, mutations)| {
            let original = &files[which.index(files.len())];
            let mut bytes = original.clone();
            for m in &mutations {
                apply(&mut bytes, m, &files);
            }
            match Scene::parse(&bytes) {
                Err(e) => {
                    rejected.set(rejected.get() + 1);
                    prop_assert!(!e.to_string().is_empty());
                    // A file cut short is never read as complete.
                    if bytes.len() < original.len() && original.starts_with(&bytes) {
                        prop_assert!(
                            matches!(e, ReadError::Truncated { .. }),
                            "a prefix of {} bytes: {:?}",
                            bytes.len(),
                            e
                        );
                    }
                    if bytes.len() >= 4 && bytes[..4] != MAGIC {
                        prop_assert_eq!(e, ReadError::BadMagic);
                    }
                }
                Ok(scene) => {
                    accepted.set(accepted.get() + 1);
                    prop_assert!(
                        bytes.len() >= original.len() || !original.starts_with(&bytes),
                        "a strict prefix of a file was accepted"
                    );
                    read_everything(&scene);
                    frames.set(frames.get() + render_all(&scene)?);
                }
            }
            Ok(())
        })
        .unwrap();
    let (rejected, accepted, frames) = (rejected.get(), accepted.get(), frames.get());
    eprintln!("corrupt files: {rejected} rejected, {accepted} accepted, {frames} frames drawn");
    // The generator must exercise the validator, and leave files that still parse (which the
    // renderer then has to cope with).
    let cases = CASES as usize;
    assert!(
        rejected >= cases / 4,
        "only {rejected} of {cases} mutated files were rejected"
    );
    assert!(
        accepted >= cases / 50,
        "only {accepted} of {cases} mutated files parsed"
    );
    assert!(frames > 0);
}

/// Each kind of mutation on its own: the validator rejects some of each kind.
#[test]
fn every_kind_of_mutation_is_caught_sometimes() {
    let files = fixtures();
    let demo = files.last().unwrap();
    let mut runner = TestRunner::deterministic();
    let kinds = ["flip", "truncate", "u32", "u64", "splice", "copy"];
    let mut rejected = [0usize; 6];
    for _ in 0..2000 {
        let m = mutation().new_tree(&mut runner).unwrap().current();
        let kind = match m {
            Mutation::FlipBit { .. } => 0,
            Mutation::Truncate { .. } => 1,
            Mutation::U32 { .. } => 2,
            Mutation::U64 { .. } => 3,
            Mutation::Splice { .. } => 4,
            Mutation::CopyWithin { .. } => 5,
        };
        let mut bytes = demo.clone();
        apply(&mut bytes, &m, &files);
        if Scene::parse(&bytes).is_err() {
            rejected[kind] += 1;
        }
    }
    for (kind, n) in kinds.iter().zip(rejected) {
        assert!(n > 0, "no {kind} mutation was rejected: {rejected:?}");
    }
}
