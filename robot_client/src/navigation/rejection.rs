//! Why a plane was not taken: by the plane search (it is not a surface) or by the backing-plane
//! rule (a surface, but not the one carrying the tag). `perceive` prints these, so a developer
//! with a scan of their own sees which rule dropped which plane instead of guessing.

use std::fmt;

use nalgebra::Vector3;

/// The rule a plane failed, with the figures it was judged by (metres and radians inside,
/// centimetres, millimetres and degrees in the sentence).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlaneRejection {
    // Not a surface (the plane search).
    /// Its largest connected patch holds too few points.
    TooFewPoints { points: usize, min: usize },
    /// Widening its band from ±t to ±2t adds too much: a slab through clutter or noise.
    Thick { ratio: f64, max: f64 },
    /// Narrower across than a surface: a band across one.
    Narrow { width: f64, min: f64 },
    /// Its cells' mean depths wander beyond the noise: a curved surface it is tangent to.
    Wavy { waviness: f64, max: f64 },
    /// Fills too little of the rectangle it spans: thin things that happen to line up.
    Unfilled { fill: f64, min: f64 },
    // A surface, but not the backing plane.
    /// Too far from vertical for a wall or a front.
    Tilted { tilt: f64, max: f64 },
    /// Smaller than a wall or a front across its narrowest direction.
    Small { width: f64, min: f64 },
    /// Seen edge-on from the robot.
    EdgeOn { angle: f64, max: f64 },
    /// The tag lies behind it: a side face, or something in front of the tag.
    TagBehind { depth: f64, tolerance: f64 },
    /// The tag hangs too far in front of it.
    TagTooFarOut { height: f64, max: f64 },
    /// None of its points lie near the tag's foot on it.
    AwayFromTag { gap: f64, max: f64 },
    /// It would do, but the tag sits nearer and flatter on another: its height above the plane
    /// plus its thickness across it, against the chosen plane's.
    FartherThanChosen { fit: f64, chosen: f64 },
    /// The tag hangs free, this far before a surface behind it seen all around its shadow: a
    /// plane carrying the tag would hide that surface, so this one only lines up with it.
    TagHangsFree { before: f64 },
}

impl PlaneRejection {
    /// Whether the plane search rejected it (as opposed to the backing-plane rule).
    pub fn is_not_a_surface(&self) -> bool {
        matches!(
            self,
            Self::TooFewPoints { .. }
                | Self::Thick { .. }
                | Self::Narrow { .. }
                | Self::Wavy { .. }
                | Self::Unfilled { .. }
        )
    }
}

impl fmt::Display for PlaneRejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cm = |m: f64| m * 100.0;
        let deg = |r: f64| r.to_degrees();
        match *self {
            Self::TooFewPoints { points, min } => write!(
                f,
                "not a surface: its largest connected patch holds {points} points, fewer than {min}"
            ),
            Self::Thick { ratio, max } => write!(
                f,
                "not a surface but a slab through clutter: doubling its band takes in {ratio:.2}× \
                 the points (a surface {max:.2}× at most)"
            ),
            Self::Narrow { width, min } => write!(
                f,
                "not a surface but a strip across one: {:.1} cm wide, under {:.1} cm",
                cm(width),
                cm(min)
            ),
            Self::Wavy { waviness, max } => write!(
                f,
                "not a plane but curved: its depth wanders {:.1} mm beyond the laser's noise \
                 (a plane {:.1} mm at most)",
                waviness * 1e3,
                max * 1e3
            ),
            Self::Unfilled { fill, min } => write!(
                f,
                "not a surface: its points fill {:.0} % of the rectangle they span (a surface \
                 {:.0} % at least)",
                fill * 100.0,
                min * 100.0
            ),
            Self::Tilted { tilt, max } => write!(
                f,
                "tilted {:.0}° from vertical, more than the {:.0}° of a wall or a front",
                deg(tilt),
                deg(max)
            ),
            Self::Small { width, min } => write!(
                f,
                "{:.1} cm across, smaller than the {:.1} cm of a wall or a front",
                cm(width),
                cm(min)
            ),
            Self::EdgeOn { angle, max } => write!(
                f,
                "seen edge-on: it faces {:.0}° away from the robot (at most {:.0}°)",
                deg(angle),
                deg(max)
            ),
            Self::TagBehind { depth, tolerance } => write!(
                f,
                "the tag lies {:.1} cm behind it (at most {:.1} cm): a side face or something \
                 in front of the tag",
                cm(depth),
                cm(tolerance)
            ),
            Self::TagTooFarOut { height, max } => write!(
                f,
                "the tag is {:.1} cm in front of it, more than {:.1} cm",
                cm(height),
                cm(max)
            ),
            Self::AwayFromTag { gap, max } => write!(
                f,
                "not the surface the tag is on: its nearest point is {:.1} cm from the tag's \
                 foot on it (at most {:.1} cm)",
                cm(gap),
                cm(max)
            ),
            Self::FartherThanChosen { fit, chosen } => write!(
                f,
                "could carry the tag, but the tag sits {:.1} cm off it (height plus thickness \
                 across it), {:.1} cm off the chosen plane",
                cm(fit),
                cm(chosen)
            ),
            Self::TagHangsFree { before } => write!(
                f,
                "only lines up with the tag: the tag hangs free {:.1} cm before a plane behind \
                 it, which shows all around the tag's shadow (a plane carrying the tag would \
                 hide it there)",
                cm(before)
            ),
        }
    }
}

/// A plane that was not taken, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct RejectedPlane {
    /// Unit normal toward the robot, and `normal · p + offset = 0` on the plane (metres).
    pub normal: Vector3<f64>,
    pub offset: f64,
    /// Points within its band when it was judged.
    pub points: usize,
    pub why: PlaneRejection,
}
