//! Close-range alignment (paper §IV-B.2.a): "EL-E moves forward until it detects contact with
//! the force/torque sensors in the base of its fingers or near contact with the IR range sensor
//! in its palm. Upon detection, EL-E backs off a fixed distance (8 to 12 cm depending on the
//! behavior)" — the back-off is the behaviour's `alignment_backoff` from the entry.

use super::Evidence;
use super::force::ForceRecorder;
use super::motion::{Hand, Touch, advance_until_touch, move_arm_by};
use crate::hal::HalError;

/// How the alignment feels for the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignmentParams {
    /// Finger force that means contact, newtons (the behaviour's `contact_force` where it has
    /// one; the paper's 2 N otherwise).
    pub contact_force: f64,
    /// Palm range that means near contact, metres.
    pub near_range: f64,
    /// How far to back off after contact, metres (the entry's `alignment_backoff`).
    pub backoff: f64,
    /// How far forward to feel before giving up, metres: the hand starts about 10 cm away.
    pub max_reach: f64,
}

impl AlignmentParams {
    /// Palm range that means near contact: the paper's 2 cm.
    pub const NEAR_RANGE: f64 = 0.02;
    /// How far forward every behaviour feels before giving up: the hand starts about 10 cm
    /// from the tag, so 25 cm finds a surface a hand's width behind where it was seen.
    pub const MAX_REACH: f64 = 0.25;

    /// The paper's 2 N contact, near contact at 2 cm, and the entry's back-off.
    pub fn with_backoff(backoff: f64) -> Self {
        Self {
            contact_force: 2.0,
            near_range: Self::NEAR_RANGE,
            backoff,
            max_reach: Self::MAX_REACH,
        }
    }
}

/// What the hand touched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Contact {
    Force,
    NearRange,
}

/// Where the alignment left the hand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// `None` when nothing was within reach: the tag is not where it was thought to be.
    pub contact: Option<Contact>,
    /// How far the arm moved forward before the contact, metres.
    pub travel: f64,
    /// How far from the surface the hand was left, metres.
    pub backoff: f64,
}

impl Alignment {
    /// A short account for the task's report.
    pub fn describe(&self) -> String {
        let backoff = self.backoff;
        match self.contact {
            Some(Contact::Force) => {
                format!("touched after {:.3} m, backed off {backoff} m", self.travel)
            }
            Some(Contact::NearRange) => {
                format!("palm saw the surface after {:.3} m, backed off {backoff} m", self.travel)
            }
            None => format!("nothing within {:.2} m", self.travel),
        }
    }
}

/// Moves forward until contact or near contact, then backs off until the palm is
/// `params.backoff` from the surface; the outcome is noted in the behaviour's evidence.
pub fn close_range_alignment(
    hand: &impl Hand,
    forces: &mut ForceRecorder<'_>,
    params: &AlignmentParams,
    evidence: &mut Evidence,
) -> Result<Alignment, HalError> {
    let (touch, travel) = advance_until_touch(
        hand,
        forces,
        params.contact_force,
        Some(params.near_range),
        params.max_reach,
    )?;
    // The back-off is measured from the surface: after a touch the palm is at it, after near
    // contact the palm range sensor says how far ahead it still is.
    let (contact, ahead) = match touch {
        Touch::Force(_) => (Some(Contact::Force), 0.0),
        Touch::NearRange(range) => (Some(Contact::NearRange), range),
        Touch::Nothing => (None, 0.0),
    };
    if contact.is_some() {
        move_arm_by(hand, ahead - params.backoff)?;
    } else {
        // Nothing there: put the hand back where it was.
        move_arm_by(hand, -travel)?;
    }
    forces.sample()?;
    let alignment = Alignment { contact, travel, backoff: params.backoff };
    evidence.step(format!("close-range alignment: {}", alignment.describe()));
    Ok(alignment)
}
