//! The hand as the devices feel it, and the two contact laws every device shares: a fingertip
//! pressing on a surface, and two fingers pinching something between them.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::sim::scene::{Part, Scene};

/// Stiffness of a fingertip against something rigid (finger pads and the force-torque sensors'
/// compliance), newtons per metre: 2 N is a millimetre of squeeze.
pub const FINGER_STIFFNESS: f64 = 2000.0;
/// Radius of a fingertip's rounded end, metres.
pub const TIP_RADIUS: f64 = 0.005;
/// Half the width of a fingertip's pad across the gripper, metres: a thin lever between the
/// nearly closed fingers still meets a pad.
pub const PAD_HALF_WIDTH: f64 = 0.012;

/// The hand in the world frame, at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hand {
    pub palm: Point3<f64>,
    /// Left and right fingertips.
    pub tips: [Point3<f64>; 2],
    /// The base's x axis (along the fingers) and y axis (across, toward the left finger).
    pub forward: Vector3<f64>,
    pub left: Vector3<f64>,
    /// How far each finger's base sits from the palm's centre line.
    pub knuckle_offset: f64,
}

impl Hand {
    /// How far `p` is ahead of the palm along the fingers.
    pub fn ahead(&self, p: &Point3<f64>) -> f64 {
        (p - self.palm).dot(&self.forward)
    }

    /// How far `p` is left of the palm's centre line.
    pub fn lateral(&self, p: &Point3<f64>) -> f64 {
        (p - self.palm).dot(&self.left)
    }

    /// The point midway between the fingertips, where a pinched thing sits.
    pub fn pinch_point(&self) -> Point3<f64> {
        nalgebra::center(&self.tips[0], &self.tips[1])
    }
}

/// Forces on the left and right fingers, newtons, world frame.
pub type FingerForces = [Vector3<f64>; 2];

/// A frame on a device: `along` the wall, `out` of it into the room, and up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceFrame {
    pub origin: Point3<f64>,
    pub out: Vector3<f64>,
}

impl DeviceFrame {
    pub fn along(&self) -> Vector3<f64> {
        Vector3::z().cross(&self.out)
    }

    /// `p` as (along, out, up) from the frame's origin.
    pub fn local(&self, p: &Point3<f64>) -> Vector3<f64> {
        let d = p - self.origin;
        Vector3::new(d.dot(&self.along()), d.dot(&self.out), d.z)
    }

    /// The world vector of (along, out, up) components.
    pub fn world(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.along() * v.x + self.out * v.y + Vector3::z() * v.z
    }
}

/// The named part of the room, which the room always has.
pub fn part<'a>(scene: &'a Scene, name: &str) -> &'a Part {
    scene.parts().iter().find(|p| p.name == name).unwrap_or_else(|| panic!("the room has {name}"))
}

/// Centre, unit axis, half-height and radius of a cylindrical part.
pub fn cylinder(part: &Part) -> (Point3<f64>, Vector3<f64>, f64, f64) {
    let c = part.shape.as_cylinder().expect("a cylinder");
    let pose: Isometry3<f64> = part.pose.cast();
    let axis = pose.rotation * Vector3::y();
    (pose.translation.vector.into(), axis, f64::from(c.half_height), f64::from(c.radius))
}

/// Pose and half extents (out, along, up, in the room's wall frames) of a box part.
pub fn cuboid(part: &Part) -> (Isometry3<f64>, Vector3<f64>) {
    let c = part.shape.as_cuboid().expect("a box");
    (part.pose.cast(), c.half_extents.cast())
}

/// Two fingers squeezing a soft thing of half-width `half_width` (the fingertips' radius
/// included) whose centre rests `rest` metres left of the palm, held there by a sideways spring
/// `lateral_stiffness`; the fingertips are `left` and `right` metres left of the palm
/// (`right < left`). Returns the squeeze on the left and right fingers, newtons: unequal when the
/// thing is off-centre, which is what a centring grasp reads.
pub fn pinch(
    left: f64,
    right: f64,
    rest: f64,
    half_width: f64,
    stiffness: f64,
    lateral_stiffness: f64,
) -> (f64, f64) {
    let squeeze = |y: f64| {
        (
            stiffness * (y + half_width - left).max(0.0),
            stiffness * (right - (y - half_width)).max(0.0),
        )
    };
    // The thing sits where the fingers' pushes and its spring balance; the balance falls
    // monotonically with its position, so bisection finds it.
    let balance = |y: f64| {
        let (l, r) = squeeze(y);
        r - l - lateral_stiffness * (y - rest)
    };
    let (mut low, mut high) = (rest - 0.3, rest + 0.3);
    for _ in 0..50 {
        let mid = 0.5 * (low + high);
        if balance(mid) > 0.0 { low = mid } else { high = mid }
    }
    squeeze(0.5 * (low + high))
}

/// The largest `x` in `[low, high]` where the decreasing function `f` is still positive, to a
/// tenth of a millimetre or better; `low` when `f(low) <= 0`.
pub fn last_positive(low: f64, high: f64, f: impl Fn(f64) -> f64) -> f64 {
    if f(low) <= 0.0 {
        return low;
    }
    if f(high) > 0.0 {
        return high;
    }
    let (mut lo, mut hi) = (low, high);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    lo
}

/// A hand facing into a wall whose normal is `out`, its palm at `palm`, the fingertips `ahead`
/// metres ahead of the palm and `half_span` metres either side of its centre line.
#[cfg(test)]
pub fn hand_facing(out: Vector3<f64>, palm: Point3<f64>, ahead: f64, half_span: f64) -> Hand {
    let forward = -out;
    let left = Vector3::z().cross(&forward);
    Hand {
        palm,
        tips: [
            palm + forward * ahead + left * half_span,
            palm + forward * ahead - left * half_span,
        ],
        forward,
        left,
        knuckle_offset: 0.015,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_off_centre_pinch_loads_the_near_finger_more() {
        let (l, r) = pinch(0.02, -0.02, 0.0, 0.022, FINGER_STIFFNESS, 150.0);
        assert!((l - r).abs() < 1e-6 && l > 3.0, "centred: {l} {r}");
        let (l, r) = pinch(0.02, -0.02, 0.01, 0.022, 800.0, 150.0);
        assert!(l > r + 0.5, "left of centre: {l} {r}");
        let (l, r) = pinch(0.05, -0.05, 0.0, 0.022, FINGER_STIFFNESS, 150.0);
        assert_eq!((l, r), (0.0, 0.0));
    }

    #[test]
    fn bisection_finds_the_crossing() {
        let x = last_positive(0.0, 1.0, |x| 0.3 - x);
        assert!((x - 0.3).abs() < 1e-6);
        assert_eq!(last_positive(0.0, 1.0, |x| -x), 0.0);
        assert_eq!(last_positive(0.0, 1.0, |x| 2.0 - x), 1.0);
    }
}
