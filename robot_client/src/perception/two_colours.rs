//! Where a point's colour lies on the chroma disc, as the camera's pixels around it say: what
//! the division of a red region by colour ([`super::bounded_tag`]) compares. A red plastic
//! lying against a tag of nearly its colour overlaps it pixel by pixel, since a camera's noise
//! spreads each about as far as they differ; the mean over the pixels around each point
//! overlaps less, and [`super::two_clusters`] pools it over the voxels around.

use nalgebra::Point3;

use super::hsv::chroma_point;
use crate::hal::{CameraCalibration, ColorImage};

/// Where each point's pixel lies on the chroma disc (saturation as radius, hue as angle), or
/// `None` when the point is outside the picture.
pub(super) fn colours_of(
    points: &[Point3<f32>],
    image: &ColorImage,
    calibration: &CameraCalibration,
) -> Vec<Option<[f32; 2]>> {
    colours_around(points, image, calibration, 0)
}

/// Where on the chroma disc the pixels around each point's pixel lie on average: the mean over
/// the square `reach` pixels around it, clipped to the picture; `None` when the point is outside.
pub(super) fn colours_around(
    points: &[Point3<f32>],
    image: &ColorImage,
    calibration: &CameraCalibration,
    reach: u32,
) -> Vec<Option<[f32; 2]>> {
    colours_at(&pixels_of(points, image, calibration), image, reach)
}

/// [`colours_around`] the pixels `pixels` (`None`: outside the picture).
pub(super) fn colours_at(
    pixels: &[Option<(u32, u32)>],
    image: &ColorImage,
    reach: u32,
) -> Vec<Option<[f32; 2]>> {
    pixels.iter().map(|px| px.map(|(x, y)| mean_colour_around(image, x, y, reach))).collect()
}

/// The pixel each point lands on, or `None` when it lands outside the picture.
pub(super) fn pixels_of(
    points: &[Point3<f32>],
    image: &ColorImage,
    calibration: &CameraCalibration,
) -> Vec<Option<(u32, u32)>> {
    let pixel_of = pixel_finder(image, calibration);
    points.iter().map(|p| pixel_of(&p.cast::<f64>())).collect()
}

/// The pixel of `image` a point in the base frame lands on, `None` off the picture or behind
/// the camera.
pub(super) fn pixel_finder<'a>(
    image: &'a ColorImage,
    calibration: &'a CameraCalibration,
) -> impl Fn(&Point3<f64>) -> Option<(u32, u32)> + 'a {
    let camera_from_base = calibration.base_from_camera.inverse();
    move |p| {
        let uv = calibration.intrinsics.project(&(camera_from_base * p))?;
        let inside = uv.x >= 0.0
            && uv.y >= 0.0
            && uv.x < f64::from(image.width)
            && uv.y < f64::from(image.height);
        inside.then_some((uv.x as u32, uv.y as u32))
    }
}

/// The mean colour, on the chroma disc, of the pixels within `reach` of pixel (`x`, `y`).
pub(super) fn mean_colour_around(image: &ColorImage, x: u32, y: u32, reach: u32) -> [f32; 2] {
    let (xs, ys) = (
        x.saturating_sub(reach)..=(x + reach).min(image.width - 1),
        y.saturating_sub(reach)..=(y + reach).min(image.height - 1),
    );
    let (mut sum, mut n) = ([0.0f32; 2], 0.0f32);
    for y in ys {
        for x in xs.clone() {
            let c = chroma_point(image.pixel(x, y));
            sum = [sum[0] + c[0], sum[1] + c[1]];
            n += 1.0;
        }
    }
    [sum[0] / n, sum[1] / n]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pixels_around_a_point_average_the_cameras_noise_away() {
        // A 9 × 9 image of red whose blue channel alternates pixel by pixel, as a camera's
        // noise scatters it, seen straight on from 1 m by a camera one pixel per millimetre.
        let mut image = ColorImage::new(9, 9);
        for y in 0..9u32 {
            for x in 0..9u32 {
                let i = (y as usize * 9 + x as usize) * 3;
                let blue = if (x + y) % 2 == 0 { 0 } else { 60 };
                image.rgb[i..i + 3].copy_from_slice(&[200, 20, blue]);
            }
        }
        let calibration = CameraCalibration {
            intrinsics: crate::hal::CameraIntrinsics {
                width: 9,
                height: 9,
                fx: 1000.0,
                fy: 1000.0,
                cx: 0.0,
                cy: 0.0,
            },
            base_from_camera: nalgebra::Isometry3::identity(),
        };
        let points: Vec<Point3<f32>> = (2..7)
            .flat_map(|y| (2..7).map(move |x| (x, y)))
            .map(|(x, y)| Point3::new(x as f32 * 1e-3 + 5e-4, y as f32 * 1e-3 + 5e-4, 1.0))
            .collect();
        let spread = |colours: Vec<Option<[f32; 2]>>| {
            let colours: Vec<[f32; 2]> = colours.into_iter().map(Option::unwrap).collect();
            let distance = |a: &[f32; 2], b: &[f32; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
            let pairs = colours.iter().flat_map(|a| colours.iter().map(move |b| distance(a, b)));
            pairs.fold(0.0f32, f32::max)
        };
        let one = spread(colours_of(&points, &image, &calibration));
        let around = spread(colours_around(&points, &image, &calibration, 1));
        // Pixel by pixel the hues lie 0.2 apart on the disc; the nine around each differ by
        // one pixel of nine each way.
        assert!(one > 0.15, "{one}");
        assert!(around < one / 4.0, "{around} against {one}");
    }
}
