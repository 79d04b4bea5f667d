//! How a simulated trial starts: the devices' initial states and the failures injected into them
//! (the paper's second set of trials, §V: an unplugged lamp, a stuck drawer, a sticky object).

/// The initial state of the room's devices and the failures injected into them.
///
/// `Scenario::default()` has everything off and nothing broken: the ceiling light and the lamp
/// off, the drawer closed, the hand empty. [`Scenario::office`] is the same with the ceiling light
/// on, the lighting of the paper's trials, and what `SimRobot::new` starts with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Scenario {
    /// Pulling the chain clicks but the lamp stays dark.
    pub lamp_unplugged: bool,
    /// The drawer does not slide: pulling and pushing meet a rigid stop.
    pub drawer_stuck: bool,
    /// The held object stays stuck to the gripper when it opens.
    pub sticky_object: bool,
    /// The robot starts holding an object (for drop).
    pub object_in_hand: bool,
    /// Initial state of the ceiling light the two switches control.
    pub ceiling_light_on: bool,
    /// Initial state of the lamp.
    pub lamp_on: bool,
    /// Initial opening of the drawer, metres (0 is closed).
    pub drawer_open: f64,
    /// Once the robot first reads a tag, a person steps onto the way it came, this many metres
    /// back along it from where its base's centre stands, and stays there; the base's bumper
    /// stops it where its outline meets them. Neither camera nor laser is drawn seeing them:
    /// they step in behind the robot, where neither looks.
    pub person_behind: Option<f64>,
}

impl Scenario {
    /// The paper's office: ceiling light on, nothing broken.
    pub fn office() -> Self {
        Self { ceiling_light_on: true, ..Self::default() }
    }
}

/// What the devices truly are, for tests and the experiment's bookkeeping only: behaviours see the
/// world through the hardware traits and never through this.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceTruth {
    pub ceiling_light_on: bool,
    pub lamp_on: bool,
    /// How far the drawer is open, metres.
    pub drawer_open: f64,
    pub object_in_hand: bool,
    pub object_in_trash: bool,
    /// The flip switch's lever points up.
    pub flip_switch_up: bool,
    /// The rocker switch's top half is pressed in.
    pub rocker_top_pressed: bool,
}
