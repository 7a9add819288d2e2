//! Lopsided free splits taken in a batch.
//!
//! On a nearly convex mesh (a finely tessellated sphere whose quads fold very slightly inward
//! once quantised) no support plane divides the list evenly: each plane only splits off its
//! own fold, a handful of fragments, and the tree is a chain as deep as there are folds.
//! Choosing those splits one node at a time costs a pass over the whole list per fold
//! (quadratic; BENCHMARKS.md, "Nearly convex meshes", has the figures). Once [`CHAIN_AFTER`]
//! splits in a row are that lopsided, [`lopsided_splits`] finds in one pass every support plane
//! that cuts nothing and leaves at most [`TOUCH_MAX`] fragments off its far side, and keeps
//! those whose fragments are disjoint. Each of them is then a proper split of what the earlier ones leave
//! (a fragment wholly on one closed side of a plane stays there once others are removed), so
//! the build lays them out as a chain without looking at the rest of the list again.

use crate::planes::{PlaneId, PlaneTable, Side};

use super::{Fragment, Sample};

/// Most fragments a lopsided split may touch: on its plane, on its small side, or cut.
pub const TOUCH_MAX: usize = 16;

/// Fewest fragments of a list for the batch to pay (below, splits are chosen one at a time).
pub const MIN_FRAGMENTS: usize = 512;

/// Lopsided splits in a row before the batch is looked for: a lone lopsided split (common in
/// scanned meshes, where the batch finds little) does not pay for a pass over every plane.
pub const CHAIN_AFTER: u32 = 8;

/// A lopsided free split of a list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Lopsided {
    /// The split plane (a support plane of the list).
    pub plane: PlaneId,
    /// The side holding few fragments (`Front` or `Back`).
    pub small: Side,
    /// Indices into the list of the fragments it touches (in its plane or on the small side),
    /// ascending; every other fragment lies on the far closed side.
    pub touched: Vec<u32>,
}

/// True when a split of `n` fragments leaving `small` on its smaller side, `on` in its plane
/// and making `cuts` is lopsided (touches at most [`TOUCH_MAX`]): the build then looks for
/// more such splits, free ones, with [`lopsided_splits`].
pub fn is_lopsided(n: usize, small: usize, on: usize, cuts: usize) -> bool {
    n >= MIN_FRAGMENTS && small + on + cuts <= TOUCH_MAX
}

/// The lopsided free splits of `frags` (their distinct support planes `planes`, sorted) that
/// can be taken one after the other: each cuts nothing and touches at most [`TOUCH_MAX`]
/// fragments, none touched by an earlier one, and at least half the list is left untouched.
/// In the order the build's rule would take them (`|front − back|` on the whole list, then
/// plane id).
pub fn lopsided_splits(
    frags: &[Fragment],
    planes: &[PlaneId],
    table: &PlaneTable,
) -> Vec<Lopsided> {
    let sample = Sample::new(frags.iter());
    // The sample numbers fragments in its own order: their positions in `frags`, from their
    // addresses (the sample borrows them from the slice).
    let size = std::mem::size_of::<Fragment>();
    let base = frags.as_ptr() as usize;
    let index: Vec<u32> = sample
        .leaf_order()
        .iter()
        .map(|&f| ((f as *const Fragment as usize - base) / size) as u32)
        .collect();
    let n = frags.len() as u64;
    let mut found: Vec<(u64, Lopsided)> = Vec::new();
    let mut touched = Vec::with_capacity(TOUCH_MAX + 1);
    for &plane in planes {
        for small in [Side::Front, Side::Back] {
            let Some(t) = sample.touched(plane, small, table, TOUCH_MAX, &mut touched) else {
                continue;
            };
            let near = if small == Side::Front {
                t.front
            } else {
                t.back
            };
            let on = touched.len() as u64 - near;
            // A plane in which nothing lies is not a support plane here, and one with nothing
            // off it is on the hull (nothing to split off).
            if on == 0 || near == 0 {
                continue;
            }
            // The build's cost of a free split: its imbalance (the plane's fragments count on
            // neither side).
            let cost = (n - on - near).abs_diff(near);
            let mut touched: Vec<u32> = touched.iter().map(|&i| index[i as usize]).collect();
            touched.sort_unstable();
            found.push((
                cost,
                Lopsided {
                    plane,
                    small,
                    touched,
                },
            ));
            break;
        }
    }
    found.sort_by_key(|(cost, s)| (*cost, s.plane));
    let mut used = vec![false; frags.len()];
    let mut left = frags.len();
    let mut taken = Vec::new();
    for (_, s) in found {
        if s.touched.iter().any(|&i| used[i as usize]) || 2 * (left - s.touched.len()) < frags.len()
        {
            continue;
        }
        for &i in &s.touched {
            used[i as usize] = true;
        }
        left -= s.touched.len();
        taken.push(s);
    }
    taken
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::split::{triangle_fragment, Placement};
    use proptest::prelude::*;

    /// Placement of every fragment against every plane, by brute force.
    fn naive_touched(
        frags: &[Fragment],
        plane: PlaneId,
        small: Side,
        table: &PlaneTable,
    ) -> Vec<u32> {
        (0..frags.len() as u32)
            .filter(|&i| {
                let p = frags[i as usize].placement(plane, table);
                !matches!(
                    (p, small),
                    (Placement::Back, Side::Front) | (Placement::Front, Side::Back)
                )
            })
            .collect()
    }

    fn soup(tris: &[[[i32; 3]; 3]]) -> (PlaneTable, Vec<Fragment>, Vec<PlaneId>) {
        let mut table = PlaneTable::default();
        let frags: Vec<Fragment> = tris
            .iter()
            .filter_map(|&t| triangle_fragment(&mut table, t))
            .collect();
        let mut planes: Vec<PlaneId> = frags.iter().map(|f| f.support).collect();
        planes.sort_unstable();
        planes.dedup();
        (table, frags, planes)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// Every split returned cuts nothing and touches exactly the fragments a brute-force
        /// placement says (at most `TOUCH_MAX`, one of them in its plane, one not), no two
        /// share a fragment, at least half the list is untouched, and no free lopsided plane
        /// was left out that could have been taken.
        #[test]
        fn splits_are_exact_disjoint_and_ordered(
            tris in prop::collection::vec(prop::array::uniform3(prop::array::uniform3(-40i32..40)), 20..120)
        ) {
            let (table, frags, planes) = soup(&tris);
            let splits = lopsided_splits(&frags, &planes, &table);
            let mut seen = vec![false; frags.len()];
            let mut touched = 0;
            for s in &splits {
                prop_assert_eq!(&s.touched, &naive_touched(&frags, s.plane, s.small, &table));
                prop_assert!(s.touched.len() <= TOUCH_MAX);
                prop_assert!(s.touched.iter().any(|&i| frags[i as usize].support == s.plane));
                prop_assert!(s.touched.iter().any(|&i| frags[i as usize].support != s.plane));
                let free = s
                    .touched
                    .iter()
                    .all(|&i| frags[i as usize].placement(s.plane, &table) != Placement::Straddle);
                prop_assert!(free);
                for &i in &s.touched {
                    prop_assert!(!seen[i as usize], "fragment {i} touched twice");
                    seen[i as usize] = true;
                }
                touched += s.touched.len();
            }
            prop_assert!(2 * (frags.len() - touched) >= frags.len());
            // Every plane left out is either not lopsided or overlaps a split taken (the
            // search tries the + side first).
            for &p in &planes {
                if splits.iter().any(|s| s.plane == p) {
                    continue;
                }
                for small in [Side::Front, Side::Back] {
                    let t = naive_touched(&frags, p, small, &table);
                    let splits_off = t.iter().any(|&i| frags[i as usize].support != p);
                    let free = t.iter().all(|&i| {
                        frags[i as usize].placement(p, &table) != Placement::Straddle
                    });
                    if t.len() <= TOUCH_MAX && splits_off && free {
                        prop_assert!(
                            t.iter().any(|&i| seen[i as usize])
                                || 2 * (frags.len() - touched - t.len()) < frags.len(),
                            "plane {p} was lopsided and free"
                        );
                        break;
                    }
                }
            }
        }
    }
}
