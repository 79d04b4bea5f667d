//! The connected regions ("blobs") of a segmented image, 8-connected.
//!
//! A tag is one red region in the image even where the laser samples it too sparsely for its
//! points to touch in a 1 cm grid (a towel seen at 70°, a line of dropouts across it): the blobs
//! tell the tag search which 3D fragments belong together.

use super::mask::Mask;

/// The blobs of a mask, as runs of set pixels per row labelled by blob.
#[derive(Debug, Clone)]
pub struct Blobs {
    /// `(start, end exclusive, blob)` of each run, rows in order, runs in a row left to right.
    runs: Vec<(u32, u32, u32)>,
    /// Where each row's runs begin in `runs`, and a last entry for the end.
    row_first: Vec<u32>,
}

impl Blobs {
    /// Labels the 8-connected regions of set pixels in `mask`.
    pub fn of(mask: &Mask) -> Self {
        let mut runs: Vec<(u32, u32, u32)> = Vec::new();
        let mut row_first = Vec::with_capacity(mask.height() + 1);
        for y in 0..mask.height() {
            row_first.push(runs.len() as u32);
            let mut x = 0;
            while x < mask.width() {
                let start = mask.next_with(y, x, true);
                if start >= mask.width() {
                    break;
                }
                let end = mask.next_with(y, start, false);
                runs.push((start as u32, end as u32, runs.len() as u32));
                x = end;
            }
        }
        row_first.push(runs.len() as u32);
        let mut parent: Vec<u32> = (0..runs.len() as u32).collect();
        fn root(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                parent[i as usize] = parent[parent[i as usize] as usize];
                i = parent[i as usize];
            }
            i
        }
        for y in 1..mask.height() {
            let above = row_first[y - 1] as usize..row_first[y] as usize;
            let mut a = above.start;
            for r in row_first[y] as usize..row_first[y + 1] as usize {
                let (s, e, _) = runs[r];
                // Diagonal neighbours count: a run above touches when it ends at s or later and
                // starts at e or earlier.
                while a < above.end && runs[a].1 < s {
                    a += 1;
                }
                let mut b = a;
                while b < above.end && runs[b].0 <= e {
                    let (ra, rb) = (root(&mut parent, r as u32), root(&mut parent, b as u32));
                    parent[ra as usize] = rb;
                    b += 1;
                }
            }
        }
        for (r, run) in runs.iter_mut().enumerate() {
            run.2 = root(&mut parent, r as u32);
        }
        Self { runs, row_first }
    }

    /// The blob pixel (x, y) belongs to, `None` when it is not set.
    pub fn at(&self, x: usize, y: usize) -> Option<u32> {
        let row = self.row_first.get(y..y + 2)?;
        let runs = &self.runs[row[0] as usize..row[1] as usize];
        let x = x as u32;
        let i = runs.partition_point(|&(_, end, _)| end <= x);
        runs.get(i).filter(|&&(start, _, _)| start <= x).map(|&(_, _, blob)| blob)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask_of(rows: &[&str]) -> Mask {
        let mut m = Mask::new(rows[0].len(), rows.len());
        for (y, row) in rows.iter().enumerate() {
            for (x, c) in row.chars().enumerate() {
                m.set(x, y, c == '#');
            }
        }
        m
    }

    #[test]
    fn diagonal_touches_join_and_gaps_separate() {
        let blobs = Blobs::of(&mask_of(&[
            "##....#", //
            "..#...#", //
            "...#...", //
            "......#", //
        ]));
        let a = blobs.at(0, 0).unwrap();
        assert_eq!(blobs.at(1, 0), Some(a));
        assert_eq!(blobs.at(2, 1), Some(a), "diagonal");
        assert_eq!(blobs.at(3, 2), Some(a));
        let b = blobs.at(6, 0).unwrap();
        assert_ne!(a, b);
        assert_eq!(blobs.at(6, 1), Some(b));
        assert_ne!(blobs.at(6, 3), Some(b), "a row apart is another blob");
        assert_eq!(blobs.at(4, 0), None);
        assert_eq!(blobs.at(0, 9), None, "outside the image");
    }
}
