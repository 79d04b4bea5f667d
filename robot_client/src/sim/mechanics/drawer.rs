//! The drawer on its slide, with a towel hanging from its handle. Pushing its front or pulling the
//! pinched towel slides it once the force beats the slide's friction; it stops hard when closed or
//! fully open, and a stuck drawer does not slide at all. A towel pulled harder than the pinch's
//! friction holds slips out of the fingers.

use nalgebra::{Isometry3, Point3, Translation3, Vector3};

use super::contact::{
    DeviceFrame, FINGER_STIFFNESS, FingerForces, Hand, PAD_HALF_WIDTH, TIP_RADIUS, cuboid,
    last_positive, part, pinch,
};
use crate::sim::room::{DeviceKind, Room};

/// Force it takes to slide the drawer, newtons.
pub const SLIDE_FRICTION: f64 = 6.0;
/// How far the drawer opens before its stop, metres.
pub const FULL_OPENING: f64 = 0.38;
/// Stiffness of the taut towel between the handle and the pinch, along the slide, newtons per
/// metre.
const TOWEL_STIFFNESS: f64 = 1500.0;
/// Squeeze stiffness of the gathered towel and its half-width in the pinch (fingertips included).
const BUNDLE_STIFFNESS: f64 = 800.0;
const BUNDLE_HALF_WIDTH: f64 = 0.025;
/// Sideways spring of the towel hanging from the handle, newtons per metre.
const HANG_STIFFNESS: f64 = 150.0;
/// Friction of cloth in rubber fingertips: a pinch of total squeeze `s` holds `TOWEL_GRIP * s`.
const TOWEL_GRIP: f64 = 3.0;

/// The room's parts that slide with the drawer, by name.
pub const MOVING_PARTS: [&str; 3] = ["top drawer", "drawer handle", "drawer towel"];

#[derive(Debug, Clone, PartialEq)]
pub struct Drawer {
    /// Origin at the centre of the closed drawer's front panel.
    frame: DeviceFrame,
    /// Half-width, half-height and half-thickness of the front panel.
    panel: Vector3<f64>,
    /// The handle's front and its extent (along, up) from the frame's origin, closed.
    handle_front: f64,
    handle_half: (f64, f64),
    handle_up: f64,
    /// The middle of the towel's front, from the frame's origin, closed.
    towel: Vector3<f64>,
    towel_half: (f64, f64),
    stuck: bool,
    opening: f64,
    /// How far out from the handle the pinch caught the towel, metres, while it is pinched.
    towel_reach: Option<f64>,
}

impl Drawer {
    pub fn new(room: &Room, opening: f64, stuck: bool) -> Self {
        let out = room.device(DeviceKind::Drawer).tag_normal;
        let (panel_pose, panel) = cuboid(part(&room.scene, "top drawer"));
        let frame = DeviceFrame { origin: panel_pose.translation.vector.into(), out };
        let (handle_pose, handle) = cuboid(part(&room.scene, "drawer handle"));
        let (towel_pose, towel) = cuboid(part(&room.scene, "drawer towel"));
        let handle_centre = frame.local(&handle_pose.translation.vector.into());
        let towel_centre = frame.local(&towel_pose.translation.vector.into());
        Self {
            frame,
            panel: Vector3::new(panel.y, panel.z, panel.x),
            handle_front: handle_centre.y + handle.x,
            handle_half: (handle.y, handle.z),
            handle_up: handle_centre.z,
            towel: Vector3::new(towel_centre.x, towel_centre.y + towel.x, towel_centre.z),
            towel_half: (towel.y, towel.z),
            stuck,
            opening: opening.clamp(0.0, FULL_OPENING),
            towel_reach: None,
        }
    }

    pub fn opening(&self) -> f64 {
        self.opening
    }

    /// How the moving parts are displaced from where the room built them.
    pub fn displacement(&self) -> Isometry3<f64> {
        Translation3::from(self.frame.out * self.opening).into()
    }

    /// The middle of the towel's front, world frame.
    pub fn towel_front(&self) -> Point3<f64> {
        self.frame.origin + self.frame.world(&self.towel) + self.frame.out * self.opening
    }

    /// Where the towel hangs from the handle, world frame.
    fn anchor(&self, opening: f64) -> Point3<f64> {
        self.frame.origin
            + self.frame.world(&Vector3::new(0.0, self.handle_front, self.handle_up))
            + self.frame.out * opening
    }

    /// How far a fingertip at `local` presses into the drawer's front at `opening`, metres.
    fn depth(&self, local: &Vector3<f64>, opening: f64) -> f64 {
        let (along, up) = (local.x.abs() - PAD_HALF_WIDTH, local.z);
        if along > self.panel.x || up.abs() > self.panel.y {
            return 0.0;
        }
        let on_handle =
            along <= self.handle_half.0 && (up - self.handle_up).abs() <= self.handle_half.1;
        let front = opening + if on_handle { self.handle_front } else { self.panel.z };
        let reach = local.y - TIP_RADIUS;
        // A fingertip well behind the front is beside the drawer, not pressing on it.
        if reach < front - 0.05 { 0.0 } else { (front - reach).max(0.0) }
    }

    /// Settles the drawer against the hand; returns the fingers' forces.
    pub fn settle(&mut self, hand: &Hand) -> FingerForces {
        let locals = hand.tips.map(|t| self.frame.local(&t));
        let push = |opening: f64| {
            locals.iter().map(|l| FINGER_STIFFNESS * self.depth(l, opening)).sum::<f64>()
        };
        if !self.stuck && push(self.opening) > SLIDE_FRICTION {
            // The drawer slides in until the push no longer beats friction, or it is closed.
            let travel =
                last_positive(0.0, self.opening, |t| push(self.opening - t) - SLIDE_FRICTION);
            self.opening -= travel;
        }
        let mut forces =
            locals.map(|l| self.frame.out * FINGER_STIFFNESS * self.depth(&l, self.opening));
        let (left, right) = self.squeeze(hand);
        if left > 0.0 && right > 0.0 {
            let grasp = hand.pinch_point();
            // The hanging towel is taut once pulled: model it as a spring along the slide, the
            // only direction the drawer can follow.
            let out = self.frame.out;
            let closed_reach = (grasp - self.anchor(0.0)).dot(&out);
            let caught_at = *self.towel_reach.get_or_insert(closed_reach - self.opening);
            let tension =
                move |opening: f64| TOWEL_STIFFNESS * (closed_reach - opening - caught_at).max(0.0);
            if !self.stuck && tension(self.opening) > SLIDE_FRICTION {
                let travel = last_positive(0.0, FULL_OPENING - self.opening, |t| {
                    tension(self.opening + t) - SLIDE_FRICTION
                });
                self.opening += travel;
            }
            let tension = tension(self.opening);
            let direction = out;
            if tension > TOWEL_GRIP * (left + right) {
                // The towel slides out of the pinch: the fingers feel nothing from it any more.
                self.towel_reach = None;
            } else {
                forces[0] += hand.left * left - direction * (tension / 2.0);
                forces[1] += -hand.left * right - direction * (tension / 2.0);
            }
        } else {
            self.towel_reach = None;
        }
        forces
    }

    /// The squeeze of the gathered towel on the left and right fingers, when the towel is
    /// between them.
    fn squeeze(&self, hand: &Hand) -> (f64, f64) {
        let front = self.towel_front();
        let tip_ahead = hand.ahead(&hand.tips[0]).min(hand.ahead(&hand.tips[1]));
        let ahead = hand.ahead(&front);
        // Closing fingers gather the hanging cloth anywhere between the palm and their tips.
        let between = (0.0..=tip_ahead + TIP_RADIUS).contains(&ahead);
        let rest = hand.lateral(&front);
        let on_towel = (front.z - hand.palm.z).abs() <= self.towel_half.1
            && rest.abs() <= self.towel_half.0 + BUNDLE_HALF_WIDTH;
        if !(between && on_towel) {
            return (0.0, 0.0);
        }
        pinch(
            hand.lateral(&hand.tips[0]),
            hand.lateral(&hand.tips[1]),
            rest,
            BUNDLE_HALF_WIDTH,
            BUNDLE_STIFFNESS,
            HANG_STIFFNESS,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mechanics::contact::hand_facing;

    #[test]
    fn pushing_an_open_drawer_feels_its_friction_until_it_closes() {
        let room = Room::paper();
        for stuck in [false, true] {
            let mut drawer = Drawer::new(&room, 0.2, stuck);
            let (centre, out) = (drawer.frame.origin, drawer.frame.out);
            let mut felt = Vec::new();
            for step in 0..300 {
                // Fingertips on the panel below the towel, 1 mm further in each step.
                let tips_at = drawer.panel.z + 0.21 - 0.001 * f64::from(step) + TIP_RADIUS;
                let palm = centre + out * (tips_at + 0.1) - Vector3::z() * 0.13;
                let forces = drawer.settle(&hand_facing(out, palm, 0.1, 0.05));
                felt.push(forces[0].norm() + forces[1].norm());
                if felt.last().is_some_and(|&f| f > 20.0) {
                    break;
                }
            }
            if stuck {
                assert_eq!(drawer.opening(), 0.2);
            } else {
                assert_eq!(drawer.opening(), 0.0);
                let sliding = felt.iter().filter(|&&f| (f - SLIDE_FRICTION).abs() < 0.1).count();
                assert!(sliding > 150, "felt the slide's friction for {sliding} mm");
            }
        }
    }
}
