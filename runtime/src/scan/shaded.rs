//! Shaded intervals in scan memory: a smooth span's pieces as two nodes each (its shade from
//! the piece's first pixel on, its material by index) or as runs of pixels alike, whichever
//! costs fewer nodes; neighbours that continue each other's shade grow instead. Pixels are
//! alike (`ScanMemory::key`) when their RGB565 colours are, in an undithered frame, and when
//! their 8-bit colours are, in a dithered one, whose runs are then level runs
//! ([`LEVEL`](super::LEVEL)).
//! A row's colours are monotonic in x (its intensity is affine, and a colour's channels grow
//! with the intensity), so a piece's runs are found by bisection, and a piece whose first and
//! last pixels agree is one colour.

use super::{Piece, Pieces, ScanMemory, ScanNode, NIL};
use crate::display::{Colour, RowShade, SHADE_FRACTION_BITS};

impl ScanMemory<'_> {
    /// What pixels of a shade must share to be kept alike: their 8-bit colour in a dithered
    /// frame (the dither takes every bit), their RGB565 colour in an undithered one.
    #[inline]
    fn key(&mut self, colour: Colour) -> u32 {
        if self.dither {
            u32::from_le_bytes([colour.r, colour.g, colour.b, 0])
        } else {
            u32::from(self.rgb565(colour))
        }
    }

    /// The piece of a run of pixels alike ([`Self::key`]) from `x` to `end` of `shade`
    /// (material `material`): a level run in a dithered frame, one RGB565 colour otherwise.
    #[inline]
    fn run(&mut self, shade: &RowShade, x: u16, end: u16, material: u8) -> Piece {
        if self.dither {
            let level = shade.colours(u32::from(x)).level();
            Piece::Level(end, ScanNode::level_field(level, material))
        } else {
            Piece::Flat(end, self.rgb565(shade.at(u32::from(x))))
        }
    }

    /// A node pair for a shaded interval (two fresh nodes in a row); `None` when the pool is
    /// spent. Shaded intervals are never freed, so the free list holds single nodes only.
    pub(super) fn alloc_pair(&mut self, first: ScanNode, shade: ScanNode) -> Option<u16> {
        let i = self.fresh;
        if usize::from(i) + 2 > self.capacity() {
            return None;
        }
        *self.node_mut(i)? = first;
        *self.node_mut(i + 1)? = shade;
        self.fresh += 2;
        Some(i)
    }

    /// The index of material `colour` among the frame's, added if new; `None` when the frame
    /// has [`MATERIALS`] others already.
    pub(super) fn material(&mut self, colour: Colour) -> Option<u8> {
        let n = usize::from(self.materials);
        let known = self.palette.get(..n).unwrap_or(&[]);
        if let Some(i) = known.iter().position(|&c| c == colour) {
            return Some(i as u8);
        }
        let slot = self.palette.get_mut(n)?;
        *slot = colour;
        self.materials += 1;
        Some(n as u8)
    }

    /// Shaded interval `i`'s shade (its colour is the material's); a level run's is constant.
    pub(super) fn row_shade(&self, i: u16, n: &ScanNode) -> RowShade {
        let (material, level) = n.material_level();
        let colour = self.palette.get(material).copied().unwrap_or_default();
        if n.is_level() {
            return RowShade {
                base: i32::from(level) << SHADE_FRACTION_BITS,
                step: 0,
                colour,
            };
        }
        let (value, step) = n.value_step(&self.node(i.wrapping_add(1)));
        RowShade {
            base: value.wrapping_sub(step.wrapping_mul(i32::from(n.first()))),
            step,
            colour,
        }
    }

    /// How far shaded interval `prev`, which ends at `at`, continues over the pixels of
    /// `at..gap_end` painted alike ([`Self::key`]) as its shade goes on (a neighbour on a
    /// smooth surface often does): their end, if there is one such pixel.
    fn extend(&mut self, prev: u16, at: u16, gap_end: u16, shade: &RowShade) -> Option<u16> {
        let p = (prev != NIL).then(|| self.node(prev))?;
        if !cfg!(feature = "smooth") || !p.is_shaded() {
            return None;
        }
        let n = self
            .row_shade(prev, &p)
            .colours(u32::from(at))
            .zip(shade.colours(u32::from(at)))
            .take(usize::from(gap_end - at))
            .take_while(|&(l, c)| self.key(l) == self.key(c))
            .count();
        let end = at + n as u16;
        (end > at).then_some(end)
    }

    /// Extend shaded interval `next`, which starts at `gap_end`, back over the pixels of
    /// `at..gap_end` painted as its shade continues: their start, if there is one such pixel
    /// (its shade is then kept from there; the caller moves its start).
    fn extend_back(&mut self, next: u16, at: u16, gap_end: u16, shade: &RowShade) -> Option<u16> {
        let n = (next != NIL).then(|| self.node(next))?;
        if !cfg!(feature = "smooth") || !n.is_shaded() {
            return None;
        }
        let right = self.row_shade(next, &n);
        let mut start = gap_end;
        while start > at {
            let x = u32::from(start - 1);
            if self.key(right.at(x)) != self.key(shade.at(x)) {
                break;
            }
            start -= 1;
        }
        (start < gap_end).then(|| {
            // A level run's shade is its colour field, the same from any pixel.
            if n.is_pair() {
                self.reshade(next, start, &right, n.material_level().0 as u8);
            }
            start
        })
    }

    /// Whether `shade` gives every pixel of shaded interval `i` (node `n`) the colour it has,
    /// tried from its left end first (`from_left`) or its right end: the end far from the gap,
    /// where a mismatch shows first.
    fn reproduces(&mut self, i: u16, n: &ScanNode, shade: &RowShade, from_left: bool) -> bool {
        let own = self.row_shade(i, n);
        let end = self.end(n);
        let same = |x: u16| self.key(own.at(u32::from(x))) == self.key(shade.at(u32::from(x)));
        if from_left {
            (n.first()..end).all(same)
        } else {
            (n.first()..end).rev().all(same)
        }
    }

    /// Give shaded interval `i` `shade` and `material` from `start` on (its shade's step fits,
    /// [`ScanNode::step_fits`]).
    fn reshade(&mut self, i: u16, start: u16, shade: &RowShade, material: u8) {
        let value = shade
            .base
            .wrapping_add(shade.step.wrapping_mul(i32::from(start)));
        let next = self.node(i).next;
        let (first, second) = ScanNode::pair(start, next, material, value, shade.step);
        if let Some(n) = self.node_mut(i) {
            *n = first;
        }
        if let Some(n) = self.node_mut(i.wrapping_add(1)) {
            *n = second;
        }
    }

    /// Grow a shaded neighbour of gap `at..gap_end` (`prev` ends at `at`, `next` starts at
    /// `gap_end`, either none) over the whole gap where `shade` (the gap's) gives the
    /// neighbour's pixels their colours: the neighbour takes `shade`. The piece it makes, if
    /// one did. (A level run has no second node for a shade.)
    fn adopt(
        &mut self,
        (at, gap_end): (u16, u16),
        prev: u16,
        next: u16,
        shade: &RowShade,
        material: u8,
    ) -> Option<Piece> {
        if !cfg!(feature = "smooth") || !ScanNode::step_fits(shade.step) {
            return None;
        }
        if prev != NIL {
            let p = self.node(prev);
            if p.is_pair() && self.reproduces(prev, &p, shade, true) {
                self.reshade(prev, p.first(), shade, material);
                return Some(Piece::Left(gap_end));
            }
        }
        if next != NIL {
            let n = self.node(next);
            if n.is_pair() && self.reproduces(next, &n, shade, false) {
                self.reshade(next, at, shade, material);
                return Some(Piece::Right(at));
            }
        }
        None
    }

    /// The end of the run of pixels of key `key` ([`Self::key`]), which pixel `from` has, in
    /// `from..to` of `shade`'s row. A row's colours are monotonic in x (so is its intensity,
    /// and so are a colour's channels in it): each key is one run, and the first pixel of
    /// another is found by bisection.
    fn run_end(&mut self, shade: &RowShade, from: u16, to: u16, key: u32) -> u16 {
        let (mut lo, mut hi) = (from + 1, to);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if self.key(shade.at(u32::from(mid))) == key {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// Whether gap `at..gap_end` of `shade` (material `material`), whose first run ends at
    /// `end` before it, costs fewer nodes shaded (two) than as its runs, the first joining the
    /// interval before it (`prev`) and the last the next one (`next`) where they match.
    fn shade_pays(
        &mut self,
        shade: &RowShade,
        (at, end, gap_end): (u16, u16, u16),
        material: u8,
        prev: u16,
        next: Option<ScanNode>,
    ) -> bool {
        // Runs, counted up to 5: five cost more than two nodes whatever joins.
        let (mut runs, mut x, mut last) = (1, end, at);
        while x < gap_end {
            if runs == 5 {
                return true;
            }
            last = x;
            let key = self.key(shade.at(u32::from(x)));
            x = self.run_end(shade, x, gap_end, key);
            runs += 1;
        }
        let before = (prev != NIL).then(|| self.node(prev));
        let left = before.is_some_and(|p| self.joins(&p, shade, at, material));
        let right = next.is_some_and(|n| self.joins(&n, shade, last, material));
        runs - i32::from(left) - i32::from(right) > 2
    }

    /// Whether node `n` is the run of `shade`'s pixels alike with pixel `x`'s (the same colour
    /// field and kind), which a run of them would join.
    fn joins(&mut self, n: &ScanNode, shade: &RowShade, x: u16, material: u8) -> bool {
        match self.run(shade, x, x, material) {
            Piece::Flat(_, c) => !n.tagged() && n.colour == c,
            Piece::Level(_, c) => n.is_shaded() && n.colour == c,
            _ => false,
        }
    }

    /// A shade kept as flat runs, undithered (a material beyond the frame's
    /// [`MATERIALS`](super::MATERIALS)), each run of pixels alike found by bisection.
    pub(super) fn runs(&mut self, y: u32, x_start: u32, x_end: u32, shade: &RowShade) -> u64 {
        let x_end = x_end.min(u32::from(self.width));
        if x_start >= x_end {
            return 0;
        }
        // In range: x_start < x_end <= width <= MAX_WIDTH.
        let (mut at, end) = (x_start as u16, x_end as u16);
        let mut covered = 0;
        while at < end {
            let colour = shade.at(u32::from(at));
            let key = self.key(colour);
            let run_end = self.run_end(shade, at, end, key);
            covered += self.span(y, u32::from(at), u32::from(run_end), colour);
            at = run_end;
        }
        covered
    }
}

/// A shaded span: its row's shade and the index of its material.
pub(super) struct Shading<'a> {
    shade: &'a RowShade,
    material: u8,
    /// The gap up to here goes as runs (decided at its first run).
    runs_until: u16,
}

impl<'a> Shading<'a> {
    pub(super) fn new(shade: &'a RowShade, material: u8) -> Self {
        Shading {
            shade,
            material,
            runs_until: 0,
        }
    }
}

impl Pieces for Shading<'_> {
    fn piece(&mut self, m: &mut ScanMemory<'_>, gap: (u16, u16), prev: u16, next: u16) -> Piece {
        let ((at, gap_end), shade) = (gap, self.shade);
        if let Some(end) = m.extend(prev, at, gap_end, shade) {
            return Piece::Left(end);
        }
        if let Some(start) = m.extend_back(next, at, gap_end, shade) {
            return Piece::Right(start);
        }
        if let Some(piece) = m.adopt((at, gap_end), prev, next, shade, self.material) {
            return piece;
        }
        let key = m.key(shade.at(u32::from(at)));
        let end = m.run_end(shade, at, gap_end, key);
        let next = (next != NIL).then(|| m.node(next));
        if at >= self.runs_until
            && end < gap_end
            && ScanNode::step_fits(shade.step)
            && m.shade_pays(shade, (at, end, gap_end), self.material, prev, next)
        {
            return Piece::Shaded(gap_end);
        }
        self.runs_until = gap_end;
        m.run(shade, at, end, self.material)
    }

    fn shaded(&self, at: u16, _end: u16, next: u16) -> (ScanNode, ScanNode) {
        let value = self
            .shade
            .base
            .wrapping_add(self.shade.step.wrapping_mul(i32::from(at)));
        ScanNode::pair(at, next, self.material, value, self.shade.step)
    }
}
