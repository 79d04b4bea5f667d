//! The ADA rocker light switch: a paddle that rocks about its horizontal centre line. Pressing the
//! half that stands out, normal to the wall, past a couple of newtons and a few millimetres snaps
//! it over; each snap toggles the ceiling light.

use nalgebra::Vector3;

use super::contact::{
    DeviceFrame, FINGER_STIFFNESS, FingerForces, Hand, PAD_HALF_WIDTH, TIP_RADIUS, cuboid, part,
};
use crate::sim::room::{DeviceKind, Room};

/// Force at the fingertip the paddle resists with just before it snaps over, newtons.
pub const SNAP_FORCE: f64 = 2.5;
/// Tilt of the paddle at either stop, radians: the raised half stands 3 mm out 2 cm from the
/// pivot.
const TILT: f64 = 0.15;
/// Around the pivot line a press cannot rock the paddle, metres.
const DEAD_BAND: f64 = 0.006;

#[derive(Debug, Clone, PartialEq)]
pub struct RockerSwitch {
    /// Origin on the pivot line, on the face of the untilted paddle.
    frame: DeviceFrame,
    /// Half the paddle's width along the wall and its height, metres.
    half_width: f64,
    half_height: f64,
    top_pressed: bool,
}

impl RockerSwitch {
    pub fn new(room: &Room, top_pressed: bool) -> Self {
        let (pose, half) = cuboid(part(&room.scene, "rocker dycem"));
        let out = room.device(DeviceKind::AdaLightSwitch).tag_normal;
        let face = nalgebra::Point3::from(pose.translation.vector) + out * half.x;
        Self {
            frame: DeviceFrame { origin: face, out },
            half_width: half.y,
            half_height: half.z.max(0.033),
            top_pressed,
        }
    }

    pub fn is_top_pressed(&self) -> bool {
        self.top_pressed
    }

    /// Settles the paddle against the fingertips; returns the fingers' forces and whether it
    /// snapped over.
    pub fn settle(&mut self, hand: &Hand) -> (FingerForces, bool) {
        let mut forces = [Vector3::zeros(); 2];
        let mut snapped = false;
        for (tip, force) in hand.tips.iter().zip(&mut forces) {
            let local = self.frame.local(tip);
            let (height, reach) = (local.z, local.y - TIP_RADIUS);
            if local.x.abs() - PAD_HALF_WIDTH > self.half_width
                || height.abs() > self.half_height
                || reach < -0.015
            {
                continue;
            }
            // Tilt > 0 has the top half pressed in; the face at `height` stands out by -tilt·h.
            let stop = if self.top_pressed { TILT } else { -TILT };
            let face = |tilt: f64| -tilt * height;
            let raised_half = (height > 0.0) != self.top_pressed;
            let mut tilt = stop;
            if raised_half && height.abs() > DEAD_BAND {
                // Pressing the raised half rocks the paddle toward its middle against a spring
                // that reaches SNAP_FORCE there.
                let toward = -stop.signum();
                let balance = |travel: f64| {
                    FINGER_STIFFNESS * (face(stop + toward * travel) - reach)
                        - SNAP_FORCE * travel / TILT
                };
                let travel = super::contact::last_positive(0.0, TILT, balance);
                if travel >= TILT {
                    self.top_pressed = !self.top_pressed;
                    snapped = true;
                    tilt = -stop;
                } else {
                    tilt = stop + toward * travel;
                }
            }
            let depth = face(tilt) - reach;
            if depth > 0.0 {
                *force = self.frame.out * FINGER_STIFFNESS * depth;
            }
        }
        (forces, snapped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mechanics::contact::hand_facing;

    /// Presses at `height` above the pivot line, closing in a tenth of a millimetre at a time
    /// until the fingers feel `limit`; returns the peak force before a snap and whether it
    /// snapped.
    fn press(height: f64, limit: f64) -> (f64, bool) {
        let room = Room::paper();
        let mut paddle = RockerSwitch::new(&room, false);
        let (face, out) = (paddle.frame.origin, paddle.frame.out);
        let mut peak: f64 = 0.0;
        for step in 0..400 {
            let gap = 0.01 - 0.0001 * f64::from(step);
            let palm = face + out * (0.1 + TIP_RADIUS + gap) + Vector3::z() * height;
            let (forces, snapped) = paddle.settle(&hand_facing(out, palm, 0.1, 0.02));
            if snapped {
                return (peak, true);
            }
            peak = peak.max(forces[0].norm());
            if peak > limit {
                break;
            }
        }
        (peak, false)
    }

    #[test]
    fn the_raised_half_snaps_past_its_force_and_the_pivot_line_never_does() {
        let (peak, snapped) = press(0.02, 3.0);
        assert!(snapped && peak > 2.0 && peak <= SNAP_FORCE + 0.1, "peak {peak:.2} N");
        assert!(!press(0.02, 2.0).1, "a 2 N touch does not switch it");
        assert!(!press(0.0, 20.0).1, "the pivot line is rigid");
        assert!(!press(-0.02, 20.0).1, "the pressed half is at its stop");
    }
}
