//! The flip-type light switch: a lever in a foam tube that snaps between up and down. Sweeping it
//! past its midpoint with a few newtons flips it, and each flip toggles the ceiling light.

use nalgebra::{Point3, Vector2, Vector3};

use super::contact::{
    DeviceFrame, FINGER_STIFFNESS, FingerForces, Hand, PAD_HALF_WIDTH, TIP_RADIUS, cylinder,
    last_positive, part,
};
use crate::sim::room::Room;

/// Angle of the lever from the wall's normal at either stop, radians.
const REST_ANGLE: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Force at the fingertip the spring resists with at the lever's midpoint, newtons: past it the
/// lever snaps to the other side.
pub const SNAP_FORCE: f64 = 4.0;

/// The lever and which side it rests on.
#[derive(Debug, Clone, PartialEq)]
pub struct FlipSwitch {
    /// Origin at the lever's pivot.
    frame: DeviceFrame,
    /// Length and radius of the foam tube around the lever, metres.
    length: f64,
    radius: f64,
    up: bool,
}

impl FlipSwitch {
    pub fn new(room: &Room, up: bool) -> Self {
        let (centre, axis, half_height, radius) = cylinder(part(&room.scene, "switch foam tube"));
        let out = room.device(crate::sim::DeviceKind::LightSwitch).tag_normal;
        // The room builds the tube pointing up; its inner end is the pivot.
        let pivot = centre - axis * half_height;
        Self { frame: DeviceFrame { origin: pivot, out }, length: 2.0 * half_height, radius, up }
    }

    pub fn is_up(&self) -> bool {
        self.up
    }

    /// The tube's centre and axis as the lever rests now, world frame: where the camera sees it.
    pub fn tube(&self) -> (Point3<f64>, Vector3<f64>) {
        let angle = if self.up { REST_ANGLE } else { -REST_ANGLE };
        let axis = self.frame.world(&Vector3::new(0.0, angle.cos(), angle.sin()));
        (self.frame.origin + axis * (self.length / 2.0), axis)
    }

    /// Settles the lever against the fingertips; returns the fingers' forces and whether the
    /// lever flipped.
    pub fn settle(&mut self, hand: &Hand) -> (FingerForces, bool) {
        let mut forces = [Vector3::zeros(); 2];
        let mut flipped = false;
        for (tip, force) in hand.tips.iter().zip(&mut forces) {
            let local = self.frame.local(tip);
            if local.x.abs() - PAD_HALF_WIDTH > self.radius {
                continue;
            }
            let finger = Vector2::new(local.y, local.z);
            let rest = if self.up { REST_ANGLE } else { -REST_ANGLE };
            let axis = Vector2::new(rest.cos(), rest.sin());
            // +1 when the finger is below the lever and pushes it up.
            let push = if axis.perp(&finger) < 0.0 { 1.0 } else { -1.0 };
            let toward_other_side = (push > 0.0) != self.up;
            let mut angle = rest;
            if toward_other_side {
                // The spring resists in proportion to how far the lever has left its stop, up to
                // SNAP_FORCE at the midpoint; the lever sits where that balances the finger.
                let balance = |travel: f64| {
                    let a = rest + push * travel;
                    FINGER_STIFFNESS * self.depth(a, &finger) - SNAP_FORCE * travel / REST_ANGLE
                };
                let travel = last_positive(0.0, REST_ANGLE, balance);
                if travel >= REST_ANGLE {
                    self.up = !self.up;
                    flipped = true;
                    angle = -rest;
                } else {
                    angle = rest + push * travel;
                }
            }
            let depth = self.depth(angle, &finger);
            if depth > 0.0 {
                let out = self.away_from_lever(angle, &finger);
                *force =
                    self.frame.world(&Vector3::new(0.0, out.x, out.y)) * FINGER_STIFFNESS * depth;
            }
        }
        (forces, flipped)
    }

    /// How deep a fingertip at `finger` (out, up from the pivot) is in the tube at `angle`.
    fn depth(&self, angle: f64, finger: &Vector2<f64>) -> f64 {
        let axis = Vector2::new(angle.cos(), angle.sin());
        let along = finger.dot(&axis).clamp(0.0, self.length);
        self.radius + TIP_RADIUS - (finger - axis * along).norm()
    }

    /// Unit direction from the tube's axis to the fingertip.
    fn away_from_lever(&self, angle: f64, finger: &Vector2<f64>) -> Vector2<f64> {
        let axis = Vector2::new(angle.cos(), angle.sin());
        let along = finger.dot(&axis).clamp(0.0, self.length);
        (finger - axis * along).try_normalize(1e-9).unwrap_or(Vector2::new(1.0, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mechanics::contact::hand_facing;

    /// Sweeps fingertips `half_span` apart up past the lever, 1.7 cm out from its pivot;
    /// returns the largest force felt before the lever flipped, and whether it did.
    fn sweep_up(half_span: f64) -> (f64, bool) {
        let room = Room::paper();
        let mut lever = FlipSwitch::new(&room, false);
        let (pivot, out) = (lever.frame.origin, lever.frame.out);
        let mut peak: f64 = 0.0;
        for step in 0..80 {
            let height = -0.04 + 0.001 * f64::from(step);
            let palm = pivot + out * 0.117 + Vector3::z() * height;
            let (forces, flipped) = lever.settle(&hand_facing(out, palm, 0.1, half_span));
            if flipped {
                return (peak, true);
            }
            peak = peak.max(forces[0].norm());
        }
        (peak, false)
    }

    #[test]
    fn the_lever_snaps_over_at_a_few_newtons() {
        let (peak, flipped) = sweep_up(0.02);
        assert!(flipped);
        assert!(peak > 0.6 * SNAP_FORCE && peak <= SNAP_FORCE + 0.5, "peak {peak:.2} N");
        // Fingers spread wider than the foam tube pass either side of it.
        assert_eq!(sweep_up(0.05), (0.0, false));
    }
}
