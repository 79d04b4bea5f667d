//! The sensors and lights of a drawn scene: the camera's pose, the laser's mount and sweep, the
//! room's lights and the flash.

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use rand::Rng;

use crate::clutter::Room;
use crate::draw::Draw;
use crate::laser::LaserModel;
use crate::lighting::{Lighting, Lights, PointLight};
use crate::scene::Pose;

/// The base frame from the optical frame of a camera at `eye` with the given yaw, pitch down and
/// roll, radians.
pub(crate) fn optical_pose(eye: Point3<f64>, yaw: f64, pitch: f64, roll: f64) -> Isometry3<f64> {
    let z = Vector3::new(pitch.cos() * yaw.cos(), pitch.cos() * yaw.sin(), -pitch.sin());
    let x0 = Vector3::new(yaw.sin(), -yaw.cos(), 0.0);
    let y0 = z.cross(&x0);
    let x = x0 * roll.cos() + y0 * roll.sin();
    let y = z.cross(&x);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    Isometry3::from_parts(
        Translation3::from(eye.coords),
        UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// The laser: mounted 5–30 cm from the camera, its sweep covering the volume around the tag,
/// its density growing with the image size (60k points at 640 wide to 250k at 1280).
pub(crate) fn draw_laser(
    d: &mut Draw,
    camera: &Isometry3<f64>,
    camera_yaw: f64,
    tag: &Point3<f64>,
    width: u32,
) -> LaserModel {
    let direction = Vector3::new(d.u(-0.3, 0.5), d.u(-0.6, 0.6), d.u(-1.0, 0.3)).normalize();
    let head_at = camera.translation.vector + direction * d.u(0.05, 0.30);
    let head_yaw = camera_yaw + d.u(-3f64, 3.0).to_radians();
    let mount = UnitQuaternion::from_euler_angles(
        d.u(-1f64, 1.0).to_radians(),
        d.u(-1f64, 1.0).to_radians(),
        head_yaw,
    );
    let head = Isometry3::from_parts(Translation3::from(head_at), mount);
    let to_tag = tag - Point3::from(head_at);
    let reach = to_tag.xy().norm();
    let (near, far) = ((reach - 0.55).max(0.25), reach + 0.55);
    let (top, bottom) = (tag.z + 0.55 - head_at.z, (tag.z - 0.55).max(0.0) - head_at.z);
    let up = top.atan2(if top > 0.0 { near } else { far });
    let down = bottom.atan2(if bottom < 0.0 { near } else { far });
    let tilt_from_deg = (-up.to_degrees() - d.u(3.0, 12.0)).max(-60.0);
    let tilt_to_deg = (-down.to_degrees() + d.u(3.0, 12.0)).min(80.0);
    let off_axis = (to_tag.y.atan2(to_tag.x) - head_yaw).to_degrees().abs();
    let needed = (0.55 / reach).min(1.0).asin().to_degrees() + off_axis + 3.0;
    let bearing_half_span_deg = d.u(45.0, 90.0).max(needed);
    let beam_step_deg = d.u(0.25, 0.5);
    let beams = (2.0 * bearing_half_span_deg / beam_step_deg).floor() + 1.0;
    let size = (f64::from(width) - 640.0) / 640.0;
    let points = ((60_000.0 + 190_000.0 * size) * d.u(0.85, 1.15)).clamp(60_000.0, 250_000.0);
    let lines = points / 0.95 / beams;
    let tilt_step_deg = ((tilt_to_deg - tilt_from_deg) / lines).clamp(0.05, 1.0);
    LaserModel {
        head: Pose::from_isometry(&head),
        axis_offset_m: d.u(0.0, 0.04),
        bearing_half_span_deg,
        beam_step_deg,
        tilt_from_deg,
        tilt_to_deg,
        tilt_step_deg,
        tilt_jitter_deg: d.u(0.02, 0.12),
        divergence_deg: d.u(0.15, 0.45),
        noise_scale: d.u(0.8, 1.6),
        dropout_rate: d.u(0.0, 0.05),
        min_range_m: 0.1,
        max_range_m: 8.0,
    }
}

pub(crate) fn draw_lights(
    lighting: Lighting,
    room: &Room,
    base_from_device: &Isometry3<f64>,
    camera: &Isometry3<f64>,
    d: &mut Draw,
) -> Lights {
    let warm = [1.0, 0.78, 0.5];
    let daylight = [1.0, 0.97, 0.92];
    let (ambient, count, power, colour) = match lighting {
        Lighting::Bright => (
            d.u(0.06, 0.15),
            d.rng.random_range(1..=2),
            d.u(1.0, 3.0),
            if d.chance(0.5) { daylight } else { warm },
        ),
        Lighting::Dim => (d.u(0.005, 0.03), 1, d.u(0.0, 0.4), warm),
    };
    let room_lights = (0..count)
        .map(|_| {
            let at =
                Point3::new(room.wall_x_m + d.u(0.8, 2.5), d.u(-1.5, 1.5), room.ceiling_m - 0.05);
            PointLight {
                position: (base_from_device * at).coords.into(),
                intensity: colour.map(|c| c * power),
            }
        })
        .collect();
    let ambient_colour = if lighting == Lighting::Dim { warm } else { colour };
    let flash_at = camera * Point3::new(d.u(-0.02, 0.02), -d.u(0.02, 0.06), 0.0);
    let flash_power = d.u(0.8, 1.2);
    Lights {
        ambient: ambient_colour.map(|c| c * ambient),
        room: room_lights,
        flash: Some(PointLight {
            position: flash_at.coords.into(),
            intensity: [1.0, 0.98, 0.95].map(|c| c * flash_power),
        }),
    }
}
