//! Points grouped by cubic cell: which points lie close together, found by one sort. The plane
//! search draws each sample's points from one cell.

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
        let key = |p: &Point3<f32>| {
            let c = cube_of(p, size).map(|v| (v + (1 << 20)) as u64 & 0x1F_FFFF);
            c[0] << 42 | c[1] << 21 | c[2]
        };
        let mut keyed: Vec<(u64, u32)> =
            points.iter().enumerate().map(|(i, p)| (key(p), i as u32)).collect();
        keyed.sort_unstable();
        let mut starts = Vec::new();
        let mut cell_of = vec![0; points.len()];
        for (at, &(k, i)) in keyed.iter().enumerate() {
            if at == 0 || keyed[at - 1].0 != k {
                starts.push(at as u32);
            }
            cell_of[i as usize] = starts.len() as u32 - 1;
        }
        starts.push(keyed.len() as u32);
        Self { order: keyed.into_iter().map(|(_, i)| i).collect(), starts, cell_of }
    }

    /// The indices of the points sharing point `i`'s cell, itself included.
    pub fn cell_of(&self, i: u32) -> &[u32] {
        self.cell(self.cell_of[i as usize] as usize)
    }

    fn cell(&self, c: usize) -> &[u32] {
        &self.order[self.starts[c] as usize..self.starts[c + 1] as usize]
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
}
