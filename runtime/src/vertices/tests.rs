use super::*;
use crate::fill::SubpixelPoint;

fn point(v: i32) -> SubpixelPoint {
    FixedPoint::new(v, -v)
}

#[test]
fn computed_once_per_frame() {
    let mut memory = [CachedVertex::EMPTY; 4];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    let mut calls = 0;
    for _ in 0..3 {
        let p = cache.get(2, || {
            calls += 1;
            point(7)
        });
        assert_eq!(p, point(7));
    }
    assert_eq!(calls, 1);
    // A new frame recomputes (the camera may have moved).
    cache.next_frame();
    assert_eq!(cache.get(2, || point(9)), point(9));
    assert_eq!(cache.get(2, || point(1)), point(9));
}

#[test]
fn out_of_range_vertices_are_computed_every_time() {
    let mut memory = [CachedVertex::EMPTY; 2];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    assert_eq!(cache.get(5, || point(3)), point(3));
    assert_eq!(cache.get(5, || point(4)), point(4));
    assert_eq!(cache.len(), 2);
}

#[test]
fn a_new_cache_clears_what_another_left() {
    let mut memory = [CachedVertex::EMPTY; 2];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    cache.get(0, || point(3));
    // The same memory in a new cache starts again at frame 1: the old entry must not count.
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    assert_eq!(cache.get(0, || point(8)), point(8));
}

#[test]
fn the_frame_number_wraps_with_a_clear() {
    let mut memory = [CachedVertex::EMPTY; 2];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame(); // frame 1
    assert_eq!(cache.get(1, || point(5)), point(5));
    // 2^32 - 1 frames later the number is 1 again: the entry of the first frame 1 must not
    // count.
    cache.set_frame(u32::MAX);
    cache.next_frame();
    assert_eq!(cache.get(1, || point(6)), point(6));
}
