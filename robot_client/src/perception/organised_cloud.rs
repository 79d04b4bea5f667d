//! A depth frame's cloud that knows where its points came from: each point's pixel and depth
//! are read from the depth image again, in the conversion's order, rather than found by
//! projecting the point back into the image (a rigid transform and two divisions a point, and
//! rounding that can only lose what the conversion knew exactly). Nothing is stored a point:
//! walking the window's depths again costs less than keeping a pixel beside every point.

use nalgebra::Point3;

use super::depth_cloud::{
    DepthImage, DepthRange, DepthSizeMismatch, PixelWindow, cloud_from_depth_in, for_each_depth_in,
};
use crate::hal::{CameraCalibration, PointCloud};

/// [`cloud_from_depth_in`], its points knowing their pixels: the steps after it read a point's
/// pixel and depth from the image instead of projecting the point back into it.
pub fn organised_cloud_from_depth_in<'a>(
    depth: &'a DepthImage,
    calibration: &CameraCalibration,
    range: &DepthRange,
    window: &PixelWindow,
) -> Result<OrganisedCloud<'a>, DepthSizeMismatch> {
    let cloud = cloud_from_depth_in(depth, calibration, range, window)?;
    let k = &calibration.intrinsics;
    let [u0, v0, u1, v1] = window.clamped(k.width, k.height);
    let window = PixelWindow { columns: [u0, u1], rows: [v0, v1] };
    Ok(OrganisedCloud::new(cloud, depth, *range, window))
}

/// A base-frame cloud whose every point came from one pixel of `depth`, aligned to the colour
/// image: the pixels of `window` whose depth `range` keeps, in pixel order, rows top to bottom.
#[derive(Debug, Clone)]
pub struct OrganisedCloud<'a> {
    cloud: PointCloud,
    depth: &'a DepthImage,
    range: DepthRange,
    /// The pixels the cloud was made of, within the image.
    window: PixelWindow,
}

impl<'a> OrganisedCloud<'a> {
    /// `cloud` must be the conversion of `window` of `depth` under `range`.
    pub(crate) fn new(
        cloud: PointCloud,
        depth: &'a DepthImage,
        range: DepthRange,
        window: PixelWindow,
    ) -> Self {
        Self { cloud, depth, range, window }
    }

    pub fn cloud(&self) -> &PointCloud {
        &self.cloud
    }

    pub fn window(&self) -> &PixelWindow {
        &self.window
    }

    /// Each point's index, pixel (column, row) and depth as the camera measured it (metres
    /// along the optical axis), in the cloud's order.
    pub fn for_each_pixel(&self, mut each: impl FnMut(usize, u32, u32, f32)) {
        let mut i = 0;
        for_each_depth_in(self.depth, &self.range, &self.window, |u, v, z| {
            each(i, u, v, z);
            i += 1;
        });
        debug_assert_eq!(i, self.cloud.len(), "a point a kept pixel");
    }

    /// The points, to move along their rays: their pixels stay theirs.
    pub(crate) fn points_mut(&mut self) -> &mut [Point3<f32>] {
        &mut self.cloud.points
    }
}
