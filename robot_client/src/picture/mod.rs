//! What the robot saw: the camera view around the tag with the paper's Fig. 5 drawn in and a
//! legend below, small enough to travel with every trial (DESIGN §10, trial pictures).
//!
//! The picture is for a person recognising the device and judging what perception did; it is
//! never read back by the robot.

mod legend;
mod overlay;

use nalgebra::Point3;

pub use overlay::draw_overlay;

use crate::hal::{CameraCalibration, ColorImage};
use crate::navigation::{ApproachPlan, RobotFootprint};
use crate::sensor_files::encode_png;

/// The largest picture the robot sends, in bytes (the registry takes up to 256 KiB).
pub const MAX_PICTURE_BYTES: usize = 200 * 1024;
/// The view around the tag, in pixels, before the legend: enough to show what is around it.
const VIEW: (u32, u32) = (320, 240);

/// The trial's picture as PNG bytes: the view around the tag (the image's middle when no tag was
/// seen), halved until it fits [`MAX_PICTURE_BYTES`].
pub fn trial_picture(
    image: &ColorImage,
    calibration: &CameraCalibration,
    plan: &ApproachPlan,
    footprint: &RobotFootprint,
) -> Result<Vec<u8>, png::EncodingError> {
    let drawn = draw_overlay(image, calibration, plan, footprint);
    let centre = plan
        .tag
        .as_ref()
        .and_then(|sighting| pixel_of(calibration, &sighting.nearest().centroid))
        .unwrap_or((f64::from(image.width) / 2.0, f64::from(image.height) / 2.0));
    let mut view = crop(&drawn, centre, VIEW);
    loop {
        let bytes = encode_png(&legend::with_legend(&view, &overlay::KEY))?;
        if bytes.len() <= MAX_PICTURE_BYTES || view.width < 64 {
            return Ok(bytes);
        }
        view = halve(&view);
    }
}

/// Where a base-frame point falls in the image.
fn pixel_of(calibration: &CameraCalibration, p: &Point3<f64>) -> Option<(f64, f64)> {
    let in_camera = calibration.base_from_camera.inverse() * p;
    calibration.intrinsics.project(&in_camera).map(|uv| (uv.x, uv.y))
}

/// The `size` window of `image` centred on `centre` as far as the image allows.
fn crop(image: &ColorImage, centre: (f64, f64), size: (u32, u32)) -> ColorImage {
    let (width, height) = (size.0.min(image.width), size.1.min(image.height));
    let start = |c: f64, window: u32, whole: u32| {
        let first = (c - f64::from(window) / 2.0).round().max(0.0) as u32;
        first.min(whole - window)
    };
    let (x0, y0) = (start(centre.0, width, image.width), start(centre.1, height, image.height));
    let mut out = ColorImage::new(width, height);
    for row in 0..height as usize {
        let from = ((y0 as usize + row) * image.width as usize + x0 as usize) * 3;
        let to = row * width as usize * 3;
        out.rgb[to..to + width as usize * 3]
            .copy_from_slice(&image.rgb[from..from + width as usize * 3]);
    }
    out
}

/// The image at half its size, each pixel the mean of four.
fn halve(image: &ColorImage) -> ColorImage {
    let (width, height) = (image.width / 2, image.height / 2);
    let mut out = ColorImage::new(width, height);
    let at = |x: u32, y: u32, c: usize| {
        u16::from(image.rgb[(y as usize * image.width as usize + x as usize) * 3 + c])
    };
    for y in 0..height {
        for x in 0..width {
            for c in 0..3 {
                let sum = at(2 * x, 2 * y, c)
                    + at(2 * x + 1, 2 * y, c)
                    + at(2 * x, 2 * y + 1, c)
                    + at(2 * x + 1, 2 * y + 1, c);
                out.rgb[(y as usize * width as usize + x as usize) * 3 + c] = (sum / 4) as u8;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(width: u32, height: u32) -> ColorImage {
        let mut image = ColorImage::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let at = ((y * width + x) * 3) as usize;
                image.rgb[at..at + 3].copy_from_slice(&[x as u8, y as u8, 7]);
            }
        }
        image
    }

    #[test]
    fn the_crop_stays_inside_the_image_and_centres_where_it_can() {
        let image = gradient(200, 100);
        let middle = crop(&image, (100.0, 50.0), (40, 20));
        assert_eq!((middle.width, middle.height), (40, 20));
        assert_eq!(&middle.rgb[..3], &[80, 40, 7]);
        let corner = crop(&image, (-50.0, 500.0), (40, 20));
        assert_eq!(&corner.rgb[..3], &[0, 80, 7], "pushed back inside at the bottom left");
        let larger = crop(&image, (100.0, 50.0), (400, 300));
        assert_eq!((larger.width, larger.height), (200, 100), "never more than the image");
        assert_eq!(larger, image);
    }

    #[test]
    fn halving_averages_four_pixels() {
        let half = halve(&gradient(4, 2));
        assert_eq!((half.width, half.height), (2, 1));
        assert_eq!(&half.rgb[..], &[0, 0, 7, 2, 0, 7]);
    }
}
