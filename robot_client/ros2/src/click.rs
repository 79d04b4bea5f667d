//! A click on `/clicked_point` answered with the paper's chain (§III-B, §IV-B.1) on the latest
//! image, camera info, static transforms and range data (a cloud or an aligned depth image,
//! whichever came last): the tag's pose, the goal 50 cm out facing it and the markers of Fig. 5.
//! Pure: messages in, messages out, no DDS.

use std::sync::Arc;

use nalgebra::{Point3, Rotation3, UnitQuaternion, Vector3};
use pps_robot::hal::{CameraCalibration, ColorImage, PointCloud};
use pps_robot::navigation::{
    ApproachParams, ApproachPlan, BackingPlane, plan_approach, plan_approach_on_depth,
};
use pps_robot::perception::{DepthNoise, DepthRange};

use crate::camera::calibration;
use crate::depth::{DepthFrame, depth_cloud};
use crate::image::color_image;
use crate::input_error::InputError;
use crate::markers::fig5_markers;
use crate::msg::builtin::{Header, Time};
use crate::msg::geometry::{PointStamped, Pose, PoseStamped};
use crate::msg::sensor::{CameraInfo, Image};
use crate::msg::visualization::MarkerArray;
use crate::transforms::TransformTree;

/// The latest of every input a click needs; cheap to clone, so a click works on a snapshot
/// while new data keeps arriving.
#[derive(Debug, Default, Clone)]
pub struct SensorState {
    pub image: Option<Arc<Image>>,
    pub camera_info: Option<Arc<CameraInfo>>,
    /// The latest cloud or depth image, whichever is fresher, already read.
    pub range: Option<RangeInput>,
    /// The depth camera's info (its intrinsics equal the colour camera's when aligned).
    pub depth_info: Option<Arc<CameraInfo>>,
    pub transforms: TransformTree,
}

/// What the robot measured the scene's geometry with.
#[derive(Debug, Clone)]
pub enum RangeInput {
    /// A cloud in the base frame (the frame it came in is checked when it arrives).
    Cloud(Arc<PointCloud>),
    /// A depth image; it becomes a cloud only when a click needs one, not at 30 Hz.
    Depth(Arc<DepthFrame>),
}

/// What a click produced.
#[derive(Debug, Clone)]
pub struct ClickAnswer {
    pub plan: ApproachPlan,
    /// The image the plan was made on, and its camera: with the plan, what the trial's picture
    /// shows.
    pub image: ColorImage,
    pub calibration: CameraCalibration,
    /// `None` when no tag was found near the click.
    pub tag_pose: Option<PoseStamped>,
    /// `None` when there is no backing plane to approach along.
    pub goal_pose: Option<PoseStamped>,
    pub markers: MarkerArray,
}

/// Runs the chain for `click`, or says which input is missing or wrong. The chain's tolerances
/// follow the range sensor's noise: `stated_noise` when given, otherwise what the range data
/// came as says (a depth image: a D435's; a cloud: a laser's), as `pps-robot perceive` decides.
pub fn answer_click(
    state: &SensorState,
    click: &PointStamped,
    base_frame: &str,
    params: &ApproachParams,
    stated_noise: Option<DepthNoise>,
) -> Result<ClickAnswer, InputError> {
    let frame = click.header.frame_id.trim_start_matches('/');
    if !frame.is_empty() && frame != base_frame {
        return Err(InputError::ClickFrame { got: frame.to_owned(), base: base_frame.to_owned() });
    }
    let target = Point3::from(click.point);
    if !target.coords.iter().all(|v| v.is_finite()) {
        return Err(InputError::ClickNotFinite);
    }
    let range = state.range.as_ref().ok_or(InputError::Missing("point cloud or depth image"))?;
    let image = state.image.as_ref().ok_or(InputError::Missing("camera image"))?;
    let info = state.camera_info.as_ref().ok_or(InputError::Missing("camera info"))?;
    let camera_frame = image.header.frame_id.trim_start_matches('/');
    let base_from_camera = state.transforms.lookup(base_frame, camera_frame).ok_or_else(|| {
        InputError::NoTransform { from: base_frame.to_owned(), to: camera_frame.to_owned() }
    })?;
    let colour = color_image(image)?;
    let calibration = calibration(info, base_from_camera, (colour.width, colour.height))?;
    let depth_image = matches!(range, RangeInput::Depth(_));
    let params = &ApproachParams {
        depth_noise: DepthNoise::stated_or_typical(stated_noise, depth_image),
        ..params.clone()
    };
    let plan = match range {
        RangeInput::Cloud(cloud) => plan_approach(&colour, cloud, &calibration, &target, params)
            .map_err(|e| InputError::Perception(e.to_string()))?,
        RangeInput::Depth(depth) => {
            let info = state.depth_info.as_ref().ok_or(InputError::Missing("depth camera info"))?;
            let base_from_depth =
                state.transforms.lookup(base_frame, &depth.frame_id).ok_or_else(|| {
                    InputError::NoTransform {
                        from: base_frame.to_owned(),
                        to: depth.frame_id.clone(),
                    }
                })?;
            let size = (depth.image.width(), depth.image.height());
            let depth_calibration = crate::camera::calibration(info, base_from_depth, size)?;
            if depth_calibration == calibration {
                // Aligned to the colour image: the organised frame turns only the pixels that
                // can matter into points, with the whole frame's answer.
                let range = DepthRange::default();
                plan_approach_on_depth(&colour, &depth.image, &calibration, &target, &range, params)
                    .map_err(|e| InputError::Perception(e.to_string()))?
            } else {
                let cloud = depth_cloud(depth, info, base_from_depth)?;
                plan_approach(&colour, &cloud, &calibration, &target, params)
                    .map_err(|e| InputError::Perception(e.to_string()))?
            }
        }
    };
    let header = Header { stamp: Time::now(), frame_id: base_frame.to_owned() };
    let tag = plan.tag.as_ref().map(|s| s.nearest());
    let tag_pose = tag.map(|tag| PoseStamped {
        header: header.clone(),
        pose: Pose::new(tag.centroid, tag_orientation(plan.backing_plane.as_ref())),
    });
    let goal_pose = plan.waypoint.as_ref().map(|w| PoseStamped {
        header: header.clone(),
        // Nav2 drives the base on the floor: the waypoint's height is the hand's, not the goal's.
        pose: Pose::new(
            Point3::new(w.position.x, w.position.y, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), w.yaw),
        ),
    });
    let markers = fig5_markers(&plan, &target, params, &header);
    Ok(ClickAnswer { plan, image: colour, calibration, tag_pose, goal_pose, markers })
}

/// The tag's frame: x into the backing plane (−normal), z as near up as that allows. Without a
/// plane the base frame's axes.
pub fn tag_orientation(plane: Option<&BackingPlane>) -> UnitQuaternion<f64> {
    let Some(plane) = plane else { return UnitQuaternion::identity() };
    let x = -plane.normal.normalize();
    let up = Vector3::z();
    let mut z = up - x * up.dot(&x);
    if z.norm() < 1e-6 {
        // A horizontal surface (a lid seen from above): keep the base's forward in the tag's z.
        z = Vector3::x() - x * x.x;
    }
    let z = z.normalize();
    let y = z.cross(&x);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_basis_unchecked(&[x, y, z]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(normal: Vector3<f64>) -> BackingPlane {
        BackingPlane { normal, offset: 0.0, points: 100 }
    }

    #[test]
    fn the_tag_frame_looks_into_the_plane_with_z_up() {
        for yaw in [0.0f64, 0.7, -2.0, 3.1] {
            let normal = Vector3::new(yaw.cos(), yaw.sin(), 0.1).normalize();
            let q = tag_orientation(Some(&plane(normal)));
            assert!((q * Vector3::x() + normal).norm() < 1e-9, "x is −normal at yaw {yaw}");
            let z = q * Vector3::z();
            assert!(z.z > 0.99 && z.dot(&normal).abs() < 1e-9, "z is up at yaw {yaw}: {z}");
        }
        let lid = tag_orientation(Some(&plane(Vector3::z())));
        assert!((lid * Vector3::x() + Vector3::z()).norm() < 1e-9);
    }

    #[test]
    fn a_click_without_its_inputs_says_which_is_missing() {
        let state = SensorState::default();
        let click = PointStamped {
            header: Header { frame_id: "base_link".into(), ..Header::default() },
            point: crate::msg::geometry::Point { x: 1.0, y: 0.0, z: 1.0 },
        };
        let params = ApproachParams::default();
        let missing = answer_click(&state, &click, "base_link", &params, None).unwrap_err();
        assert_eq!(missing, InputError::Missing("point cloud or depth image"));
        let elsewhere = PointStamped {
            header: Header { frame_id: "map".into(), ..Header::default() },
            ..click
        };
        let wrong = answer_click(&state, &elsewhere, "base_link", &params, None).unwrap_err();
        assert!(wrong.to_string().contains("`map`"), "{wrong}");
    }
}
