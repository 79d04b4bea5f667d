//! Points grouped by cubic cell: which points lie close together, found by counting them into
//! cells (or, for a cloud spread over a vast box, by one sort). The plane search draws each
//! sample's points from one cell.

use nalgebra::Point3;

use crate::perception::voxel_coords::cube_of;

/// The points of a cloud ordered by the cubic cell they fall in.
#[derive(Debug, Clone)]
pub struct CellIndex {
    /// Point indices ordered by cell.
    order: Vec<u32>,
    /// Where each cell's run of `order` starts, and a last entry for the end.
    starts: Vec<u32>,
    /// For each point, its cell's number.
    cell_of: Vec<u32>,
}

impl CellIndex {
    /// Groups `points` into cubes of `size` metres.
    pub fn new(points: &[Point3<f32>], size: f32) -> Self {
        let cubes: Vec<[i64; 3]> = points.iter().map(|p| cube_of(p, size)).collect();
        match DenseBox::around(&cubes) {
            Some(dense) => dense.index(&cubes),
            None => Self::sorted(&cubes),
        }
    }

    /// By sorting the cubes: for a cloud spread over far more cubes than it has points.
    fn sorted(cubes: &[[i64; 3]]) -> Self {
        let mut order: Vec<u32> = (0..cubes.len() as u32).collect();
        order.sort_unstable_by_key(|&i| (cubes[i as usize], i));
        let mut starts = Vec::new();
        let mut cell_of = vec![0; cubes.len()];
        for (at, &i) in order.iter().enumerate() {
            if at == 0 || cubes[order[at - 1] as usize] != cubes[i as usize] {
                starts.push(at as u32);
            }
            cell_of[i as usize] = starts.len() as u32 - 1;
        }
        starts.push(order.len() as u32);
        Self { order, starts, cell_of }
    }

    /// The indices of the points sharing point `i`'s cell, itself included.
    pub fn cell_of(&self, i: u32) -> &[u32] {
        self.cell(self.cell_of[i as usize] as usize)
    }

    fn cell(&self, c: usize) -> &[u32] {
        &self.order[self.starts[c] as usize..self.starts[c + 1] as usize]
    }
}

/// The box of cubes a cloud spans, when it is small enough to count points into: a volume of
/// interest is about a thousand 10 cm cubes, and counting is linear where sorting its tens of
/// thousands of points was most of the plane search's set-up.
struct DenseBox {
    lo: [i64; 3],
    dims: [i64; 3],
}

impl DenseBox {
    /// `None` when the cubes span far more cells than there are points, or than u32 numbers.
    fn around(cubes: &[[i64; 3]]) -> Option<Self> {
        let first = cubes.first()?;
        let (mut lo, mut hi) = (*first, *first);
        for c in cubes {
            for axis in 0..3 {
                lo[axis] = lo[axis].min(c[axis]);
                hi[axis] = hi[axis].max(c[axis]);
            }
        }
        let dims = [0, 1, 2].map(|axis| hi[axis].saturating_sub(lo[axis]).saturating_add(1));
        let volume = dims.iter().try_fold(1i64, |v, &d| v.checked_mul(d))?;
        // Cube numbers are u32, as point indices are.
        let small = volume <= 8 * cubes.len().max(1024) as i64 && volume <= i64::from(u32::MAX);
        small.then_some(Self { lo, dims })
    }

    /// The cube's number in the box, in the order of x, then y, then z, as sorting them would
    /// order them.
    fn number(&self, c: &[i64; 3]) -> u32 {
        let [x, y, z] = [0, 1, 2].map(|axis| c[axis] - self.lo[axis]);
        ((x * self.dims[1] + y) * self.dims[2] + z) as u32
    }

    /// The index by a counting sort: the same cells, in the same order, as sorting gives.
    fn index(&self, cubes: &[[i64; 3]]) -> CellIndex {
        // Each point's cube numbered once.
        let numbers: Vec<u32> = cubes.iter().map(|c| self.number(c)).collect();
        let volume = self.dims.iter().product::<i64>() as usize;
        let mut count = vec![0u32; volume];
        for &k in &numbers {
            count[k as usize] += 1;
        }
        // Occupied cubes become cells in their numbers' order; `next` is where each cube's
        // next point goes and `cell_number` its cell.
        let mut starts = Vec::new();
        let (mut next, mut cell_number) = (count, vec![0u32; volume]);
        let mut at = 0;
        for (cube, slot) in next.iter_mut().enumerate() {
            if *slot > 0 {
                cell_number[cube] = starts.len() as u32;
                starts.push(at);
                (at, *slot) = (at + *slot, at);
            }
        }
        starts.push(at);
        let mut order = vec![0; cubes.len()];
        let mut cell_of = Vec::with_capacity(cubes.len());
        for (i, &k) in numbers.iter().enumerate() {
            let slot = &mut next[k as usize];
            order[*slot as usize] = i as u32;
            *slot += 1;
            cell_of.push(cell_number[k as usize]);
        }
        CellIndex { order, starts, cell_of }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_in_one_cube_share_a_cell() {
        let points = [
            Point3::new(0.01, 0.01, 0.01),
            Point3::new(0.5, 0.5, 0.5),
            Point3::new(0.09, 0.02, 0.05),
            Point3::new(-0.01, 0.01, 0.01),
        ];
        let cells = CellIndex::new(&points, 0.1);
        let mut first = cells.cell_of(0).to_vec();
        first.sort_unstable();
        assert_eq!(first, [0, 2]);
        assert_eq!(cells.cell_of(3), [3], "negative coordinates fall in their own cube");
        assert_eq!(cells.cell_of(1), [1]);
    }

    #[test]
    fn a_vast_cloud_is_grouped_alike() {
        // 2 km across at 10 cm: too many cells to count into, so they are sorted.
        let points = [
            Point3::new(1000.0, 0.01, 0.0),
            Point3::new(-1000.0, 0.0, 0.0),
            Point3::new(1000.05, 0.02, 0.01),
            Point3::new(-1000.0, 0.05, 0.02),
            Point3::new(3.0, 0.0, 0.0),
        ];
        let cells = CellIndex::new(&points, 0.1);
        assert_eq!(cells.cell_of(0), [0, 2]);
        assert_eq!(cells.cell_of(3), [1, 3]);
        assert_eq!(cells.cell_of(4), [4]);
        assert_eq!(cells.order, [1, 3, 4, 0, 2], "cells in the order of their coordinates");
    }
}
