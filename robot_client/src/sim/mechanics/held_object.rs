//! The object in the hand and the trash can it is dropped into. Opening the gripper lets the
//! object fall, into the can when it is above the can's opening; a sticky object stays stuck to a
//! finger instead.

use nalgebra::{Isometry3, Point3, Vector3};

use super::contact::{FINGER_STIFFNESS, FingerForces, Hand, TIP_RADIUS, cuboid, part, pinch};
use crate::sim::body::BodyGeometry;
use crate::sim::room::Room;

/// Radius and weight of the object (a ball of tape, as in the paper's sticky trial).
pub const OBJECT_RADIUS: f64 = 0.025;
pub const OBJECT_WEIGHT: f64 = 1.0;
/// How far ahead of the palm the held object's centre is, metres: about the middle of the
/// fingers.
const OBJECT_AHEAD: f64 = 0.06;
/// How far ahead of the palm the held object's near side is, metres: what the palm IR sees.
pub const OBJECT_RANGE: f64 = OBJECT_AHEAD - OBJECT_RADIUS;
/// Squeeze the gripper starts with on an object it already holds, newtons.
const START_SQUEEZE: f64 = 3.0;

#[derive(Debug, Clone, PartialEq)]
pub struct HeldObject {
    pub in_hand: bool,
    pub in_trash: bool,
    sticky: bool,
    /// The trash can's pose and half extents (out, along, up).
    can: (Isometry3<f64>, Vector3<f64>),
}

impl HeldObject {
    pub fn new(room: &Room, in_hand: bool, sticky: bool) -> Self {
        Self { in_hand, in_trash: false, sticky, can: cuboid(part(&room.scene, "trash can")) }
    }

    /// The gripper opening, radians, at which the fingers hold the object with a firm squeeze.
    pub fn holding_opening(geometry: &BodyGeometry) -> f64 {
        let contact = OBJECT_RADIUS + TIP_RADIUS - START_SQUEEZE / FINGER_STIFFNESS;
        2.0 * ((contact - geometry.knuckle_offset) / OBJECT_AHEAD.min(geometry.finger_length))
            .asin()
    }

    /// Settles the object in the hand; returns the fingers' forces.
    pub fn settle(&mut self, hand: &Hand) -> FingerForces {
        if !self.in_hand {
            return [Vector3::zeros(); 2];
        }
        // The fingers touch the object part way along, where they are narrower than at the tips.
        let along = OBJECT_AHEAD / hand.ahead(&hand.tips[0]).max(OBJECT_AHEAD);
        let at_object = |tip: &Point3<f64>| {
            let lateral = hand.lateral(tip);
            let knuckle = lateral.signum() * hand.knuckle_offset;
            knuckle + (lateral - knuckle) * along
        };
        let (left, right) = pinch(
            at_object(&hand.tips[0]),
            at_object(&hand.tips[1]),
            0.0,
            OBJECT_RADIUS + TIP_RADIUS,
            FINGER_STIFFNESS,
            1.0,
        );
        let weight = Vector3::z() * -OBJECT_WEIGHT;
        if left > 0.0 && right > 0.0 {
            return [hand.left * left + weight / 2.0, -hand.left * right + weight / 2.0];
        }
        if self.sticky {
            // Stuck to the left finger's pad, hanging from it.
            return [weight, Vector3::zeros()];
        }
        self.in_hand = false;
        self.in_trash = self.above_opening(&(hand.palm + hand.forward * OBJECT_AHEAD));
        [Vector3::zeros(); 2]
    }

    /// Whether an object released at `p` falls into the can.
    fn above_opening(&self, p: &Point3<f64>) -> bool {
        let (pose, half) = self.can;
        let local = pose.inverse() * p;
        local.x.abs() < half.x - OBJECT_RADIUS
            && local.y.abs() < half.y - OBJECT_RADIUS
            && local.z > half.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::DeviceKind;
    use crate::sim::mechanics::contact::hand_facing;

    #[test]
    fn an_object_released_over_the_opening_lands_in_the_can_and_elsewhere_on_the_floor() {
        let room = Room::paper();
        let can = room.device(DeviceKind::TrashCan);
        let middle = can.tag_center - can.tag_normal * 0.127;
        for (offset, lands_in) in [(0.0, true), (0.3, false)] {
            let mut object = HeldObject::new(&room, true, false);
            let palm =
                Point3::new(middle.x, middle.y, 0.55) + can.tag_normal * (OBJECT_AHEAD + offset);
            let hand = |half_span| hand_facing(can.tag_normal, palm, 0.1, half_span);
            let held = object.settle(&hand(0.025));
            assert!(held.iter().all(|f| f.norm() > 1.0) && object.in_hand);
            assert!(object.settle(&hand(0.08)).iter().all(|f| f.norm() == 0.0));
            assert!(!object.in_hand);
            assert_eq!(object.in_trash, lands_in, "released {offset} m out from the middle");
        }
    }
}
