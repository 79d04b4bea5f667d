//! Navigation geometry (paper §IV-B.1): from a target point, an image and a cloud to where the
//! base should stand; and, once there, which RFID tag the fingers are reading.
//!
//! In the paper's order: [`VolumeOfInterest`] (a vertical cylinder around the target),
//! [`find_planes`] (every plane in it, dropping those under 100 points and slabs that are not
//! surfaces, each judged against the noise measured across it),
//! [`choose_backing_plane`] (the surface behind the tag; the paper's nearest-plane rule
//! is kept as [`nearest_plane_to_target`]), [`approach_waypoint`] (50 cm out along its normal,
//! facing the tag), [`check_clearance`] (the robot with its arm extended against the cloud);
//! [`plan_approach`] runs them all. [`identify_tag`] picks the strongest RFID read, and
//! [`find_container_opening`] where the drop behaviour lets go.
//!
//! Like perception, navigation geometry works on data and never on devices or the simulator.

mod approach;
mod backing_plane;
mod cells;
mod container;
mod depth_approach;
mod plane;
mod plane_evidence;
mod ransac;
mod refit;
mod rejection;
mod rfid_choice;
mod robust_width;
mod tag_centre;
mod voi;
mod waviness;
mod waypoint;

pub use approach::{ApproachParams, ApproachPlan, plan_approach};
pub use backing_plane::{
    BackingChoice, BackingPlane, BackingPlaneRule, choose_backing_plane, nearest_plane_to_target,
};
pub use container::{ContainerOpening, ContainerSearch, find_container_opening};
pub use depth_approach::{DepthApproachError, plan_approach_on_depth};
pub use plane::Plane;
pub use plane_evidence::{PlanarPatch, PlaneEvidenceRule, assess_plane};
pub use ransac::{DetectedPlane, PlaneSearch, PlaneSearchParams, find_planes};
pub use rejection::{PlaneRejection, RejectedPlane};
pub use rfid_choice::{RfidIdentity, TagSignal, identify_among, identify_tag, tag_signals};
pub use tag_centre::tag_centre_on;
pub use voi::VolumeOfInterest;
pub use waypoint::{
    ApproachWaypoint, Clearance, RobotFootprint, approach_waypoint, check_clearance,
};
