//! The static transform tree from `/tf_static`: which frame sits where in which, so the camera
//! can be placed in the base frame by the image header's `frame_id`.

use std::collections::HashMap;

use nalgebra::Isometry3;

use crate::msg::tf::TfMessage;

/// Longest chain of frames followed; a deeper one is taken for a cycle.
const MAX_DEPTH: usize = 64;

/// Every static transform heard, by child frame (a later one for the same child wins, as tf2
/// has it).
#[derive(Debug, Clone, Default)]
pub struct TransformTree {
    parent_of: HashMap<String, (String, Isometry3<f64>)>,
}

impl TransformTree {
    /// Takes in the transforms of one message; returns those it could not use, in words.
    pub fn insert(&mut self, message: &TfMessage) -> Vec<String> {
        let mut unusable = Vec::new();
        for t in &message.transforms {
            let parent = t.header.frame_id.trim_start_matches('/');
            let child = t.child_frame_id.trim_start_matches('/');
            match t.transform.to_isometry() {
                Some(iso) if !parent.is_empty() && !child.is_empty() && parent != child => {
                    self.parent_of.insert(child.to_owned(), (parent.to_owned(), iso));
                }
                _ => unusable.push(format!(
                    "the transform from `{parent}` to `{child}` is not a rigid transform between \
                     two named frames"
                )),
            }
        }
        unusable
    }

    /// `frame` and each frame above it, with the transform mapping `frame`'s points into it.
    fn ancestors(&self, frame: &str) -> Vec<(String, Isometry3<f64>)> {
        let mut chain = vec![(frame.to_owned(), Isometry3::identity())];
        while chain.len() <= MAX_DEPTH {
            let (current, up_from_frame) = chain.last().cloned().unwrap_or_default();
            let Some((parent, parent_from_current)) = self.parent_of.get(&current) else { break };
            chain.push((parent.clone(), parent_from_current * up_from_frame));
        }
        chain
    }

    /// The transform mapping points of `frame` into `target`, when the tree connects them.
    pub fn lookup(&self, target: &str, frame: &str) -> Option<Isometry3<f64>> {
        let (target, frame) = (target.trim_start_matches('/'), frame.trim_start_matches('/'));
        let from_frame = self.ancestors(frame);
        let from_target = self.ancestors(target);
        from_frame.iter().find_map(|(ancestor, ancestor_from_frame)| {
            let (_, ancestor_from_target) = from_target.iter().find(|(a, _)| a == ancestor)?;
            Some(ancestor_from_target.inverse() * ancestor_from_frame)
        })
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3};

    use super::*;
    use crate::msg::builtin::Header;
    use crate::msg::geometry::{Transform, TransformStamped};

    fn stamped(parent: &str, child: &str, iso: Isometry3<f64>) -> TransformStamped {
        TransformStamped {
            header: Header { frame_id: parent.into(), ..Header::default() },
            child_frame_id: child.into(),
            transform: Transform::from_isometry(&iso),
        }
    }

    fn iso(x: f64, y: f64, z: f64, yaw: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
        )
    }

    #[test]
    fn a_chain_is_composed_and_siblings_are_joined_through_their_parent() {
        let mut tree = TransformTree::default();
        let unusable = tree.insert(&TfMessage {
            transforms: vec![
                stamped("base_link", "head", iso(0.1, 0.0, 1.2, 0.5)),
                stamped("/head", "camera_optical", iso(0.05, 0.0, 0.0, -0.2)),
                stamped("base_link", "laser", iso(0.2, 0.0, 0.3, 0.0)),
            ],
        });
        assert!(unusable.is_empty());
        let p = Point3::new(1.0, 2.0, 3.0);
        let expected = iso(0.1, 0.0, 1.2, 0.5) * iso(0.05, 0.0, 0.0, -0.2) * p;
        let base_from_camera = tree.lookup("base_link", "camera_optical").unwrap();
        assert!((base_from_camera * p - expected).norm() < 1e-12);
        let laser_from_camera = tree.lookup("laser", "camera_optical").unwrap();
        let via_base = iso(0.2, 0.0, 0.3, 0.0).inverse() * expected;
        assert!((laser_from_camera * p - via_base).norm() < 1e-12);
        assert!(tree.lookup("base_link", "base_link").unwrap().translation.vector.norm() < 1e-12);
    }

    #[test]
    fn unconnected_frames_and_broken_transforms_are_reported() {
        let mut tree = TransformTree::default();
        let mut broken = stamped("base_link", "camera", iso(0.0, 0.0, 0.0, 0.0));
        broken.transform.rotation.w = 0.0;
        assert_eq!(tree.insert(&TfMessage { transforms: vec![broken] }).len(), 1);
        assert!(tree.lookup("base_link", "camera").is_none());
        tree.insert(&TfMessage { transforms: vec![stamped("a", "b", iso(1.0, 0.0, 0.0, 0.0))] });
        assert!(tree.lookup("base_link", "b").is_none());
    }
}
