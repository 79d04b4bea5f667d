//! The floor lamp's pull chain: the foam on its end can be pinched, and pulling it down takes up a
//! centimetre of slack, then meets a spring until the switch clicks, then a hard stop. Each click
//! toggles the lamp's switch; an unplugged lamp clicks and stays dark.

use nalgebra::{Point3, Vector3};

use super::contact::{
    FINGER_STIFFNESS, FingerForces, Hand, TIP_RADIUS, cylinder, last_positive, part, pinch,
};
use crate::sim::room::Room;

/// Pull taken up by the chain's slack, metres, and the chain's weight felt meanwhile, newtons.
const SLACK: f64 = 0.01;
const CHAIN_WEIGHT: f64 = 0.3;
/// Pull at which the switch clicks, and the force it takes to get there, metres and newtons.
pub const CLICK_PULL: f64 = 0.025;
pub const CLICK_FORCE: f64 = 5.0;
/// Pull at which the chain comes up against the switch's end stop, metres.
const END_STOP: f64 = 0.035;
/// Spring of the switch after the click, newtons per metre.
const RETURN_STIFFNESS: f64 = 100.0;
/// Sideways spring of the hanging chain, newtons per metre: it swings out of the way easily.
const SWING_STIFFNESS: f64 = 30.0;
/// Friction between the fingertips and the foam: a pinch of total squeeze `s` holds up to
/// `GRIP_FRICTION * s`; pulled harder, the foam slides through it.
const GRIP_FRICTION: f64 = 2.0;

#[derive(Debug, Clone, PartialEq)]
pub struct PullChain {
    /// Centre of the foam on the chain's end while the chain hangs free, its half-height and
    /// radius.
    foam: Point3<f64>,
    half_height: f64,
    radius: f64,
    /// How far the chain is pulled down, metres.
    pull: f64,
    /// Whether this pull already clicked (reset when the chain returns).
    clicked: bool,
    /// Palm height at which the chain would be at zero pull, while it is pinched.
    grip_height: Option<f64>,
    /// The lamp's own switch.
    pub switched_on: bool,
}

/// Tension in the chain pulled down by `pull` metres, newtons.
fn tension(pull: f64, clicked: bool) -> f64 {
    if pull <= SLACK {
        CHAIN_WEIGHT * pull.max(0.0) / SLACK
    } else if clicked {
        CHAIN_WEIGHT + RETURN_STIFFNESS * (pull - SLACK)
    } else {
        CHAIN_WEIGHT + (CLICK_FORCE - CHAIN_WEIGHT) * (pull - SLACK) / (CLICK_PULL - SLACK)
    }
}

impl PullChain {
    pub fn new(room: &Room, switched_on: bool) -> Self {
        let (foam, _, half_height, radius) = cylinder(part(&room.scene, "lamp chain foam"));
        Self {
            foam,
            half_height,
            radius,
            pull: 0.0,
            clicked: false,
            grip_height: None,
            switched_on,
        }
    }

    /// Settles the chain against the hand; returns the fingers' forces and whether the switch
    /// clicked.
    pub fn settle(&mut self, hand: &Hand) -> (FingerForces, bool) {
        let foam = self.foam - Vector3::z() * self.pull;
        let (left, right) = self.squeeze(hand, &foam);
        let mut clicked_now = false;
        let mut chain_tension = 0.0;
        if left > 0.0 && right > 0.0 {
            // The most the pinch holds before the foam slides through it.
            let hold = GRIP_FRICTION * (left + right);
            let grip = *self.grip_height.get_or_insert(hand.palm.z + self.pull);
            let free_pull = grip - hand.palm.z;
            let through_pinch = move |p: f64| (FINGER_STIFFNESS * (free_pull - p)).min(hold);
            // The chain settles where the fingers' pull through the pinch balances its tension.
            let balance = |clicked: bool| move |p: f64| through_pinch(p) - tension(p, clicked);
            let mut pull = last_positive(0.0, CLICK_PULL, balance(self.clicked));
            if !self.clicked && pull >= CLICK_PULL {
                self.clicked = true;
                clicked_now = true;
                self.switched_on = !self.switched_on;
            }
            if self.clicked {
                pull = last_positive(0.0, END_STOP, balance(true));
            }
            chain_tension = if pull >= END_STOP {
                through_pinch(END_STOP)
            } else {
                tension(pull, self.clicked)
            };
            if FINGER_STIFFNESS * (free_pull - pull) > hold {
                // The foam slides down through the pinch: the fingers now hold it higher up,
                // until they slip off its lower end (`squeeze` then finds nothing between them).
                self.grip_height = Some(hand.palm.z + pull + hold / FINGER_STIFFNESS);
            }
            self.pull = pull;
        } else {
            self.release();
        }
        let up = Vector3::z() * (chain_tension / 2.0);
        ([hand.left * left + up, -hand.left * right + up], clicked_now)
    }

    fn squeeze(&self, hand: &Hand, foam: &Point3<f64>) -> (f64, f64) {
        let tip_ahead = hand.ahead(&hand.tips[0]);
        let ahead = hand.ahead(foam);
        let between = (0.0..=tip_ahead + TIP_RADIUS).contains(&ahead)
            && (foam.z - hand.palm.z).abs() <= self.half_height + TIP_RADIUS;
        if !between {
            return (0.0, 0.0);
        }
        pinch(
            hand.lateral(&hand.tips[0]),
            hand.lateral(&hand.tips[1]),
            hand.lateral(foam),
            self.radius + TIP_RADIUS,
            FINGER_STIFFNESS,
            SWING_STIFFNESS,
        )
    }

    fn release(&mut self) {
        self.grip_height = None;
        self.pull = 0.0;
        self.clicked = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mechanics::contact::hand_facing;

    #[test]
    fn a_pinched_chain_clicks_once_past_its_force_and_a_loose_one_never_does() {
        let room = Room::paper();
        let out = room.device(crate::sim::DeviceKind::Lamp).tag_normal;
        for (half_span, clicks) in [(0.015, 1), (0.04, 0)] {
            let mut chain = PullChain::new(&room, false);
            let (mut peak, mut before_click, mut count): (f64, f64, usize) = (0.0, 0.0, 0);
            // An 8 cm pull, well past the end stop.
            for step in 0..80 {
                let palm = chain.foam + out * 0.08 - Vector3::z() * (0.001 * f64::from(step));
                let (forces, clicked) = chain.settle(&hand_facing(out, palm, 0.1, half_span));
                let pulling = forces[0].z + forces[1].z;
                if clicked {
                    count += 1;
                    before_click = peak;
                }
                peak = peak.max(pulling);
            }
            assert_eq!(count, clicks, "half span {half_span}");
            assert_eq!(chain.switched_on, clicks == 1, "half span {half_span}");
            if clicks == 1 {
                assert!(
                    (CLICK_FORCE - before_click).abs() < 0.5,
                    "before the click {before_click:.2} N"
                );
                // Past the end stop the foam slides through the pinch instead of the pull
                // growing without bound, and at last slips off the fingers' lower edge.
                let (left, right) = chain.squeeze(
                    &hand_facing(out, chain.foam + out * 0.08, 0.1, half_span),
                    &chain.foam,
                );
                assert!(peak <= GRIP_FRICTION * (left + right) + 0.1, "peak pull {peak:.2} N");
                assert_eq!(chain.grip_height, None, "the foam slipped out of the pinch");
            }
        }
    }
}
