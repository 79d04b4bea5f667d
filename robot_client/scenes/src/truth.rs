//! Ground truth of a scene, and whether an approach plan got it right: the tag centroid within
//! 4 cm of the tag's centre, the backing plane's normal within 15° of the true surface's, and
//! the waypoint within 10 cm of the one 50 cm out along it (issue 11's bar).

use nalgebra::{Point3, Vector3};
use pps_robot::navigation::ApproachPlan;
use pps_schema::TagSize;
use serde::{Deserialize, Serialize};

use crate::devices::DeviceKind;

/// Largest tag centroid error that is right, metres.
pub const TAG_TOLERANCE_M: f64 = 0.04;
/// Largest angle between the found and the true backing normal that is right, degrees.
pub const NORMAL_TOLERANCE_DEG: f64 = 15.0;
/// Largest waypoint error that is right, metres.
pub const WAYPOINT_TOLERANCE_M: f64 = 0.10;
/// The waypoint's distance from the tag, metres (the paper's 50 cm).
pub const STANDOFF_M: f64 = 0.5;

/// What a scene really holds, base frame, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    pub kind: DeviceKind,
    /// Centre of the tag's visible front (a foam tube's axis middle).
    pub tag_center: [f64; 3],
    /// Unit normal of the surface the tag rests on, toward the room.
    pub backing_normal: [f64; 3],
    /// The point of the backing surface behind the tag's centre.
    pub backing_foot: [f64; 3],
    /// The tag centre plus `STANDOFF_M` along the horizontal normal.
    pub expected_waypoint: [f64; 3],
    /// The tag's size as a caretaker registers it (`tag_size`: its two largest sides), metres;
    /// zero when not known.
    #[serde(default)]
    pub tag_size_m: [f64; 2],
}

impl Truth {
    pub fn new(
        kind: DeviceKind,
        tag_center: Point3<f64>,
        backing_normal: Vector3<f64>,
        backing_foot: Point3<f64>,
    ) -> Self {
        let n = backing_normal.normalize();
        let out = Vector3::new(n.x, n.y, 0.0).normalize();
        Self {
            kind,
            tag_center: tag_center.coords.into(),
            backing_normal: n.into(),
            backing_foot: backing_foot.coords.into(),
            expected_waypoint: (tag_center + out * STANDOFF_M).coords.into(),
            tag_size_m: [0.0; 2],
        }
    }

    /// The same truth with the tag's registered size, `size` (metres, the larger side first).
    pub fn with_tag_size(self, size: [f64; 2]) -> Self {
        Self { tag_size_m: size, ..self }
    }

    /// The tag's size as a caretaker registers it.
    pub fn registered_size(&self) -> TagSize {
        TagSize { width: self.tag_size_m[0], height: self.tag_size_m[1] }
    }
}

/// How a plan compares with the truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// Tag centroid to the tag's centre, metres; `None` when no tag was found.
    pub tag_error_m: Option<f64>,
    /// Backing-plane normal to the true one, degrees; `None` when no plane was chosen.
    pub normal_error_deg: Option<f64>,
    /// Waypoint to the expected one, metres.
    pub waypoint_error_m: Option<f64>,
    /// What was wrong, in words; empty when the plan is right.
    pub problems: Vec<String>,
}

impl Verdict {
    pub fn is_right(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Compares `plan` with `truth`.
pub fn judge(truth: &Truth, plan: &ApproachPlan) -> Verdict {
    let mut problems = Vec::new();
    let tag_error_m =
        plan.tag.as_ref().map(|t| (t.nearest().centroid - Point3::from(truth.tag_center)).norm());
    match tag_error_m {
        None => problems.push("no tag".to_string()),
        Some(e) if e > TAG_TOLERANCE_M => problems.push(format!("tag {:.1} cm off", e * 100.0)),
        Some(_) => {}
    }
    if plan.tag.as_ref().is_some_and(|t| t.is_ambiguous()) {
        // Not wrong by itself (the nearest is still reported), but worth seeing beside a miss.
        if tag_error_m.is_some_and(|e| e > TAG_TOLERANCE_M) {
            problems.push("tag ambiguous".to_string());
        }
    }
    let normal_error_deg = plan.backing_plane.as_ref().map(|p| {
        p.normal
            .normalize()
            .dot(&Vector3::from(truth.backing_normal))
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees()
    });
    match normal_error_deg {
        None if tag_error_m.is_some() => problems.push("no backing plane".to_string()),
        None => {}
        Some(e) if e > NORMAL_TOLERANCE_DEG => problems.push(format!("normal {e:.0}° off")),
        Some(_) => {}
    }
    let waypoint_error_m =
        plan.waypoint.as_ref().map(|w| (w.position - Point3::from(truth.expected_waypoint)).norm());
    if let Some(e) = waypoint_error_m
        && e > WAYPOINT_TOLERANCE_M
    {
        problems.push(format!("waypoint {:.1} cm off", e * 100.0));
    }
    Verdict { tag_error_m, normal_error_deg, waypoint_error_m, problems }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pps_robot::navigation::{ApproachWaypoint, BackingPlane};
    use pps_robot::perception::{TagDetection, TagSighting};
    use pps_robot::timings::StepTimings;

    fn plan(centroid: [f64; 3], normal: Option<[f64; 3]>) -> ApproachPlan {
        let centroid = Point3::from(centroid);
        let backing_plane = normal.map(|n| BackingPlane {
            normal: Vector3::from(n).normalize(),
            offset: 0.0,
            points: 1000,
        });
        let waypoint = backing_plane.as_ref().map(|p| {
            let out = Vector3::new(p.normal.x, p.normal.y, 0.0).normalize();
            ApproachWaypoint { position: centroid + out * 0.5, yaw: 0.0 }
        });
        ApproachPlan {
            tag: Some(TagSighting::Found(TagDetection {
                centroid,
                points: 100,
                voxels: 20,
                distance_to_target: 0.0,
                radius: 0.1,
                members: Vec::new(),
            })),
            tag_notes: Vec::new(),
            surface_points: Vec::new(),
            voi_points: 0,
            planes: Vec::new(),
            backing_index: None,
            backing_plane,
            rejected_planes: Vec::new(),
            waypoint,
            clearance: None,
            timings: StepTimings::default(),
        }
    }

    #[test]
    fn a_plan_is_right_only_within_every_tolerance() {
        let truth = Truth::new(
            DeviceKind::Drawer,
            Point3::new(1.0, 0.0, 0.5),
            -Vector3::x(),
            Point3::new(1.01, 0.0, 0.5),
        );
        assert_eq!(truth.expected_waypoint, [0.5, 0.0, 0.5]);
        assert!(judge(&truth, &plan([1.02, 0.01, 0.5], Some([-1.0, 0.0, 0.0]))).is_right());
        let off = judge(&truth, &plan([1.0, 0.05, 0.5], Some([-1.0, 0.0, 0.0])));
        assert_eq!(off.problems, vec!["tag 5.0 cm off".to_string()], "the waypoint moves 5 cm too");
        // 20° off: the normal fails and so does the waypoint (0.5 · 2 sin 10° = 17 cm).
        let (s, c) = 20f64.to_radians().sin_cos();
        let turned = judge(&truth, &plan([1.0, 0.0, 0.5], Some([-c, s, 0.0])));
        assert_eq!(turned.problems.len(), 2, "{:?}", turned.problems);
        assert!(turned.problems[0].starts_with("normal 20°"));
        let none = judge(&truth, &plan([1.0, 0.0, 0.5], None));
        assert_eq!(none.problems, vec!["no backing plane".to_string()]);
    }
}
