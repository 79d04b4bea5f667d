//! What a trial is sent with from the click that led to it (DESIGN §10): the view of the latest
//! click — the camera image, its calibration and what perception made of it — goes with the
//! next trial recorded after it, drawn as the paper's Fig. 5 by the code `pps-robot run` uses;
//! and once the fingers have read the tag's EPC, the colour of the pixels the click took for
//! the tag and its size on the surface behind it, by the functions `pps-robot run` uses, so
//! that the registry learns the tag's colour and size.
//!
//! The rule, since a trial on `/pps/trial` does not say which click led to it: a view goes with
//! a trial that finished after the click and started at most [`VIEW_FRESH_FOR`] after it, and
//! with one trial only. A trial with no such view is recorded without a picture. The tag's
//! colour and size go only when the fingers' latest inventory round since the click in which tags
//! answered chose the trial's EPC unambiguously: only then are the pixels known to be that tag.

use std::sync::Mutex;
use std::time::Duration;

use pps_robot::hal::{CameraCalibration, ColorImage};
use pps_robot::navigation::{ApproachPlan, RobotFootprint};
use pps_robot::perception::{TagSearchParams, tag_color, tag_size};
use pps_robot::picture::trial_picture;
use pps_schema::{Epc, TagColor, TagSize, Trial};
use time::OffsetDateTime;

/// How long after a click the robot may start acting on what it showed.
pub const VIEW_FRESH_FOR: Duration = Duration::from_secs(10 * 60);

/// What a click saw and made of it.
#[derive(Debug, Clone)]
pub struct PerceivedView {
    pub image: ColorImage,
    pub calibration: CameraCalibration,
    pub plan: ApproachPlan,
    pub at: OffsetDateTime,
    /// The EPC the fingers' latest inventory round since the click chose unambiguously; `None`
    /// before any, or when that round found two tags alike.
    pub read: Option<Epc>,
}

impl PerceivedView {
    /// Whether `trial` may be what the robot did after this view.
    fn led_to(&self, trial: &Trial) -> bool {
        trial.finished_at >= self.at && trial.started_at <= self.at + VIEW_FRESH_FOR
    }

    /// The colour statistics of the pixels this view took for the tag, for `trial`: `None`
    /// unless the fingers read the trial's EPC since, or when no tag was found. `params` are the
    /// tag search's, whose thresholds every pixel counted passed.
    pub fn tag_color(&self, trial: &Trial, params: &TagSearchParams) -> Option<TagColor> {
        if self.read.as_ref() != Some(&trial.epc) {
            return None;
        }
        let tag = self.plan.tag.as_ref()?.nearest();
        tag_color(&self.image, &self.calibration, tag, params)
    }

    /// The size of what this view took for the tag on the surface behind it, for `trial`, on
    /// the same condition as [`Self::tag_color`]; `None` too when no surface was found.
    pub fn tag_size(&self, trial: &Trial, params: &TagSearchParams) -> Option<TagSize> {
        if self.read.as_ref() != Some(&trial.epc) {
            return None;
        }
        let tag = self.plan.tag.as_ref()?.nearest();
        let surface = self.plan.backing_plane.as_ref()?;
        tag_size(&self.image, &self.calibration, tag, params, &surface.normal)
    }

    /// The Fig. 5 picture of this view, PNG bytes; `None` (and a warning) when it cannot be
    /// encoded.
    pub fn picture(&self, footprint: &RobotFootprint) -> Option<Vec<u8>> {
        match trial_picture(&self.image, &self.calibration, &self.plan, footprint) {
            Ok(bytes) => Some(bytes),
            Err(error) => {
                tracing::warn!("no picture for the trial: it could not be encoded ({error})");
                None
            }
        }
    }
}

/// The latest click's view, waiting for the trial it led to.
#[derive(Debug, Default)]
pub struct LastView(Mutex<Option<PerceivedView>>);

impl LastView {
    /// A new click's view replaces any view still waiting.
    pub fn perceived(&self, view: PerceivedView) {
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(view);
    }

    /// The fingers' latest inventory round in which tags answered chose `epc` unambiguously
    /// (`None`: two tags alike): the waiting view's tag, if the next trial names it.
    pub fn read(&self, epc: Option<Epc>) {
        if let Some(view) = self.0.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
            view.read = epc;
        }
    }

    /// The view that goes with `trial`, taken so that it goes with no other.
    pub fn take_for(&self, trial: &Trial) -> Option<PerceivedView> {
        let mut slot = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if slot.as_ref().is_some_and(|view| view.led_to(trial)) { slot.take() } else { None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Point3};
    use pps_robot::hal::{CameraIntrinsics, PointCloud};
    use pps_robot::navigation::{ApproachParams, plan_approach};
    use serde_json::json;
    use time::macros::datetime;

    /// A view of nothing: a dark image and no cloud, so no tag.
    fn view_at(at: OffsetDateTime) -> PerceivedView {
        let image = ColorImage::new(64, 48);
        let calibration = CameraCalibration {
            intrinsics: CameraIntrinsics {
                width: 64,
                height: 48,
                fx: 50.0,
                fy: 50.0,
                cx: 32.0,
                cy: 24.0,
            },
            base_from_camera: Isometry3::identity(),
        };
        let plan = plan_approach(
            &image,
            &PointCloud::default(),
            &calibration,
            &Point3::new(1.0, 0.0, 1.0),
            &ApproachParams::default(),
        )
        .unwrap();
        PerceivedView { image, calibration, plan, at, read: None }
    }

    fn trial(started: OffsetDateTime, finished: OffsetDateTime) -> Trial {
        let format = &time::format_description::well_known::Rfc3339;
        serde_json::from_value(json!({
            "id": "7d1f2b9e-4c3a-4e55-9a41-0c2d9b6e8f10", "epc": "355AB1C60000001000000001",
            "robot": "el-e-1", "action": "on", "behavior": "push_top",
            "started_at": started.format(format).unwrap(),
            "finished_at": finished.format(format).unwrap(),
            "outcome": "success", "detector": {}, "forces": [], "measurements": {}
        }))
        .unwrap()
    }

    #[test]
    fn a_view_goes_with_the_one_trial_that_followed_it() {
        let click = datetime!(2026-12-05 10:00:00 UTC);
        let views = LastView::default();
        views.perceived(view_at(click));
        let earlier = trial(click - Duration::from_secs(60), click - Duration::from_secs(1));
        assert!(views.take_for(&earlier).is_none(), "a trial over before the click");
        let much_later =
            trial(click + Duration::from_secs(3600), click + Duration::from_secs(3620));
        assert!(views.take_for(&much_later).is_none(), "a trial an hour after the click");
        let next = trial(click + Duration::from_secs(5), click + Duration::from_secs(25));
        let view = views.take_for(&next).expect("the trial that followed the click");
        assert_eq!(view.at, click);
        assert!(views.take_for(&next).is_none(), "a view goes with one trial only");

        views.perceived(view_at(click));
        views.perceived(view_at(click + Duration::from_secs(30)));
        let after_both = trial(click + Duration::from_secs(40), click + Duration::from_secs(50));
        assert_eq!(views.take_for(&after_both).unwrap().at, click + Duration::from_secs(30));
    }

    #[test]
    fn a_read_belongs_to_the_click_it_followed() {
        let click = datetime!(2026-12-05 10:00:00 UTC);
        let epc = Epc::parse("355AB1C60000001000000001").unwrap();
        let views = LastView::default();
        views.read(Some(epc.clone()));
        views.perceived(view_at(click));
        let next = trial(click + Duration::from_secs(5), click + Duration::from_secs(25));
        assert_eq!(views.take_for(&next).unwrap().read, None, "a read before the click");
        views.perceived(view_at(click));
        views.read(Some(epc.clone()));
        assert_eq!(views.take_for(&next).unwrap().read, Some(epc.clone()));
        views.perceived(view_at(click));
        views.read(Some(epc.clone()));
        views.read(None);
        assert_eq!(views.take_for(&next).unwrap().read, None, "then two tags alike");
        views.perceived(view_at(click));
        views.read(Some(epc));
        views.perceived(view_at(click + Duration::from_secs(1)));
        assert_eq!(views.take_for(&next).unwrap().read, None, "a new click forgets the read");
    }

    #[test]
    fn the_picture_is_a_png_within_the_size_a_trial_may_carry() {
        let view = view_at(datetime!(2026-12-05 10:00:00 UTC));
        let png = view.picture(&RobotFootprint::default()).expect("a picture");
        assert_eq!(&png[1..4], b"PNG");
        assert!(png.len() <= pps_robot::picture::MAX_PICTURE_BYTES);
    }
}
