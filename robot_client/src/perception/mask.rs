//! A binary image, one bit per pixel, and the morphology the paper applies to it (§III-B:
//! "hole filling, closing, then opening").
//!
//! Bits are packed 64 to a word so that the square structuring element is separable into a
//! horizontal pass (shifts and ORs of whole words) and a vertical pass (ORs of whole rows), both
//! over only the box around the set pixels: a 1280×960 mask is 19 200 words, a tag's box a few
//! hundred.

use std::ops::Range;

/// Pixels set or not; bit `x % 64` of word `x / 64` of row `y`. Bits past `width` are always 0.
#[derive(Clone, PartialEq, Eq)]
pub struct Mask {
    width: usize,
    height: usize,
    words_per_row: usize,
    words: Vec<u64>,
}

impl std::fmt::Debug for Mask {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Mask {}x{} ({} set)", self.width, self.height, self.count())
    }
}

impl Mask {
    pub fn new(width: usize, height: usize) -> Self {
        let words_per_row = width.div_ceil(64);
        Self { width, height, words_per_row, words: vec![0; words_per_row * height] }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    #[inline]
    pub fn get(&self, x: usize, y: usize) -> bool {
        self.words[y * self.words_per_row + x / 64] >> (x % 64) & 1 == 1
    }

    pub fn set(&mut self, x: usize, y: usize, on: bool) {
        let word = &mut self.words[y * self.words_per_row + x / 64];
        if on {
            *word |= 1 << (x % 64);
        } else {
            *word &= !(1 << (x % 64));
        }
    }

    /// The first x ≥ `from` in row `y` whose pixel is `value`, or the width.
    pub(crate) fn next_with(&self, y: usize, from: usize, value: bool) -> usize {
        next_with(self.row(y), from, self.width, value)
    }

    /// Row `y` as words, for writers that fill a row 64 pixels at a time.
    pub(crate) fn row_mut(&mut self, y: usize) -> &mut [u64] {
        &mut self.words[y * self.words_per_row..(y + 1) * self.words_per_row]
    }

    /// Row `y` as words, for readers that take a row 64 pixels at a time.
    pub(crate) fn row(&self, y: usize) -> &[u64] {
        &self.words[y * self.words_per_row..(y + 1) * self.words_per_row]
    }

    /// How many pixels are set.
    pub fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// The mask of the last word of a row: which of its bits are inside the image.
    fn tail(&self) -> u64 {
        match self.width % 64 {
            0 => u64::MAX,
            used => (1 << used) - 1,
        }
    }

    /// The rows and the word columns that hold set pixels, `None` when none is set.
    fn set_box(&self) -> Option<(Range<usize>, Range<usize>)> {
        let (mut rows, mut words) = ((usize::MAX, 0), (usize::MAX, 0));
        for y in 0..self.height {
            for (i, &w) in self.row(y).iter().enumerate() {
                if w != 0 {
                    rows = (rows.0.min(y), y + 1);
                    words = (words.0.min(i), words.1.max(i + 1));
                }
            }
        }
        (rows.0 < rows.1).then_some((rows.0..rows.1, words.0..words.1))
    }

    /// Dilation by a (2r+1)×(2r+1) square; outside the image counts as unset.
    pub fn dilate(&self, radius: usize) -> Self {
        self.square(radius, Square::Dilate)
    }

    /// Erosion by a (2r+1)×(2r+1) square; outside the image counts as set, so a region touching
    /// the border is not eaten from that side.
    pub fn erode(&self, radius: usize) -> Self {
        self.square(radius, Square::Erode)
    }

    /// `op` by a (2r+1)×(2r+1) square, separated into a pass along rows and one across them,
    /// both confined to the box around the set pixels: a tag's mask is mostly empty, and an
    /// empty stretch stays empty under either operator.
    fn square(&self, radius: usize, op: Square) -> Self {
        let Some((rows, words)) = self.set_box().filter(|_| radius > 0) else {
            return self.clone();
        };
        let radius = radius.min(63);
        // A radius under 64 reaches one word sideways; a dilation also grows by it up and down.
        let words = words.start.saturating_sub(1)..(words.end + 1).min(self.words_per_row);
        let reach = rows.start.saturating_sub(radius)..(rows.end + radius).min(self.height);
        let out_rows = match op {
            Square::Dilate => reach.clone(),
            Square::Erode => rows,
        };
        let tail = self.tail();
        let mut horizontal = Self::new(self.width, self.height);
        for y in reach {
            square_row(
                self.row(y),
                &mut horizontal.row_mut(y)[words.clone()],
                words.start,
                radius,
                tail,
                op,
            );
        }
        let mut out = Self::new(self.width, self.height);
        for y in out_rows {
            let from = y.saturating_sub(radius);
            let to = (y + radius).min(self.height - 1);
            for i in words.clone() {
                // Rows outside the image are the operator's identity, so they are left out.
                let mut acc = op.outside();
                for yy in from..=to {
                    acc = op.combine(acc, horizontal.words[yy * self.words_per_row + i]);
                }
                out.words[y * self.words_per_row + i] = acc;
            }
        }
        out
    }

    /// Closing: dilation then erosion; bridges gaps narrower than the square.
    pub fn close(&self, radius: usize) -> Self {
        self.dilate(radius).erode(radius)
    }

    /// Opening: erosion then dilation; removes specks smaller than the square.
    pub fn open(&self, radius: usize) -> Self {
        self.erode(radius).dilate(radius)
    }

    /// Sets every unset pixel that cannot reach the image border through unset pixels (4-connected):
    /// the holes a glint or a fold leaves inside a red patch.
    pub fn fill_holes(&self) -> Self {
        // Runs of unset pixels, row by row, joined by union-find where runs of adjacent rows overlap.
        let mut runs: Vec<(usize, usize, usize)> = Vec::new(); // (row, start, end exclusive)
        let mut row_first = Vec::with_capacity(self.height + 1);
        for y in 0..self.height {
            row_first.push(runs.len());
            let row = self.row(y);
            let mut x = 0;
            while x < self.width {
                let start = next_with(row, x, self.width, false);
                if start >= self.width {
                    break;
                }
                let end = next_with(row, start, self.width, true);
                runs.push((y, start, end));
                x = end;
            }
        }
        row_first.push(runs.len());
        let mut parent: Vec<usize> = (0..runs.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for y in 1..self.height {
            let (above, here) = (row_first[y - 1]..row_first[y], row_first[y]..row_first[y + 1]);
            let mut a = above.start;
            for r in here {
                let (_, s, e) = runs[r];
                while a < above.end && runs[a].2 <= s {
                    a += 1;
                }
                let mut b = a;
                while b < above.end && runs[b].1 < e {
                    let (ra, rb) = (root(&mut parent, r), root(&mut parent, b));
                    parent[ra] = rb;
                    b += 1;
                }
            }
        }
        let mut outside = vec![false; runs.len()];
        for (i, &(y, s, e)) in runs.iter().enumerate() {
            if y == 0 || y + 1 == self.height || s == 0 || e == self.width {
                let r = root(&mut parent, i);
                outside[r] = true;
            }
        }
        let mut out = self.clone();
        for (i, &(y, s, e)) in runs.iter().enumerate() {
            let r = root(&mut parent, i);
            if !outside[r] {
                for x in s..e {
                    out.set(x, y, true);
                }
            }
        }
        out
    }
}

/// The first x ≥ `from` whose bit equals `value`, or `width`.
fn next_with(row: &[u64], from: usize, width: usize, value: bool) -> usize {
    let mut i = from / 64;
    if i >= row.len() {
        return width;
    }
    let flip = if value { 0 } else { u64::MAX };
    let mut w = (row[i] ^ flip) & (u64::MAX << (from % 64));
    loop {
        if w != 0 {
            return (i * 64 + w.trailing_zeros() as usize).min(width);
        }
        i += 1;
        if i >= row.len() {
            return width;
        }
        w = row[i] ^ flip;
    }
}

/// A morphological operator: a pixel takes the OR (dilation) or the AND (erosion) of its square.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Square {
    Dilate,
    Erode,
}

impl Square {
    /// What lies outside the image, for this operator: unset for a dilation, set for an erosion.
    fn outside(self) -> u64 {
        match self {
            Self::Dilate => 0,
            Self::Erode => u64::MAX,
        }
    }

    fn combine(self, a: u64, b: u64) -> u64 {
        match self {
            Self::Dilate => a | b,
            Self::Erode => a & b,
        }
    }
}

/// `out[x]` = `op` of `row[x-r..=x+r]` for the words of one row from `first` on (r ≤ 63); the
/// bits of the last word past the image's width (`tail` marks the ones inside) read as outside.
fn square_row(row: &[u64], out: &mut [u64], first: usize, r: usize, tail: u64, op: Square) {
    let last = row.len() - 1;
    let read = |i: usize| {
        let w = row[i];
        if i == last { (w & tail) | (op.outside() & !tail) } else { w }
    };
    for (i, o) in (first..).zip(out.iter_mut()) {
        let w = read(i);
        let prev = if i > 0 { read(i - 1) } else { op.outside() };
        let next = if i < last { read(i + 1) } else { op.outside() };
        let mut acc = w;
        for k in 1..=r {
            // Pixel x sees x+k (a right shift brings higher x down) and x-k (a left shift).
            acc = op.combine(acc, (w >> k) | (next << (64 - k)));
            acc = op.combine(acc, (w << k) | (prev >> (64 - k)));
        }
        *o = if i == last { acc & tail } else { acc };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_mask(rng: &mut ChaCha8Rng, w: usize, h: usize, p: f64) -> Mask {
        let mut m = Mask::new(w, h);
        for y in 0..h {
            for x in 0..w {
                m.set(x, y, rng.random_bool(p));
            }
        }
        m
    }

    fn complement(m: &Mask) -> Mask {
        let mut out = Mask::new(m.width, m.height);
        for y in 0..m.height {
            for x in 0..m.width {
                out.set(x, y, !m.get(x, y));
            }
        }
        out
    }

    /// The textbook definition, pixel by pixel, to check the word-parallel one against.
    fn naive_dilate(m: &Mask, r: usize) -> Mask {
        let mut out = Mask::new(m.width, m.height);
        for y in 0..m.height {
            for x in 0..m.width {
                let hit = (y.saturating_sub(r)..=(y + r).min(m.height - 1)).any(|yy| {
                    (x.saturating_sub(r)..=(x + r).min(m.width - 1)).any(|xx| m.get(xx, yy))
                });
                out.set(x, y, hit);
            }
        }
        out
    }

    #[test]
    fn dilation_and_erosion_match_the_definition() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..300 {
            let (w, h) = (rng.random_range(1..300), rng.random_range(1..40));
            let density = rng.random_range(0.02..0.6);
            let mut m = random_mask(&mut rng, w, h, density);
            if case % 2 == 1 {
                // Set pixels in a patch only, as a tag's mask: the operators work on its box.
                let (x0, y0) = (rng.random_range(0..w), rng.random_range(0..h));
                let (x1, y1) = (rng.random_range(x0..w) + 1, rng.random_range(y0..h) + 1);
                for y in 0..h {
                    for x in 0..w {
                        let inside = (x0..x1).contains(&x) && (y0..y1).contains(&y);
                        m.set(x, y, inside && m.get(x, y));
                    }
                }
            }
            let r = rng.random_range(0..5);
            assert_eq!(m.dilate(r), naive_dilate(&m, r));
            assert_eq!(m.erode(r), complement(&naive_dilate(&complement(&m), r)));
        }
    }

    #[test]
    fn opening_removes_specks_and_closing_bridges_gaps() {
        let mut m = Mask::new(100, 60);
        for y in 10..40 {
            for x in 20..60 {
                m.set(x, y, x != 40); // a 1-pixel gap through the patch
            }
        }
        m.set(80, 50, true); // a speck
        let closed = m.close(1);
        assert!(closed.get(40, 25), "the gap is bridged");
        let opened = closed.open(1);
        assert!(!opened.get(80, 50), "the speck is gone");
        assert_eq!(opened.count(), 30 * 40, "the patch keeps its shape");
    }

    #[test]
    fn fills_holes_but_not_bays() {
        let mut m = Mask::new(70, 30);
        for y in 5..25 {
            for x in 5..65 {
                m.set(x, y, true);
            }
        }
        for (x, y) in [(10, 10), (11, 10), (30, 15), (64, 12)] {
            m.set(x, y, false);
        }
        // A bay open to the border through a channel is not a hole.
        for x in 40..70 {
            m.set(x, 20, false);
        }
        let filled = m.fill_holes();
        assert!(filled.get(10, 10) && filled.get(11, 10) && filled.get(30, 15));
        assert!(!filled.get(50, 20), "a channel to the border stays open");
        assert!(!filled.get(64, 12), "a notch on the patch's edge at x=64 is open to the right");
        assert!(!filled.get(0, 0));
    }
}
