//! How the body moves against the world: every motion of the base, carriage, arm or gripper is
//! taken in small steps, and after each step the devices settle against the hand and the rigid
//! room pushes back on the fingertips. A motion stops at the step where the force on a finger
//! first exceeds its limit, refined to a fraction of a millimetre, so the fingers end up pressing
//! with about that force, as a force-limited motion does on a robot.

use nalgebra::{Point3, Vector3};

use super::body::BodyState;
use super::mechanics::{DeviceMechanics, FINGER_STIFFNESS, FingerForces, Hand, MOVING_PARTS};
use super::robot::SimState;
use super::room::DeviceKind;
use crate::hal::Finger;

/// How far a person standing on the floor reaches from where they stand, metres: feet and legs
/// about 40 cm across.
const PERSON_RADIUS: f64 = 0.2;

/// Halvings of a step when refining where a motion met its force limit.
const REFINEMENTS: usize = 10;
/// Force along the fingers past which the arm gives way backwards while the gripper moves,
/// newtons: closing fingers that meet a surface slide back along it instead of driving into it.
const ARM_YIELD_FORCE: f64 = 1.5;

impl SimState {
    /// The hand in the world frame, for `body`.
    pub(super) fn hand_at(&self, body: &BodyState) -> Hand {
        let world = body.world_from_base_3d();
        let tip = |f| world * body.fingertip(&self.geometry, f);
        Hand {
            palm: world * body.palm(&self.geometry),
            tips: [tip(Finger::Left), tip(Finger::Right)],
            forward: world * Vector3::x(),
            left: world * Vector3::y(),
            knuckle_offset: self.geometry.knuckle_offset,
        }
    }

    /// Forces of the rigid room (walls, furniture, the devices' fixed parts) on the fingertips,
    /// world frame: a spring pushing each tip out of whatever it is inside.
    fn rigid_forces(&self, hand: &Hand) -> FingerForces {
        hand.tips.map(|tip| {
            let p: Point3<f32> = tip.cast();
            self.room
                .scene
                .penetration_of(&p, |part| !MOVING_PARTS.contains(&part.name))
                .map_or(Vector3::zeros(), |(depth, out)| {
                    out.cast::<f64>() * f64::from(depth) * FINGER_STIFFNESS
                })
        })
    }

    /// The devices settled against the hand of `body`, and the total force on each finger.
    fn settled_at(&self, body: &BodyState) -> (DeviceMechanics, FingerForces) {
        let hand = self.hand_at(body);
        let mut devices = self.devices.clone();
        let from_devices = devices.settle(&hand);
        let rigid = self.rigid_forces(&hand);
        (devices, [from_devices[0] + rigid[0], from_devices[1] + rigid[1]])
    }

    /// Forces on the left and right fingers now, world frame, without disturbing anything.
    pub(super) fn finger_forces(&self) -> FingerForces {
        self.settled_at(&self.body).1
    }

    /// The body `fraction` of the way along `motion` from `start`; with `yielding_arm`, the arm
    /// retracts as far as it takes to keep the push along the fingers near `ARM_YIELD_FORCE`.
    fn place(
        &self,
        start: &BodyState,
        fraction: f64,
        motion: &dyn Fn(&mut BodyState, f64),
        yielding_arm: bool,
    ) -> BodyState {
        let mut body = *start;
        motion(&mut body, fraction);
        if yielding_arm {
            for _ in 0..3 {
                let hand = self.hand_at(&body);
                let push: f64 =
                    self.settled_at(&body).1.iter().map(|f| -f.dot(&hand.forward)).sum();
                if push <= ARM_YIELD_FORCE {
                    break;
                }
                let give = (push - ARM_YIELD_FORCE) / (2.0 * FINGER_STIFFNESS);
                body.arm_extension = (body.arm_extension - give).max(self.geometry.arm_travel.0);
            }
        }
        body
    }

    /// Moves the body along `motion` (which places it `fraction` of the way, 0 to 1) in `steps`
    /// steps, stopping where a finger's force first exceeds `max_force` and is still rising (so
    /// a hand pressing hard can always back away). Returns the fraction reached.
    pub(super) fn move_body(
        &mut self,
        steps: usize,
        max_force: f64,
        yielding_arm: bool,
        motion: impl Fn(&mut BodyState, f64),
    ) -> f64 {
        let start = self.body;
        let at = |state: &Self, fraction: f64| state.place(&start, fraction, &motion, yielding_arm);
        let peak = |forces: &FingerForces| forces.iter().map(|f| f.norm()).fold(0.0, f64::max);
        let mut before = peak(&self.finger_forces());
        let too_hard = |forces: &FingerForces, before: f64| {
            let now = peak(forces);
            now > max_force && now > before
        };
        let steps = steps.max(1);
        let mut reached = 0.0;
        let bumped_before = self.bumps(&start);
        for i in 1..=steps {
            let fraction = i as f64 / steps as f64;
            let body = at(self, fraction);
            // The base's bumper stops it at the step before its outline meets a person.
            if !bumped_before && self.bumps(&body) {
                break;
            }
            let (devices, forces) = self.settled_at(&body);
            if !too_hard(&forces, before) {
                self.go_to(body, devices);
                reached = fraction;
                before = peak(&forces);
                continue;
            }
            // Refine between the last step that was fine and this one; devices settle in order,
            // since a lever that snapped stays snapped.
            let mut over = (body, devices, fraction);
            for _ in 0..REFINEMENTS {
                let mid = 0.5 * (reached + over.2);
                let body = at(self, mid);
                let (devices, forces) = self.settled_at(&body);
                if too_hard(&forces, before) {
                    over = (body, devices, mid);
                } else {
                    self.go_to(body, devices);
                    reached = mid;
                    before = peak(&forces);
                }
            }
            let (body, _, fraction) = over;
            let (devices, _) = self.settled_at(&body);
            self.go_to(body, devices);
            reached = fraction;
            break;
        }
        self.show_moving_parts();
        reached
    }

    /// Whether the base's outline at `body` meets the person standing in the room, if one does.
    fn bumps(&self, body: &BodyState) -> bool {
        self.person.is_some_and(|person| {
            let p = body.world_from_base.inverse_transform_point(&person);
            let dx = (p.x.abs() - self.geometry.base_front).max(0.0);
            let dy = (p.y.abs() - self.geometry.base_half_width).max(0.0);
            dx.hypot(dy) <= PERSON_RADIUS
        })
    }

    /// Puts the body at `body` with the devices settled as `devices`, keeping the base's and
    /// the body's paths.
    fn go_to(&mut self, body: BodyState, devices: DeviceMechanics) {
        if body.world_from_base != self.body.world_from_base {
            self.base_path.push(body.world_from_base);
        }
        if body != self.body {
            self.body_path.push(body);
        }
        (self.body, self.devices) = (body, devices);
    }

    /// Moves the parts the camera and laser see (the drawer, the lever) and the drawer's tag to
    /// where the mechanics put them.
    pub(super) fn show_moving_parts(&mut self) {
        self.room.scene.move_parts(&self.devices.part_poses());
        let tag = self.devices.drawer_tag();
        if let Some(drawer) = self.room.devices.iter_mut().find(|d| d.kind == DeviceKind::Drawer) {
            drawer.tag_center = tag;
        }
    }
}
