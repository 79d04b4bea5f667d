//! The robot classes the simulator builds. They differ where two makers' robots differ and where
//! the tag entries' per-class overrides have to make up for it: the gripper (how far apart the
//! fingers' bases sit, how wide it opens) and the camera's colour response (the same red tag
//! comes out orange in one and red in the other). Both run the same perception and behaviours;
//! what they do differently comes from the registry's entries, never from code that asks which
//! robot it is.

use super::body::BodyGeometry;
use super::camera::{Exposure, TRUE_COLOUR};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimBody {
    /// EL-E-like, the paper's robot (class `el-e`): the simulator's default body.
    ElE,
    /// Stretch-like (class `stretch`): knuckles closer together, a gripper that opens only to
    /// 55°, and a camera whose red channel leaks into green.
    Stretch,
}

/// How the Stretch-like camera's channels mix the scene's linear colours: reds come out about
/// 27° toward orange, and less saturated, than in the EL-E-like camera. With about half the
/// gain and half the flash, a tag at arm's length does not clip its red channel (clipped, the
/// tag's orange would drift further, toward the wood's hue).
const STRETCH_COLOUR: [[f32; 3]; 3] = {
    const GAIN: f32 = 0.5;
    [
        [0.76 * GAIN, 0.19 * GAIN, 0.05 * GAIN],
        [0.27 * GAIN, 0.70 * GAIN, 0.03 * GAIN],
        [0.03 * GAIN, 0.09 * GAIN, 0.88 * GAIN],
    ]
};
const STRETCH_FLASH: f32 = 0.6;

impl SimBody {
    pub const ALL: [Self; 2] = [Self::ElE, Self::Stretch];

    /// The body for a robot class as the registry names it.
    pub fn for_class(class: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|body| body.class() == class)
    }

    /// The registry's name for the class.
    pub fn class(self) -> &'static str {
        match self {
            Self::ElE => "el-e",
            Self::Stretch => "stretch",
        }
    }

    pub fn geometry(self) -> BodyGeometry {
        match self {
            Self::ElE => BodyGeometry::default(),
            Self::Stretch => BodyGeometry {
                knuckle_offset: 0.012,
                gripper_travel: (0.0, 55f64.to_radians()),
                ..BodyGeometry::default()
            },
        }
    }

    pub fn exposure(self) -> Exposure {
        match self {
            Self::ElE => Exposure { colour_response: TRUE_COLOUR, ..Exposure::default() },
            Self::Stretch => Exposure {
                colour_response: STRETCH_COLOUR,
                flash_power: STRETCH_FLASH,
                ..Exposure::default()
            },
        }
    }
}
