use super::*;
use crate::fill::SubpixelPoint;

/// A point the memory can keep (coordinates in `0..2^24`).
fn point(v: i32) -> SubpixelPoint {
    FixedPoint::new(v, 2 * v)
}

/// Calls `get` for `index` and says whether `compute` (giving `point(value)`) ran.
fn computed(cache: &mut VertexCache<'_>, index: u32, value: i32) -> (SubpixelPoint, bool) {
    computed_point(cache, index, point(value))
}

/// Calls `get` for `index` and says whether `compute` (giving `p`) ran.
fn computed_point(
    cache: &mut VertexCache<'_>,
    index: u32,
    p: SubpixelPoint,
) -> (SubpixelPoint, bool) {
    let mut ran = false;
    let got = cache.get(index, || {
        ran = true;
        p
    });
    (got, ran)
}

#[test]
fn computed_once_per_frame() {
    let mut memory = [CachedVertex::EMPTY; 4];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    assert_eq!(computed(&mut cache, 2, 7), (point(7), true));
    assert_eq!(computed(&mut cache, 2, 8), (point(7), false));
    assert_eq!(computed(&mut cache, 2, 9), (point(7), false));
    // A new frame recomputes (the camera may have moved).
    cache.next_frame();
    assert_eq!(computed(&mut cache, 2, 9), (point(9), true));
    assert_eq!(computed(&mut cache, 2, 1), (point(9), false));
}

#[test]
fn vertices_sharing_an_entry_replace_each_other() {
    let mut memory = [CachedVertex::EMPTY; 4];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    // 1 and 5 share entry 1 of 4; 2 has its own.
    assert_eq!(computed(&mut cache, 1, 10), (point(10), true));
    assert_eq!(computed(&mut cache, 2, 20), (point(20), true));
    assert_eq!(computed(&mut cache, 5, 50), (point(50), true));
    assert_eq!(computed(&mut cache, 1, 11), (point(11), true));
    assert_eq!(computed(&mut cache, 2, 21), (point(20), false));
}

#[test]
fn only_a_power_of_two_of_the_memory_is_used() {
    let mut memory = [CachedVertex::EMPTY; 6];
    let cache: VertexCache<'_> = VertexCache::new(&mut memory);
    assert_eq!(cache.len(), 4);
    let mut none: [CachedVertex; 0] = [];
    let mut cache = VertexCache::new(&mut none);
    assert!(cache.is_empty());
    cache.next_frame();
    assert_eq!(computed(&mut cache, 0, 3), (point(3), true));
    assert_eq!(computed(&mut cache, 0, 4), (point(4), true));
}

#[test]
fn a_new_cache_clears_what_another_left() {
    let mut memory = [CachedVertex::EMPTY; 2];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    cache.get(0, || point(3));
    // The same memory in a new cache: the old entry must not count.
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    assert_eq!(computed(&mut cache, 0, 8), (point(8), true));
}

#[test]
fn the_empty_marker_is_never_a_hit() {
    let mut memory = [CachedVertex::EMPTY; 2];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    assert_eq!(computed(&mut cache, u32::MAX, 3), (point(3), true));
    assert_eq!(computed(&mut cache, u32::MAX, 4), (point(4), true));
}

#[test]
fn an_entry_takes_eight_bytes() {
    assert_eq!(core::mem::size_of::<CachedVertex>(), 8);
}

#[test]
fn an_empty_entry_is_never_a_hit() {
    let mut memory = [CachedVertex::EMPTY; 4];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    // An empty entry is all zeros: vertex 0 is not in it.
    assert_eq!(computed(&mut cache, 0, 3), (point(3), true));
    // Index over entries 255 and 256: their tags would not fit in 8 bits, never kept.
    for index in [255 << 2, 256 << 2] {
        assert_eq!(computed(&mut cache, index, 5), (point(5), true));
        assert_eq!(computed(&mut cache, index, 6), (point(6), true));
    }
    // The largest tag kept.
    assert_eq!(computed(&mut cache, 254 << 2 | 1, 7), (point(7), true));
    assert_eq!(computed(&mut cache, 254 << 2 | 1, 8), (point(7), false));
}

#[test]
fn points_with_x_outside_24_bits_are_not_kept() {
    let mut memory = [CachedVertex::EMPTY; 4];
    let mut cache = VertexCache::new(&mut memory);
    cache.next_frame();
    // Whether the second call for `index` finds what the first computed.
    let mut keep = |index, p: SubpixelPoint| {
        assert_eq!(computed_point(&mut cache, index, p).0, p);
        computed_point(&mut cache, index, p) == (p, false)
    };
    assert!(keep(0, FixedPoint::new(0, 0)));
    assert!(keep(1, FixedPoint::new(0xff_ffff, i32::MIN)));
    assert!(!keep(2, FixedPoint::new(0x100_0000, 0)));
    assert!(!keep(3, FixedPoint::new(-1, 0)));
    // A point not kept leaves the entry's vertex where it was.
    assert!(keep(5, FixedPoint::new(4, 4)));
    assert!(!keep(9, FixedPoint::new(-4, 4)));
    let before = computed_point(&mut cache, 5, FixedPoint::new(0, 0));
    assert_eq!(before, (FixedPoint::new(4, 4), false));
}
