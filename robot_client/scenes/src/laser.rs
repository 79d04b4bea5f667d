//! The tilting laser: a planar scanner on a servo, mounted apart from the camera, sweeping the
//! scene line by line. What it gets wrong, as real ones do:
//!
//! - range noise whose σ grows with range and with the incidence angle (2 to 12 mm);
//! - dropouts, a few percent anywhere and many more at grazing incidence or on dark surfaces;
//! - mixed pixels: a beam whose footprint straddles a depth edge returns a range between the two
//!   surfaces (the veil of points between a towel and the drawer behind it);
//! - servo jitter: each line's true tilt is off by a small random angle, while the points are
//!   computed from the commanded one, as the robot's driver does.
//!
//! Points come back in the base frame (x forward, y left, z up, metres).

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Vector3};
use pps_robot::hal::PointCloud;
use serde::{Deserialize, Serialize};

use crate::caster::RayCaster;
use crate::geometry::Ray;
use crate::noise::NoiseSource;
use crate::scene::Pose;

/// Beams of one scan line that share a cull.
const CHUNK: usize = 24;
/// A neighbour further than this in range, metres, is another surface.
const DEPTH_EDGE: f64 = 0.02;

/// The scanner, its servo and its flaws.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LaserModel {
    /// Base frame from the scan head at zero tilt: the scan plane is the head's x–y plane, the
    /// middle beam along its x; the servo tilts the head about its y axis.
    pub head: Pose,
    /// Height of the optical centre above the tilt axis, metres: it moves as the head tilts.
    pub axis_offset_m: f64,
    /// Beams fan out ±`bearing_half_span_deg` from the middle beam, `beam_step_deg` apart.
    pub bearing_half_span_deg: f64,
    pub beam_step_deg: f64,
    /// The commanded sweep, degrees, positive tilting the forward edge down.
    pub tilt_from_deg: f64,
    pub tilt_to_deg: f64,
    pub tilt_step_deg: f64,
    /// σ of each line's tilt error, degrees.
    pub tilt_jitter_deg: f64,
    /// Full angle of the beam's footprint, degrees.
    pub divergence_deg: f64,
    /// Scales the range noise (a better or a worse unit), about 1.
    pub noise_scale: f64,
    /// Chance of no return on a bright surface seen square on, 0..0.05.
    pub dropout_rate: f64,
    pub min_range_m: f64,
    pub max_range_m: f64,
}

/// One sweep: the cloud, and which primitive each point came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    pub cloud: PointCloud,
    /// For each point, the primitive its beam's centre met.
    pub sources: Vec<u32>,
}

/// One beam's true return, before noise.
#[derive(Debug, Clone, Copy)]
struct Return {
    range: f64,
    incidence: f64,
    reflectance: f64,
    primitive: u32,
}

impl LaserModel {
    /// σ of the range noise, metres, at `range` metres and `incidence` radians from the normal.
    pub fn range_sigma(&self, range: f64, incidence: f64) -> f64 {
        let slant = 1.0 / incidence.cos().max(0.05) - 1.0;
        (self.noise_scale * (0.002 + 0.0025 * range + 0.003 * slant)).clamp(0.002, 0.012)
    }

    /// Chance of no return at `incidence` radians on a surface of mean `reflectance`.
    pub fn dropout_probability(&self, incidence: f64, reflectance: f64) -> f64 {
        let grazing = ((incidence.to_degrees() - 60.0) / 30.0).max(0.0);
        let dark = (0.15 - reflectance).max(0.0);
        (self.dropout_rate + 0.35 * grazing * grazing + 0.3 * dark).min(1.0)
    }

    fn bearings(&self) -> Vec<f64> {
        let n = (2.0 * self.bearing_half_span_deg / self.beam_step_deg).floor() as usize + 1;
        (0..n)
            .map(|i| (-self.bearing_half_span_deg + i as f64 * self.beam_step_deg).to_radians())
            .collect()
    }

    fn tilts(&self) -> Vec<f64> {
        let n = ((self.tilt_to_deg - self.tilt_from_deg) / self.tilt_step_deg).floor() as usize + 1;
        (0..n).map(|i| (self.tilt_from_deg + i as f64 * self.tilt_step_deg).to_radians()).collect()
    }

    /// How many beams the sweep fires.
    pub fn beam_count(&self) -> usize {
        self.bearings().len() * self.tilts().len()
    }

    /// The head's pose at `tilt` radians: base frame from the beam frame.
    fn head_at(&self, tilt: f64) -> Isometry3<f64> {
        let tilted = Isometry3::rotation(Vector3::y() * tilt);
        self.head.isometry() * tilted * Isometry3::translation(0.0, 0.0, self.axis_offset_m)
    }

    /// Sweeps the scene, drawing every flaw from `noise`.
    pub fn scan(&self, caster: &RayCaster, noise: &mut NoiseSource) -> Sweep {
        let bearings = self.bearings();
        let tilts = self.tilts();
        let local: Vec<Vector3<f64>> =
            bearings.iter().map(|b| Vector3::new(b.cos(), b.sin(), 0.0)).collect();
        let step = self.beam_step_deg.to_radians();
        let mut grid: Vec<Option<Return>> = vec![None; tilts.len() * bearings.len()];
        let mut candidates = Vec::new();
        for (i, &tilt) in tilts.iter().enumerate() {
            let jitter = self.tilt_jitter_deg.to_radians() * noise.normal();
            let actual = self.head_at(tilt + jitter);
            let rotation: Matrix3<f64> = *actual.rotation.to_rotation_matrix().matrix();
            let origin = Point3::from(actual.translation.vector);
            for (c, chunk) in local.chunks(CHUNK).enumerate() {
                let middle = rotation * chunk[chunk.len() / 2];
                let half_angle = (chunk.len() as f64 / 2.0 + 1.0) * step;
                caster.cull_cone(&origin, &middle, half_angle, &mut candidates);
                for (k, beam) in chunk.iter().enumerate() {
                    let ray = Ray::new(origin, rotation * beam);
                    let Some(hit) = caster.cast(&ray, &candidates, self.max_range_m) else {
                        continue;
                    };
                    if hit.t < self.min_range_m {
                        continue;
                    }
                    grid[i * bearings.len() + c * CHUNK + k] = Some(Return {
                        range: hit.t,
                        incidence: hit.normal.dot(&-ray.direction).clamp(-1.0, 1.0).acos(),
                        reflectance: caster.material(hit.primitive).reflectance(),
                        primitive: hit.primitive,
                    });
                }
            }
        }
        self.measure(&grid, &tilts, &local, noise)
    }

    /// The measured points: mixed pixels, noise and dropouts on the true returns, placed along
    /// the commanded beam directions.
    fn measure(
        &self,
        grid: &[Option<Return>],
        tilts: &[f64],
        local: &[Vector3<f64>],
        noise: &mut NoiseSource,
    ) -> Sweep {
        let columns = local.len();
        // Chance that a footprint reaches the edge between it and the neighbour, per direction.
        let half_footprint = self.divergence_deg / 2.0;
        let reach_along_line = (half_footprint / self.beam_step_deg).min(1.0);
        let reach_across_lines = (half_footprint / self.tilt_step_deg).min(1.0);
        let mut points = Vec::with_capacity(grid.len());
        let mut sources = Vec::with_capacity(grid.len());
        for (i, &tilt) in tilts.iter().enumerate() {
            let commanded = self.head_at(tilt);
            let rotation: Rotation3<f64> = commanded.rotation.to_rotation_matrix();
            let origin = Point3::from(commanded.translation.vector);
            for j in 0..columns {
                let Some(ret) = grid[i * columns + j] else { continue };
                let neighbours = [
                    (j > 0).then(|| grid[i * columns + j - 1]).map(|n| (n, reach_along_line)),
                    (j + 1 < columns)
                        .then(|| grid[i * columns + j + 1])
                        .map(|n| (n, reach_along_line)),
                    (i > 0).then(|| grid[(i - 1) * columns + j]).map(|n| (n, reach_across_lines)),
                    (i + 1 < tilts.len())
                        .then(|| grid[(i + 1) * columns + j])
                        .map(|n| (n, reach_across_lines)),
                ];
                let mut range = ret.range;
                let mut lost = false;
                for (neighbour, reach) in neighbours.into_iter().flatten() {
                    let other = neighbour.map(|n| n.range);
                    if other.is_some_and(|r| (r - ret.range).abs() < DEPTH_EDGE) {
                        continue;
                    }
                    if noise.chance(reach) {
                        // Up to half the footprint lies on the other side of the edge.
                        let share = 0.5 * noise.uniform();
                        match other {
                            Some(r) => range = (1.0 - share) * ret.range + share * r,
                            None => lost = noise.chance(share),
                        }
                        break;
                    }
                }
                if lost || noise.chance(self.dropout_probability(ret.incidence, ret.reflectance)) {
                    continue;
                }
                range += self.range_sigma(range, ret.incidence) * noise.normal();
                let p = origin + rotation * (local[j] * range);
                points.push(p.cast::<f32>());
                sources.push(ret.primitive);
            }
        }
        Sweep { cloud: PointCloud { points }, sources }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use crate::lighting::Lights;
    use crate::materials::WALLS;
    use crate::scene::{Primitive, Scene};
    use nalgebra::UnitQuaternion;

    fn model() -> LaserModel {
        LaserModel {
            head: Pose::at(Vector3::new(0.0, 0.0, 1.0)),
            axis_offset_m: 0.0,
            bearing_half_span_deg: 10.0,
            beam_step_deg: 0.5,
            tilt_from_deg: -10.0,
            tilt_to_deg: 10.0,
            tilt_step_deg: 0.5,
            tilt_jitter_deg: 0.0,
            divergence_deg: 0.0,
            noise_scale: 1.0,
            dropout_rate: 0.0,
            min_range_m: 0.05,
            max_range_m: 10.0,
        }
    }

    #[test]
    fn a_wall_ahead_comes_back_where_it_is_in_the_base_frame() {
        let wall = Primitive::new(
            "wall",
            Shape::Rectangle { half_size: [2.0, 2.0] },
            Isometry3::from_parts(
                Vector3::new(2.0, 0.0, 1.0).into(),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
            ),
            WALLS[0],
        );
        let scene = Scene {
            primitives: vec![wall],
            lights: Lights { ambient: [0.0; 3], room: vec![], flash: None },
        };
        let caster = RayCaster::new(&scene);
        let laser = model();
        let sweep = laser.scan(&caster, &mut NoiseSource::new(1, 2));
        assert_eq!(sweep.cloud.len(), laser.beam_count(), "no dropouts asked for");
        let mean_x: f64 = sweep.cloud.points.iter().map(|p| f64::from(p.x)).sum::<f64>()
            / sweep.cloud.len() as f64;
        assert!((mean_x - 2.0).abs() < 0.002, "{mean_x}");
        // Positive tilt looks down: the first line (tilt −10°) is above the head.
        assert!(sweep.cloud.points[0].z > 1.3);
        assert!(sweep.cloud.points.last().unwrap().z < 0.7);
    }
}
