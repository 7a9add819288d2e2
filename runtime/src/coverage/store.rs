//! Where a [`Coverage`](super::Coverage) keeps its intervals: [`Store`], rows of slots in
//! span memory ([`Rows`]) or a scan-order frame's scan memory. Without the `scan-order`
//! feature the scan variant holds an uninhabited type, so it takes no room and every match
//! on it compiles to the rows' arm alone: the store is a type, not a flag tested per span.

use core::convert::Infallible;
use core::marker::PhantomData;

use crate::display::Paint;

/// The intervals of a coverage.
#[derive(Debug)]
pub(super) enum Store<'m> {
    /// Span memory: `per_row` slots a row.
    Rows(Rows<'m>),
    /// Scan memory: coloured lists sharing one pool.
    #[cfg_attr(not(feature = "scan-order"), allow(dead_code))]
    Scan(ScanStore<'m>),
}

/// Scan memory, the second store.
#[cfg(feature = "scan-order")]
pub(crate) type ScanStore<'m> = crate::scan::ScanMemory<'m>;
/// Without `scan-order` there is no scan memory: a store that cannot exist.
#[cfg(not(feature = "scan-order"))]
pub(crate) type ScanStore<'m> = NoScan<'m>;

/// No scan memory (built without `scan-order`): uninhabited, so [`Store::Scan`] never is.
#[derive(Debug)]
pub(crate) struct NoScan<'m> {
    never: Infallible,
    _memory: PhantomData<&'m ()>,
}

#[allow(dead_code)]
impl NoScan<'_> {
    pub(crate) fn width(&self) -> u32 {
        match self.never {}
    }
    pub(crate) fn height(&self) -> u32 {
        match self.never {}
    }
    pub(crate) fn clear(&mut self) {
        match self.never {}
    }
    pub(crate) fn exhausted(&self) -> bool {
        match self.never {}
    }
    pub(crate) fn covered(&self) -> u64 {
        match self.never {}
    }
    pub(crate) fn is_full(&self, _: u32) -> bool {
        match self.never {}
    }
    pub(crate) fn covers(&self, _: u32, _: u32, _: u32, _: u32) -> bool {
        match self.never {}
    }
    pub(crate) fn paint(&mut self, _: u32, _: u32, _: u32, _: Paint<'_>) -> u64 {
        match self.never {}
    }
    pub(crate) fn uncovered(&self, _: u32, _: u32, _: u32, _: impl FnMut(u32, u32)) {
        match self.never {}
    }
}

/// Span memory: `intervals` split into rows of `per_row` slots, `counts[y]` of them in use.
#[derive(Debug)]
pub(super) struct Rows<'m> {
    pub(super) intervals: &'m mut [(u16, u16)],
    pub(super) counts: &'m mut [u16],
    pub(super) per_row: usize,
    pub(super) full_rows: u32,
    pub(super) covered: u64,
    pub(super) exhausted: bool,
}

impl Rows<'_> {
    /// Forget every interval.
    pub(super) fn clear(&mut self) {
        for c in self.counts.iter_mut() {
            *c = 0;
        }
        self.full_rows = 0;
        self.covered = 0;
        self.exhausted = false;
    }

    /// Row `y`'s intervals (empty past the counts).
    #[inline]
    pub(super) fn row(&self, y: u32) -> &[(u16, u16)] {
        let y = y as usize;
        let n = usize::from(self.counts.get(y).copied().unwrap_or(0));
        let start = y * self.per_row;
        self.intervals.get(start..start + n).unwrap_or(&[])
    }

    /// Replace intervals `first..last` of row `y` (all touching `[a, b]`) by their union with
    /// `[a, b]`; the caller checked there is room.
    pub(super) fn merge(
        &mut self,
        y: usize,
        first: usize,
        last: usize,
        a: u16,
        b: u16,
        width: u16,
    ) {
        let base = y * self.per_row;
        // Every index below is in range by construction; `get` keeps the path panic-free.
        let n = usize::from(self.counts.get(y).copied().unwrap_or(0));
        let Some(row) = self.intervals.get_mut(base..base + self.per_row) else {
            return;
        };
        let (mut s, mut e) = (a, b);
        let mut before = 0u64;
        for &(rs, re) in row.get(first..last).unwrap_or(&[]) {
            s = s.min(rs);
            e = e.max(re);
            before += u64::from(re - rs);
        }
        let was_full = n == 1 && row.first() == Some(&(0, width));
        let new_n = n + 1 - (last - first);
        // Shift the tail so that exactly one slot replaces `first..last`.
        // (Element by element with `get`: `copy_within`'s checks are not provably dead.)
        let (src, dst, moved) = (last, first + 1, n.saturating_sub(last));
        let mut shift = |i: usize| {
            if let (Some(&v), Some(_)) = (row.get(src + i), row.get(dst + i)) {
                if let Some(d) = row.get_mut(dst + i) {
                    *d = v;
                }
            }
        };
        if dst < src {
            (0..moved).for_each(&mut shift);
        } else if dst > src {
            (0..moved).rev().for_each(&mut shift);
        }
        if let Some(slot) = row.get_mut(first) {
            *slot = (s, e);
        }
        if let Some(count) = self.counts.get_mut(y) {
            *count = new_n as u16;
        }
        self.covered += u64::from(e - s) - before;
        if !was_full && new_n == 1 && s == 0 && e == width {
            self.full_rows += 1;
        }
    }
}
