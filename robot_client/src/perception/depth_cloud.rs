//! An RGB-D camera's depth image, aligned to its colour image, turned into the base-frame cloud
//! the chain reads: the one conversion `perceive --depth` and the ROS 2 node share.
//!
//! Depth is the distance along the optical axis (z), as RealSense, Azure Kinect and OAK-D give
//! it, not along the ray. Pixel (u, v) is back-projected through its centre, (u + 0.5, v + 0.5)
//! in the calibration's pixel coordinates, the inverse of the chain's projection, so every point
//! lands on the very colour pixel it was measured at. Holes are dropped: 0, NaN, infinities
//! and anything outside [`DepthRange`]. The conversion allocates once per frame, never per point.
//! [`cloud_from_depth_in`] converts only a window of the frame ([`PixelWindow::of_box`]: the
//! pixels whose rays can meet a box around the target), in the same order.

use nalgebra::{Point3, Vector3};

use crate::hal::{CameraCalibration, PointCloud};

/// How the depth samples are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DepthEncoding {
    /// Unsigned 16-bit millimetres, 0 meaning no depth (16-bit PNG, ROS 2 `16UC1`).
    Millimetres16 { big_endian: bool },
    /// 32-bit float metres, 0 or NaN meaning no depth (PFM, ROS 2 `32FC1`).
    Metres32 { big_endian: bool },
}

impl DepthEncoding {
    /// Bytes one sample takes.
    pub fn sample_bytes(self) -> usize {
        match self {
            Self::Millimetres16 { .. } => 2,
            Self::Metres32 { .. } => 4,
        }
    }
}

/// A depth image, rows top to bottom, as raw bytes: files and messages hand theirs over
/// without a copy.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthImage {
    width: u32,
    height: u32,
    /// Bytes from the start of one row to the start of the next (drivers pad rows).
    row_bytes: usize,
    encoding: DepthEncoding,
    data: Vec<u8>,
}

impl DepthImage {
    /// Checks that `data` holds `height` rows of `width` samples `row_bytes` apart.
    pub fn new(
        width: u32,
        height: u32,
        row_bytes: usize,
        encoding: DepthEncoding,
        data: Vec<u8>,
    ) -> Result<Self, String> {
        if width == 0 || height == 0 {
            return Err(format!("it is {width}×{height} pixels"));
        }
        let row = width as usize * encoding.sample_bytes();
        if row_bytes < row {
            return Err(format!(
                "rows are {row_bytes} bytes apart, shorter than {width} samples ({row} bytes)"
            ));
        }
        let needed = row_bytes * (height as usize - 1) + row;
        if data.len() < needed {
            return Err(format!(
                "{} bytes of data for {height} rows {row_bytes} bytes apart ({needed} needed)",
                data.len()
            ));
        }
        Ok(Self { width, height, row_bytes, encoding, data })
    }

    /// Millimetres, rows unpadded, in this machine's byte order: what tests and the simulator
    /// make.
    pub fn from_millimetres(width: u32, height: u32, depth: &[u16]) -> Result<Self, String> {
        let data = depth.iter().flat_map(|d| d.to_ne_bytes()).collect();
        let big_endian = cfg!(target_endian = "big");
        let encoding = DepthEncoding::Millimetres16 { big_endian };
        Self::new(width, height, width as usize * 2, encoding, data)
    }

    /// Metres, rows unpadded, in this machine's byte order.
    pub fn from_metres(width: u32, height: u32, depth: &[f32]) -> Result<Self, String> {
        let data = depth.iter().flat_map(|d| d.to_ne_bytes()).collect();
        let big_endian = cfg!(target_endian = "big");
        Self::new(width, height, width as usize * 4, DepthEncoding::Metres32 { big_endian }, data)
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn encoding(&self) -> DepthEncoding {
        self.encoding
    }

    /// The depths of row `v`'s `columns` in metres, each handed to `each(u, z)`; holes come as 0
    /// or non-finite.
    fn for_each_in_row(
        &self,
        v: usize,
        columns: std::ops::Range<usize>,
        mut each: impl FnMut(usize, f32),
    ) {
        let bytes = self.encoding.sample_bytes();
        let start = v * self.row_bytes + columns.start * bytes;
        let row = &self.data[start..start + columns.len() * bytes];
        let first = columns.start;
        match self.encoding {
            DepthEncoding::Millimetres16 { big_endian } => {
                for (u, b) in row.chunks_exact(2).enumerate().map(|(i, b)| (first + i, b)) {
                    let b = [b[0], b[1]];
                    let mm = if big_endian { u16::from_be_bytes(b) } else { u16::from_le_bytes(b) };
                    each(u, f32::from(mm) * 1e-3);
                }
            }
            DepthEncoding::Metres32 { big_endian } => {
                for (u, b) in row.chunks_exact(4).enumerate().map(|(i, b)| (first + i, b)) {
                    let b = [b[0], b[1], b[2], b[3]];
                    let m = if big_endian { f32::from_be_bytes(b) } else { f32::from_le_bytes(b) };
                    each(u, m);
                }
            }
        }
    }
}

/// The depths kept, metres along the optical axis. Nearer or farther readings are what RGB-D
/// cameras give where they measured nothing (a stereo camera's minimum range, a structured-light
/// camera's saturated far field), not surfaces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthRange {
    pub near: f32,
    pub far: f32,
}

impl DepthRange {
    /// Whether a reading of `z` metres is a surface; NaN fails both comparisons, and so is
    /// dropped with 0 and the infinities.
    pub fn keeps(&self, z: f32) -> bool {
        z >= self.near && z <= self.far
    }
}

impl Default for DepthRange {
    /// 0.1–10 m: below the nearest any RGB-D camera measures (a D435 starts near 0.1 m at its
    /// smallest resolution), beyond the farthest they are specified for (10 m), and beyond the
    /// reach of a robot's perception of a tag the size of a hand.
    fn default() -> Self {
        Self { near: 0.1, far: 10.0 }
    }
}

/// Why a depth image cannot be turned into a cloud with this calibration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the depth image is {}×{} pixels but the camera calibration is for {}×{}; the depth must be \
     aligned to the colour image",
    depth.0, depth.1, camera.0, camera.1
)]
pub struct DepthSizeMismatch {
    pub depth: (u32, u32),
    pub camera: (u32, u32),
}

/// The base-frame cloud of `depth`, taken by the camera of `calibration`, holes dropped; the
/// points come in pixel order, rows top to bottom.
pub fn cloud_from_depth(
    depth: &DepthImage,
    calibration: &CameraCalibration,
    range: &DepthRange,
) -> Result<PointCloud, DepthSizeMismatch> {
    cloud_from_depth_in(depth, calibration, range, &PixelWindow::whole(depth.width, depth.height))
}

/// The cloud of the pixels of `window` alone, in the order [`cloud_from_depth`] gives them: an
/// organised frame need not turn a pixel into a point before it is known to matter.
pub fn cloud_from_depth_in(
    depth: &DepthImage,
    calibration: &CameraCalibration,
    range: &DepthRange,
    window: &PixelWindow,
) -> Result<PointCloud, DepthSizeMismatch> {
    let k = &calibration.intrinsics;
    if (depth.width, depth.height) != (k.width, k.height) {
        return Err(DepthSizeMismatch {
            depth: (depth.width, depth.height),
            camera: (k.width, k.height),
        });
    }
    let base_from_camera = calibration.base_from_camera.cast::<f32>();
    let rotation = base_from_camera.rotation.to_rotation_matrix();
    let r = rotation.matrix();
    let origin = base_from_camera.translation.vector;
    let [u0, v0, u1, v1] = window.clamped(k.width, k.height);
    // p = R (z x_u, z y_v, z) + t = z (R₀ x_u + R₁ y_v + R₂) + t: one vector per column, one per
    // row, and per pixel a sum, a scale and a shift.
    let columns: Vec<Vector3<f32>> =
        (u0..u1).map(|u| r.column(0) * ((f64::from(u) + 0.5 - k.cx) / k.fx) as f32).collect();
    let mut points = Vec::with_capacity(((u1 - u0) * (v1 - v0)) as usize);
    for v in v0 as usize..v1 as usize {
        let row = r.column(1) * ((v as f64 + 0.5 - k.cy) / k.fy) as f32 + r.column(2);
        depth.for_each_in_row(v, u0 as usize..u1 as usize, |u, z| {
            if range.keeps(z) {
                points.push(Point3::from((columns[u - u0 as usize] + row) * z + origin));
            }
        });
    }
    Ok(PointCloud { points })
}

/// The pixels of `window` that [`cloud_from_depth_in`] makes points of, in the order it makes
/// them, each handed to `each(u, v, z)` with its depth in metres.
pub(crate) fn for_each_depth_in(
    depth: &DepthImage,
    range: &DepthRange,
    window: &PixelWindow,
    mut each: impl FnMut(u32, u32, f32),
) {
    let [u0, v0, u1, v1] = window.clamped(depth.width, depth.height);
    for v in v0..v1 {
        depth.for_each_in_row(v as usize, u0 as usize..u1 as usize, |u, z| {
            if range.keeps(z) {
                each(u as u32, v, z);
            }
        });
    }
}

/// A rectangle of pixels, `[u0, v0, u1, v1)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelWindow {
    pub columns: [u32; 2],
    pub rows: [u32; 2],
}

impl PixelWindow {
    pub fn whole(width: u32, height: u32) -> Self {
        Self { columns: [0, width], rows: [0, height] }
    }

    /// The pixels whose rays can meet the box from `min` to `max` (base frame, metres), and
    /// `pad` pixels around: the box's corners projected, the image where a corner lies behind
    /// the lens (a box around the camera is seen everywhere).
    pub fn of_box(
        calibration: &CameraCalibration,
        min: &Point3<f64>,
        max: &Point3<f64>,
        pad: u32,
    ) -> Self {
        let k = &calibration.intrinsics;
        let camera_from_base = calibration.base_from_camera.inverse();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for corner in 0..8 {
            let pick = |bit: usize, a: f64, b: f64| if corner & bit == 0 { a } else { b };
            let p =
                Point3::new(pick(1, min.x, max.x), pick(2, min.y, max.y), pick(4, min.z, max.z));
            let c = camera_from_base * p;
            // Within a millimetre of the lens plane a projection says nothing useful.
            let Some(pixel) = k.project(&c).filter(|_| c.z > 1e-3) else {
                return Self::whole(k.width, k.height);
            };
            // Pixel u is the ray through u + 0.5.
            lo = [lo[0].min(pixel.x - 0.5), lo[1].min(pixel.y - 0.5)];
            hi = [hi[0].max(pixel.x - 0.5), hi[1].max(pixel.y - 0.5)];
        }
        let pad = f64::from(pad);
        let bound = |x: f64, n: u32| x.clamp(0.0, f64::from(n)) as u32;
        Self {
            columns: [
                bound(lo[0].floor() - pad, k.width),
                bound(hi[0].ceil() + 1.0 + pad, k.width),
            ],
            rows: [bound(lo[1].floor() - pad, k.height), bound(hi[1].ceil() + 1.0 + pad, k.height)],
        }
    }

    /// Pixels in the window.
    pub fn area(&self) -> u64 {
        u64::from(self.columns[1].saturating_sub(self.columns[0]))
            * u64::from(self.rows[1].saturating_sub(self.rows[0]))
    }

    /// The window cut to an image `width` × `height` pixels: first column, first row, and one
    /// past the last of each.
    pub(super) fn clamped(&self, width: u32, height: u32) -> [u32; 4] {
        let u1 = self.columns[1].min(width);
        let v1 = self.rows[1].min(height);
        [self.columns[0].min(u1), self.rows[0].min(v1), u1, v1]
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Vector3};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::hal::CameraIntrinsics;

    fn calibration(width: u32, height: u32, rng: &mut impl Rng) -> CameraCalibration {
        CameraCalibration {
            intrinsics: CameraIntrinsics {
                width,
                height,
                fx: rng.random_range(200.0..900.0),
                fy: rng.random_range(200.0..900.0),
                cx: f64::from(width) / 2.0 + rng.random_range(-20.0..20.0),
                cy: f64::from(height) / 2.0 + rng.random_range(-20.0..20.0),
            },
            base_from_camera: Isometry3::new(
                Vector3::new(
                    rng.random_range(-0.5..0.5),
                    rng.random_range(-0.5..0.5),
                    rng.random_range(0.3..1.8),
                ),
                Vector3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                ),
            ),
        }
    }

    #[test]
    fn every_point_projects_back_onto_its_pixel_at_its_depth() {
        let mut rng = ChaCha8Rng::seed_from_u64(34);
        for _ in 0..200 {
            let (width, height) = (rng.random_range(1..40), rng.random_range(1..30));
            let calibration = calibration(width, height, &mut rng);
            let metres: Vec<f32> =
                (0..width * height).map(|_| rng.random_range(0.2f32..9.0)).collect();
            let depth = DepthImage::from_metres(width, height, &metres).unwrap();
            let cloud = cloud_from_depth(&depth, &calibration, &DepthRange::default()).unwrap();
            assert_eq!(cloud.len(), metres.len());
            let camera_from_base = calibration.base_from_camera.inverse();
            for (i, p) in cloud.points.iter().enumerate() {
                let in_camera = camera_from_base * p.cast::<f64>();
                let pixel = calibration.intrinsics.project(&in_camera).unwrap();
                let (u, v) = (i as u32 % width, i as u32 / width);
                assert!((in_camera.z - f64::from(metres[i])).abs() < 1e-5, "depth at {i}");
                assert!((pixel.x - (f64::from(u) + 0.5)).abs() < 1e-3, "column at {i}");
                assert!((pixel.y - (f64::from(v) + 0.5)).abs() < 1e-3, "row at {i}");
            }
        }
    }

    #[test]
    fn holes_and_readings_out_of_range_are_dropped() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let calibration = calibration(4, 2, &mut rng);
        let metres = [0.0, f32::NAN, f32::INFINITY, -1.0, 0.05, 12.0, 1.0, 2.5];
        let depth = DepthImage::from_metres(4, 2, &metres).unwrap();
        let cloud = cloud_from_depth(&depth, &calibration, &DepthRange::default()).unwrap();
        assert_eq!(cloud.len(), 2);
        let camera_from_base = calibration.base_from_camera.inverse();
        let z: Vec<f64> = cloud.points.iter().map(|p| (camera_from_base * p.cast()).z).collect();
        assert!((z[0] - 1.0).abs() < 1e-6 && (z[1] - 2.5).abs() < 1e-6, "{z:?}");
        let millimetres = [0, 1500, 65535, 99, 100, 10_000, 10_001, 0];
        let depth = DepthImage::from_millimetres(4, 2, &millimetres).unwrap();
        let cloud = cloud_from_depth(&depth, &calibration, &DepthRange::default()).unwrap();
        assert_eq!(cloud.len(), 3, "1.5 m, 0.1 m and 10 m are kept");
    }

    #[test]
    fn padded_big_endian_rows_read_as_the_same_depths() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let calibration = calibration(3, 2, &mut rng);
        let millimetres = [1000u16, 1200, 1400, 2000, 0, 3000];
        let mut padded = Vec::new();
        for row in millimetres.chunks(3) {
            padded.extend(row.iter().flat_map(|d| d.to_be_bytes()));
            padded.extend_from_slice(&[0xEE; 4]);
        }
        let encoding = DepthEncoding::Millimetres16 { big_endian: true };
        let depth = DepthImage::new(3, 2, 10, encoding, padded).unwrap();
        let plain = DepthImage::from_millimetres(3, 2, &millimetres).unwrap();
        let range = DepthRange::default();
        assert_eq!(
            cloud_from_depth(&depth, &calibration, &range).unwrap(),
            cloud_from_depth(&plain, &calibration, &range).unwrap()
        );
    }

    #[test]
    fn a_depth_image_of_another_size_or_short_of_data_is_refused_in_words() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let calibration = calibration(4, 3, &mut rng);
        let depth = DepthImage::from_millimetres(3, 4, &[1000; 12]).unwrap();
        let refused = cloud_from_depth(&depth, &calibration, &DepthRange::default()).unwrap_err();
        assert!(refused.to_string().contains("3×4 pixels but the camera calibration is for 4×3"));
        let encoding = DepthEncoding::Metres32 { big_endian: false };
        let short = DepthImage::new(4, 3, 16, encoding, vec![0; 47]).unwrap_err();
        assert!(short.contains("48 needed"), "{short}");
        let narrow = DepthImage::new(4, 3, 15, encoding, vec![0; 64]).unwrap_err();
        assert!(narrow.contains("shorter than 4 samples"), "{narrow}");
    }
}
