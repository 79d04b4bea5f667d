//! The paper's Fig. 5 drawn into the camera image, so a person can look at what perception made
//! of a scan instead of reading numbers (`perceive --overlay`, and every trial's picture). The
//! paper's key: cyan points lie in the volume of interest, red ones are the tag's, dark green
//! ones the backing plane's, and yellow-green boxes are the robot's body and extended arm
//! checked for collisions at the waypoint (here with the waypoint itself as a yellow-green disc
//! and a heading tick).

use nalgebra::{Isometry3, Point2, Point3, Vector3};

use crate::hal::{CameraCalibration, ColorImage};
use crate::navigation::{ApproachPlan, RobotFootprint};

pub(super) const CYAN: [u8; 3] = [0, 230, 230];
pub(super) const RED: [u8; 3] = [255, 30, 30];
pub(super) const DARK_GREEN: [u8; 3] = [0, 110, 30];
pub(super) const YELLOW_GREEN: [u8; 3] = [170, 230, 40];

/// The key of the markings as the legend prints it: in a caretaker's words, since the picture
/// is what the tag's page shows first (the paper's: volume of interest, tag, backing plane,
/// robot at the waypoint).
pub(super) const KEY: [([u8; 3], &str); 4] = [
    (CYAN, "where it looked"),
    (RED, "the tag"),
    (DARK_GREEN, "surface behind it"),
    (YELLOW_GREEN, "where it stood"),
];

/// The camera image, dimmed so the markings stand out, with the plan drawn in.
pub fn draw_overlay(
    image: &ColorImage,
    calibration: &CameraCalibration,
    plan: &ApproachPlan,
    footprint: &RobotFootprint,
) -> ColorImage {
    let mut canvas = Canvas {
        image: ColorImage {
            rgb: image.rgb.iter().map(|&c| (u16::from(c) * 3 / 5) as u8).collect(),
            ..image.clone()
        },
        camera_from_base: calibration.base_from_camera.inverse(),
        calibration: *calibration,
    };
    for p in &plan.surface_points {
        canvas.dot(&p.cast(), 0, CYAN);
    }
    let backing = plan.backing_index.and_then(|i| plan.planes.get(i));
    for &i in backing.map(|p| &p.inliers[..]).unwrap_or_default() {
        canvas.dot(&plan.surface_points[i as usize].cast(), 1, DARK_GREEN);
    }
    if let Some(sighting) = &plan.tag {
        for p in &sighting.nearest().members {
            canvas.dot(&p.cast(), 1, RED);
        }
    }
    if let Some(waypoint) = &plan.waypoint {
        let at = waypoint.position;
        let heading = Vector3::new(waypoint.yaw.cos(), waypoint.yaw.sin(), 0.0);
        let floor = Point3::new(at.x, at.y, 0.0);
        let pose = Isometry3::new(floor.coords, Vector3::z() * waypoint.yaw);
        let f = footprint;
        canvas.cuboid(
            &pose,
            [-f.base_half_length, -f.base_half_width, f.floor_clearance],
            [f.base_half_length, f.base_half_width, f.height],
        );
        canvas.cuboid(
            &pose,
            [f.base_half_length, -f.arm_half_width, at.z - f.arm_half_height],
            [f.arm_reach, f.arm_half_width, at.z + f.arm_half_height],
        );
        canvas.dot(&at, 5, YELLOW_GREEN);
        canvas.line(&at, &(at + heading * 0.15), YELLOW_GREEN);
    }
    canvas.image
}

/// The part of the segment `a`–`b` inside the frame `[0, width] × [0, height]` (pixels), by
/// Liang–Barsky: a line that leaves the frame is drawn to its edge and no further.
fn clip_to_frame(
    a: Point2<f64>,
    b: Point2<f64>,
    (width, height): (f64, f64),
) -> Option<(Point2<f64>, Point2<f64>)> {
    let d = b - a;
    let (mut enter, mut leave) = (0.0f64, 1.0f64);
    for (p, q) in [(-d.x, a.x), (d.x, width - a.x), (-d.y, a.y), (d.y, height - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
            continue;
        }
        let t = q / p;
        if p < 0.0 {
            enter = enter.max(t);
        } else {
            leave = leave.min(t);
        }
    }
    (enter <= leave).then(|| (a + d * enter, a + d * leave))
}

struct Canvas {
    image: ColorImage,
    camera_from_base: Isometry3<f64>,
    calibration: CameraCalibration,
}

impl Canvas {
    /// Where a base-frame point falls in the image, if in front of the camera.
    fn pixel(&self, p: &Point3<f64>) -> Option<(f64, f64)> {
        let uv = self.calibration.intrinsics.project(&(self.camera_from_base * p))?;
        Some((uv.x, uv.y))
    }

    fn paint(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        let (w, h) = (i64::from(self.image.width), i64::from(self.image.height));
        if (0..w).contains(&x) && (0..h).contains(&y) {
            let at = ((y * w + x) * 3) as usize;
            self.image.rgb[at..at + 3].copy_from_slice(&colour);
        }
    }

    /// A filled square of half-size `radius` pixels at the point's pixel.
    fn dot(&mut self, p: &Point3<f64>, radius: i64, colour: [u8; 3]) {
        let Some((u, v)) = self.pixel(p) else { return };
        let (u, v) = (u.floor() as i64, v.floor() as i64);
        for y in v - radius..=v + radius {
            for x in u - radius..=u + radius {
                self.paint(x, y, colour);
            }
        }
    }

    /// A segment between two base-frame points, the part behind the camera cut off.
    fn line(&mut self, a: &Point3<f64>, b: &Point3<f64>, colour: [u8; 3]) {
        const NEAR: f64 = 0.05;
        let (mut ca, mut cb) = (self.camera_from_base * a, self.camera_from_base * b);
        if ca.z < NEAR && cb.z < NEAR {
            return;
        }
        if ca.z < NEAR || cb.z < NEAR {
            let s = (NEAR - ca.z) / (cb.z - ca.z);
            let cut = ca + (cb - ca) * s;
            if ca.z < NEAR {
                ca = cut;
            } else {
                cb = cut;
            }
        }
        let k = &self.calibration.intrinsics;
        let (Some(pa), Some(pb)) = (k.project(&ca), k.project(&cb)) else { return };
        let size = (f64::from(self.image.width), f64::from(self.image.height));
        let Some((pa, pb)) = clip_to_frame(pa, pb, size) else { return };
        let steps = (pb - pa).abs().max().ceil() as usize;
        for i in 0..=steps {
            let q = pa + (pb - pa) * (i as f64 / steps.max(1) as f64);
            self.paint(q.x.floor() as i64, q.y.floor() as i64, colour);
        }
    }

    /// The twelve edges of a box given by its corners in `pose`'s frame.
    fn cuboid(&mut self, pose: &Isometry3<f64>, lo: [f64; 3], hi: [f64; 3]) {
        let corner = |i: usize| {
            pose * Point3::new(
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            )
        };
        for i in 0..8 {
            for bit in [1, 2, 4] {
                if i & bit == 0 {
                    self.line(&corner(i), &corner(i | bit), YELLOW_GREEN);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_cut_at_the_frame() {
        let frame = (100.0, 50.0);
        let (a, b) = clip_to_frame(Point2::new(-100.0, 25.0), Point2::new(300.0, 25.0), frame)
            .expect("it crosses the frame");
        assert_eq!((a.x, b.x), (0.0, 100.0));
        let inside = (Point2::new(10.0, 10.0), Point2::new(20.0, 30.0));
        assert_eq!(clip_to_frame(inside.0, inside.1, frame), Some(inside));
        assert_eq!(clip_to_frame(Point2::new(-5.0, -5.0), Point2::new(-1.0, 60.0), frame), None);
        let (a, b) = clip_to_frame(Point2::new(50.0, 25.0), Point2::new(50.0, 1e9), frame).unwrap();
        assert_eq!((a.y, b.y), (25.0, 50.0), "a nearly endless line ends at the edge");
    }
}
