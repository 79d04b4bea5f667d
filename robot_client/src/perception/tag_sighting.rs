//! What the tag search saw near the target: a red lump taken for a tag, and whether another
//! is about as near.

use nalgebra::Point3;

use super::occupancy::Component;

/// A red lump of laser points taken for a tag.
#[derive(Debug, Clone, PartialEq)]
pub struct TagDetection {
    /// Centroid of the tag's points, base frame, metres; once the approach has found the
    /// backing plane, the middle of the tag's outline on it ([`crate::navigation::tag_centre_on`]).
    pub centroid: Point3<f64>,
    /// Laser points and occupied voxels in the tag's component.
    pub points: usize,
    pub voxels: usize,
    /// From the target to the tag's nearest point, metres.
    pub distance_to_target: f64,
    /// How far the tag's points reach from its centroid (half its bounding box's diagonal), metres.
    pub radius: f64,
    /// The tag's laser points, base frame.
    pub members: Vec<Point3<f32>>,
}

impl From<&Component> for TagDetection {
    fn from(c: &Component) -> Self {
        Self {
            centroid: c.centroid,
            points: c.points,
            voxels: c.voxels,
            distance_to_target: c.distance_to_target,
            radius: c.radius,
            members: c.members.clone(),
        }
    }
}

/// What the search saw near the target.
#[derive(Debug, Clone, PartialEq)]
pub enum TagSighting {
    /// One tag is clearly the nearest.
    Found(TagDetection),
    /// Two tags are about equally near: the caller should re-aim, read RFID closer, or cross-check.
    Ambiguous { nearest: TagDetection, other: TagDetection },
}

impl TagSighting {
    /// The tag nearest the target, ambiguous or not.
    pub fn nearest(&self) -> &TagDetection {
        match self {
            Self::Found(tag) | Self::Ambiguous { nearest: tag, .. } => tag,
        }
    }

    pub fn is_ambiguous(&self) -> bool {
        matches!(self, Self::Ambiguous { .. })
    }

    pub fn nearest_mut(&mut self) -> &mut TagDetection {
        match self {
            Self::Found(tag) | Self::Ambiguous { nearest: tag, .. } => tag,
        }
    }
}
