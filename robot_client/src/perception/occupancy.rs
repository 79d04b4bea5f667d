//! The paper's 1 cm³ occupancy grid over the red points and its 3D connected components.
//!
//! Voxels are kept sorted by key, so the grid is a sorted array searched by bisection: for the
//! few thousand red points of a tag this beats hashing and needs no allocation per voxel.

use nalgebra::Point3;

use super::flood_fill::flood_fill;
use super::voxel_coords::cube_of;

/// One connected lump of occupied voxels: a tag candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Component {
    /// Mean of the component's points, base frame.
    pub centroid: Point3<f64>,
    pub points: usize,
    pub voxels: usize,
    /// Distance from the target to the component's nearest point, metres.
    pub distance_to_target: f64,
    /// Half the diagonal of the points' bounding box, metres: how far the lump reaches.
    pub radius: f64,
    /// The points themselves.
    pub members: Vec<Point3<f32>>,
}

impl Component {
    /// One component of this and `other`'s points.
    pub fn joined_with(mut self, other: Component) -> Component {
        let n = (self.points + other.points) as f64;
        self.centroid = Point3::from(
            (self.centroid.coords * self.points as f64
                + other.centroid.coords * other.points as f64)
                / n,
        );
        self.points += other.points;
        self.voxels += other.voxels;
        self.distance_to_target = self.distance_to_target.min(other.distance_to_target);
        self.members.extend(other.members);
        let (lo, hi) = self.members.iter().fold(
            (Point3::from([f32::INFINITY; 3]), Point3::from([f32::NEG_INFINITY; 3])),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        self.radius = f64::from((hi - lo).norm()) / 2.0;
        self
    }
}

/// Occupied voxels of a cloud at a fixed resolution.
#[derive(Debug, Clone)]
pub struct OccupancyGrid {
    resolution: f32,
    /// Sorted voxel keys and, for each, the range of its points in `points`.
    keys: Vec<u64>,
    ranges: Vec<(u32, u32)>,
    points: Vec<Point3<f32>>,
    /// Least and greatest voxel coordinates occupied on each axis: most points asked about
    /// (the volume of interest against the tag's few voxels) fall outside them.
    bounds: [[i64; 3]; 2],
    /// The same box in metres, a voxel wider on every side (far beyond rounding): a point
    /// outside it is found outside without dividing and flooring its coordinates.
    reach: [[f32; 3]; 2],
}

const BITS: u32 = 21;
const OFFSET: i64 = 1 << (BITS - 1);

fn key_of(v: [i64; 3]) -> Option<u64> {
    let limit = 1 << BITS;
    let mut key = 0u64;
    for c in v {
        let shifted = c + OFFSET;
        if !(0..limit).contains(&shifted) {
            return None;
        }
        key = key << BITS | shifted as u64;
    }
    Some(key)
}

fn coords_of(key: u64) -> [i64; 3] {
    let mask = (1u64 << BITS) - 1;
    [(key >> (2 * BITS)) & mask, (key >> BITS) & mask, key & mask].map(|c| c as i64 - OFFSET)
}

impl OccupancyGrid {
    /// Bins `points` into cubic voxels of `resolution` metres (the paper uses 0.01). Points too far
    /// from the origin to index (beyond ±10 km at 1 cm) are left out.
    pub fn new(points: &[Point3<f32>], resolution: f32) -> Self {
        let mut keyed: Vec<(u64, Point3<f32>)> =
            points.iter().filter_map(|p| key_of(cube_of(p, resolution)).map(|k| (k, *p))).collect();
        keyed.sort_unstable_by_key(|&(k, _)| k);
        let mut keys = Vec::new();
        let mut ranges = Vec::new();
        for (i, &(k, _)) in keyed.iter().enumerate() {
            if keys.last() != Some(&k) {
                keys.push(k);
                ranges.push((i as u32, i as u32 + 1));
            } else if let Some(last) = ranges.last_mut() {
                last.1 = i as u32 + 1;
            }
        }
        let mut bounds = [[i64::MAX; 3], [i64::MIN; 3]];
        for &k in &keys {
            let v = coords_of(k);
            for axis in 0..3 {
                bounds[0][axis] = bounds[0][axis].min(v[axis]);
                bounds[1][axis] = bounds[1][axis].max(v[axis]);
            }
        }
        let reach = [
            bounds[0].map(|v| v.saturating_sub(1) as f32 * resolution),
            bounds[1].map(|v| v.saturating_add(2) as f32 * resolution),
        ];
        let points = keyed.into_iter().map(|(_, p)| p).collect();
        Self { resolution, keys, ranges, points, bounds, reach }
    }

    pub fn resolution(&self) -> f32 {
        self.resolution
    }

    /// Whether `p` falls in an occupied voxel.
    pub fn contains(&self, p: &Point3<f32>) -> bool {
        let [near, far] = &self.reach;
        let c = [p.x, p.y, p.z];
        if (0..3).any(|axis| c[axis] < near[axis] || c[axis] > far[axis]) {
            return false;
        }
        let v = cube_of(p, self.resolution);
        let [lo, hi] = &self.bounds;
        (0..3).all(|axis| (lo[axis]..=hi[axis]).contains(&v[axis]))
            && key_of(v).is_some_and(|k| self.keys.binary_search(&k).is_ok())
    }

    /// How many voxels are occupied.
    pub fn occupied(&self) -> usize {
        self.keys.len()
    }

    /// The 26-connected components of the occupied voxels, with their distance to `target`.
    pub fn connected_components(&self, target: &Point3<f64>) -> Vec<Component> {
        let found = flood_fill(
            self.keys.len(),
            |_| true,
            |v, push| {
                let [x, y, z] = coords_of(self.keys[v]);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let Some(k) = key_of([x + dx, y + dy, z + dz]) else { continue };
                            if let Ok(n) = self.keys.binary_search(&k) {
                                push(n);
                            }
                        }
                    }
                }
            },
        );
        found.members.iter().map(|voxels| self.component(voxels, target)).collect()
    }

    /// The component made of `voxels`, its points in the voxels' order.
    fn component(&self, voxels: &[usize], target: &Point3<f64>) -> Component {
        let (mut sum, mut nearest) = (nalgebra::Vector3::zeros(), f64::INFINITY);
        let (mut lo, mut hi) =
            (Point3::from([f32::INFINITY; 3]), Point3::from([f32::NEG_INFINITY; 3]));
        let mut members = Vec::new();
        for &v in voxels {
            let (from, to) = self.ranges[v];
            for p in &self.points[from as usize..to as usize] {
                (lo, hi) = (lo.inf(p), hi.sup(p));
                members.push(*p);
                let p: Point3<f64> = p.cast();
                sum += p.coords;
                nearest = nearest.min((p - target).norm());
            }
        }
        Component {
            centroid: Point3::from(sum / members.len() as f64),
            points: members.len(),
            voxels: voxels.len(),
            distance_to_target: nearest,
            radius: f64::from((hi - lo).norm()) / 2.0,
            members,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separates_lumps_more_than_a_voxel_apart() {
        let mut points = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                points.push(Point3::new(1.0, i as f32 * 0.005, j as f32 * 0.005));
                points.push(Point3::new(1.0, 0.3 + i as f32 * 0.005, j as f32 * 0.005));
            }
        }
        points.push(Point3::new(1.0, 0.1, 0.1)); // a speck on its own
        let grid = OccupancyGrid::new(&points, 0.01);
        let mut components = grid.connected_components(&Point3::new(1.0, 0.0, 0.0));
        components.sort_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target));
        assert_eq!(components.len(), 3);
        assert_eq!(components[0].points, 100);
        assert!((components[0].centroid - Point3::new(1.0, 0.0225, 0.0225)).norm() < 1e-4);
        assert_eq!(components[1].points, 1);
        assert_eq!(components[2].points, 100);
        assert!(components[0].distance_to_target < 1e-6);
    }

    #[test]
    fn diagonal_neighbours_connect() {
        let points = [
            Point3::new(0.005, 0.005, 0.005),
            Point3::new(0.015, 0.015, 0.015),
            Point3::new(-0.005, 0.005, 0.025),
        ];
        let grid = OccupancyGrid::new(&points, 0.01);
        assert_eq!(grid.occupied(), 3);
        assert_eq!(grid.connected_components(&Point3::origin()).len(), 2);
    }
}
