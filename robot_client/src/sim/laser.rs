//! The tilting laser: a planar scanner swept by a servo, ray cast against the room with range
//! noise, random dropouts and the dropouts of grazing incidence.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;

use super::noise::SensorNoise;
use super::scene::Scene;
use crate::hal::{PointCloud, TiltSweep};

/// The scanner and its mount.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserModel {
    /// The scan head at zero tilt, base frame. The scan plane is the head's x-y plane (the middle
    /// beam along x); the servo tilts it about the head's y axis.
    pub base_from_head: Isometry3<f64>,
    /// Half the scan's field of view and the angle between beams, radians.
    pub half_field_of_view: f64,
    pub beam_step: f64,
    /// Standard deviation of the range noise, metres.
    pub range_noise: f64,
    /// Probability that a beam returns nothing, anywhere.
    pub dropout: f64,
    pub max_range: f64,
}

impl Default for LaserModel {
    /// A Hokuyo UTM-30LX-like scanner (0.25° steps) a metre above the floor, cropped to ±45°.
    fn default() -> Self {
        Self {
            base_from_head: Isometry3::translation(0.15, 0.0, 1.0),
            half_field_of_view: 45f64.to_radians(),
            beam_step: 0.25f64.to_radians(),
            range_noise: 0.006,
            dropout: 0.005,
            max_range: 30.0,
        }
    }
}

/// Sweeps the scan plane through `sweep` and returns the returns in the base frame.
pub fn sweep_scan(
    scene: &Scene,
    world_from_base: &Isometry3<f64>,
    model: &LaserModel,
    sweep: &TiltSweep,
    rng: &mut impl Rng,
) -> PointCloud {
    let beams = (2.0 * model.half_field_of_view / model.beam_step).round() as usize + 1;
    let mut points = Vec::with_capacity(beams * sweep.angles().count());
    let mut noise = SensorNoise::new(rng);
    for tilt in sweep.angles() {
        // Positive tilt turns the forward edge of the scan plane down.
        let base_from_tilted = model.base_from_head
            * Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), tilt),
            );
        let world_from_tilted: Isometry3<f32> = (world_from_base * base_from_tilted).cast();
        let base_from_tilted: Isometry3<f32> = base_from_tilted.cast();
        let origin = Point3::from(world_from_tilted.translation.vector);
        for b in 0..beams {
            let bearing = -model.half_field_of_view + b as f64 * model.beam_step;
            let local = Vector3::new(bearing.cos() as f32, bearing.sin() as f32, 0.0);
            let dir = world_from_tilted.rotation * local;
            let Some(hit) = scene.cast(&origin, &dir, model.max_range as f32) else { continue };
            // Returns fade as the beam grazes the surface.
            let incidence = hit.normal.dot(&-dir).clamp(0.0, 1.0);
            let grazing = ((0.2 - incidence) / 0.2).max(0.0) as f64 * 0.9;
            if noise.chance(model.dropout + grazing) {
                continue;
            }
            let range = f64::from(hit.distance) + model.range_noise * noise.gaussian();
            points.push(base_from_tilted * Point3::from(local * range as f32));
        }
    }
    PointCloud { points }
}
