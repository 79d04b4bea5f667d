//! The devices' mechanics: how the switches, the lamp's pull chain, the drawer, the held object and
//! the trash can respond to the fingers, and the contact forces the fingers feel back.
//!
//! Everything is quasi-static: after each small step of the hand, every device settles to where
//! the force of the fingers balances its springs, friction and stops, and the fingers feel that
//! balance through their contact spring. Device state (a lever's side, the drawer's opening)
//! changes only through these contacts; nothing here reads the robot's sensors or decides
//! anything for it.

mod contact;
mod drawer;
mod flip_switch;
mod held_object;
mod pull_chain;
mod rocker_switch;

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};

pub use contact::{FINGER_STIFFNESS, FingerForces, Hand};
pub use held_object::{HeldObject, OBJECT_RANGE};

use super::camera::Lighting;
use super::room::Room;
use super::scenario::{DeviceTruth, Scenario};
use drawer::Drawer;
use flip_switch::FlipSwitch;
use pull_chain::PullChain;
use rocker_switch::RockerSwitch;

/// Parts of the room whose contacts with the fingers the mechanics compute; the rigid-room contact
/// model skips them.
pub const MOVING_PARTS: [&str; 8] = [
    "switch foam tube",
    "rocker paddle",
    "rocker dycem",
    "lamp chain",
    "lamp chain foam",
    "top drawer",
    "drawer handle",
    "drawer towel",
];

/// Every device in the room that the hand can change.
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceMechanics {
    /// The two switches are wired as a two-way pair: flipping either toggles the ceiling light.
    ceiling_light_on: bool,
    lamp_unplugged: bool,
    flip_switch: FlipSwitch,
    rocker_switch: RockerSwitch,
    pull_chain: PullChain,
    drawer: Drawer,
    held_object: HeldObject,
    /// The drawer's parts as the room built them (closed), by index in the scene.
    drawer_parts: Vec<(usize, Isometry3<f64>)>,
    flip_tube: usize,
    /// The drawer's tag as the room built it (closed).
    drawer_tag: Point3<f64>,
}

impl DeviceMechanics {
    /// The devices as `scenario` starts them; the switches stand as the light's state implies.
    pub fn new(room: &Room, scenario: &Scenario) -> Self {
        Self {
            ceiling_light_on: scenario.ceiling_light_on,
            lamp_unplugged: scenario.lamp_unplugged,
            flip_switch: FlipSwitch::new(room, scenario.ceiling_light_on),
            rocker_switch: RockerSwitch::new(room, scenario.ceiling_light_on),
            pull_chain: PullChain::new(room, scenario.lamp_on),
            drawer: Drawer::new(room, scenario.drawer_open, scenario.drawer_stuck),
            held_object: HeldObject::new(room, scenario.object_in_hand, scenario.sticky_object),
            drawer_parts: room
                .scene
                .parts()
                .iter()
                .enumerate()
                .filter(|(_, p)| drawer::MOVING_PARTS.contains(&p.name))
                .map(|(i, p)| (i, p.pose.cast()))
                .collect(),
            flip_tube: room
                .scene
                .parts()
                .iter()
                .position(|p| p.name == "switch foam tube")
                .expect("the room has a flip switch"),
            drawer_tag: room.device(super::room::DeviceKind::Drawer).tag_center,
        }
    }

    /// Settles every device against the hand where it is now; returns the forces the devices
    /// put on the fingers.
    pub fn settle(&mut self, hand: &Hand) -> FingerForces {
        let (flip, flipped) = self.flip_switch.settle(hand);
        let (rocker, rocked) = self.rocker_switch.settle(hand);
        if flipped != rocked {
            self.ceiling_light_on = !self.ceiling_light_on;
        }
        let (chain, _) = self.pull_chain.settle(hand);
        let drawer = self.drawer.settle(hand);
        let object = self.held_object.settle(hand);
        let mut forces = [Vector3::zeros(); 2];
        for contribution in [flip, rocker, chain, drawer, object] {
            forces[0] += contribution[0];
            forces[1] += contribution[1];
        }
        forces
    }

    /// Which lights are on, for the cameras.
    pub fn lighting(&self) -> Lighting {
        Lighting { ceiling_on: self.ceiling_light_on, lamp_on: self.lamp_lit() }
    }

    fn lamp_lit(&self) -> bool {
        self.pull_chain.switched_on && !self.lamp_unplugged
    }

    /// Whether the hand holds an object the palm's IR sensor sees.
    pub fn object_in_hand(&self) -> bool {
        self.held_object.in_hand
    }

    /// Where the parts that move are now, by index in the room's scene, so the camera and the
    /// laser see the drawer open and the lever flipped.
    pub fn part_poses(&self) -> Vec<(usize, Isometry3<f32>)> {
        let displaced = self.drawer.displacement();
        let mut moved: Vec<_> =
            self.drawer_parts.iter().map(|(i, built)| (*i, (displaced * built).cast())).collect();
        let (centre, axis) = self.flip_switch.tube();
        // Cylinders run along their local y axis, as the room builds them.
        let rotation = UnitQuaternion::rotation_between(&Vector3::y(), &axis).unwrap_or_default();
        moved.push((self.flip_tube, Isometry3::from_parts(centre.coords.into(), rotation).cast()));
        moved
    }

    /// Where the drawer's tag is, moved with the drawer.
    pub fn drawer_tag(&self) -> Point3<f64> {
        self.drawer.displacement() * self.drawer_tag
    }

    pub fn truth(&self) -> DeviceTruth {
        DeviceTruth {
            ceiling_light_on: self.ceiling_light_on,
            lamp_on: self.lamp_lit(),
            drawer_open: self.drawer.opening(),
            object_in_hand: self.held_object.in_hand,
            object_in_trash: self.held_object.in_trash,
            flip_switch_up: self.flip_switch.is_up(),
            rocker_top_pressed: self.rocker_switch.is_top_pressed(),
        }
    }
}
