//! An independent scene source for the robot's perception: scenes we did not tune it to.
//!
//! The robot's perception was measured only against the simulator's own renderer, and it
//! failed on the first scenes rendered by anything else (issue 11). This crate is that anything
//! else, kept deliberately unlike `pps_robot::sim`: scenes are data (boxes, rectangles,
//! cylinders and a cone frustum with materials, see [`scene`]), cast by its own analytic ray
//! caster ([`geometry`], [`caster`]), seen by its own camera model ([`camera`]: flash with
//! inverse-square fall-off, highlights, vignetting, white balance, metered exposure, shot noise,
//! sRGB) and its own laser ([`laser`]: a tilting scanner mounted apart from the camera, range
//! noise growing with range and incidence, dropouts, mixed pixels at depth edges, servo
//! jitter). [`corpus`] draws scenes from seeds across the space the issue names, each with its
//! [`truth`].
//!
//! It must never borrow the simulator's rendering, noise or room, nor be tuned until perception
//! passes: it only uses the robot's data types, its file writers and the approach under test.

pub mod camera;
pub mod caster;
pub mod clutter;
pub mod corpus;
pub mod depth_sensor;
pub mod devices;
mod draw;
pub mod furnishing;
pub mod geometry;
pub mod home_materials;
pub mod laser;
pub mod lighting;
pub mod materials;
pub mod noise;
pub mod rgbd;
pub mod rig;
pub mod scene;
pub mod sensitivity;
pub mod touching;
pub mod truth;

use std::time::Instant;

use nalgebra::{Point3, Vector3};
use pps_robot::hal::{CameraCalibration, ColorImage, PointCloud};
use pps_robot::perception::{DepthImage, DepthNoise, DepthRange, cloud_from_depth};
use serde::Serialize;

pub use corpus::{DrawnScene, SceneParameters, draw, draw_rgbd};
pub use devices::DeviceKind;
pub use rgbd::RgbdVariants;
pub use truth::{Truth, Verdict, judge};

use caster::RayCaster;
use noise::NoiseSource;

/// Fewest laser returns on the tag, and pixels of it, for the tag to count as in plain sight; a
/// draw with fewer is redrawn, since no method could place a tag the sensors barely saw.
pub const MIN_TAG_POINTS: usize = 30;
pub const MIN_TAG_PIXELS: usize = 120;
/// Redraws before a seed gives up on plain sight and keeps its last draw.
const MAX_REDRAWS: u32 = 20;

/// How well the sensors saw what matters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Visibility {
    pub tag_pixels: usize,
    pub tag_points: usize,
    /// Laser points within 1.5 cm of the true backing surface's plane and 0.5 m of the tag.
    pub backing_points: usize,
    pub cloud_points: usize,
    /// Centroid of the laser returns on the tag (mixed pixels at its edges included), base
    /// frame: what a perfect segmentation would report.
    pub tag_points_centroid: Option<[f64; 3]>,
}

/// A scene drawn and rendered: what perception gets, and what is true.
#[derive(Debug, Clone)]
pub struct GeneratedScene {
    pub drawn: DrawnScene,
    pub image: ColorImage,
    pub cloud: PointCloud,
    /// The RGB-D camera's depth image in millimetres (0: none), aligned to `image`, row by row,
    /// when an RGB-D camera saw the scene; `cloud` is then this depth's dense cloud.
    pub depth_mm: Option<Vec<u16>>,
    /// Exactly the calibration the image was rendered with.
    pub calibration: CameraCalibration,
    pub target: Point3<f64>,
    pub visibility: Visibility,
    /// Wall-clock time spent rendering the image and sweeping the laser, milliseconds.
    pub render_ms: f64,
}

impl GeneratedScene {
    pub fn truth(&self) -> &Truth {
        &self.drawn.truth
    }

    pub fn parameters(&self) -> &SceneParameters {
        &self.drawn.parameters
    }

    /// How the range sensor that saw the scene scatters its depths: the RGB-D camera's model,
    /// or the laser's.
    pub fn depth_noise(&self) -> DepthNoise {
        self.parameters().rgbd.as_ref().map_or(DepthNoise::LASER, |r| r.sensor.noise())
    }

    /// The depth image as perception reads it, when an RGB-D camera saw the scene.
    pub fn depth_image(&self) -> Option<DepthImage> {
        let mm = self.depth_mm.as_ref()?;
        Some(depth_sensor::depth_image(self.image.width, self.image.height, mm))
    }
}

/// Scene `seed` of the corpus, of the device kind the seed gives.
pub fn corpus(seed: u64) -> GeneratedScene {
    generate(seed, None)
}

/// Scene `seed` of `kind` (the seed's own kind when `None`), rendered.
pub fn generate(seed: u64, kind: Option<DeviceKind>) -> GeneratedScene {
    generate_with(seed, kind, None)
}

/// Scene `seed` of `kind` as an RGB-D camera sees it, with the variants allowed, rendered.
pub fn generate_rgbd(
    seed: u64,
    kind: Option<DeviceKind>,
    variants: RgbdVariants,
) -> GeneratedScene {
    generate_with(seed, kind, Some(variants))
}

fn generate_with(
    seed: u64,
    kind: Option<DeviceKind>,
    rgbd: Option<RgbdVariants>,
) -> GeneratedScene {
    let mut redraw = 0;
    loop {
        let drawn = match rgbd {
            None => draw(seed, kind, redraw),
            Some(variants) => draw_rgbd(seed, kind, redraw, variants),
        };
        let scene = render(drawn);
        let v = scene.visibility;
        let in_sight = v.tag_points >= MIN_TAG_POINTS && v.tag_pixels >= MIN_TAG_PIXELS;
        if in_sight || redraw >= MAX_REDRAWS {
            return scene;
        }
        redraw += 1;
    }
}

/// A cloud and, point by point, the primitive each came from.
struct Sensed {
    cloud: PointCloud,
    sources: Vec<u32>,
    depth_mm: Option<Vec<u16>>,
}

/// Renders a drawn scene: the camera's picture with the flash and the laser's sweep, or the
/// RGB-D camera's picture and depth.
pub fn render(drawn: DrawnScene) -> GeneratedScene {
    let start = Instant::now();
    let caster = RayCaster::new(&drawn.scene);
    let seed = drawn.parameters.seed ^ (u64::from(drawn.parameters.redraws) << 40);
    let mut camera_noise = NoiseSource::new(seed, 11);
    let (picture, sensed) = match &drawn.parameters.rgbd {
        None => {
            let picture = drawn.camera.render(&drawn.scene, &caster, &mut camera_noise);
            let sweep = drawn.laser.scan(&caster, &mut NoiseSource::new(seed, 12));
            (picture, Sensed { cloud: sweep.cloud, sources: sweep.sources, depth_mm: None })
        }
        Some(rgbd) => {
            let picture =
                drawn.camera.render_with_surfaces(&drawn.scene, &caster, &mut camera_noise);
            let sensed = sense_depth(&drawn, &rgbd.sensor, &picture.surfaces, &caster, seed);
            (picture, sensed)
        }
    };
    let render_ms = start.elapsed().as_secs_f64() * 1e3;
    let sweep = sensed;
    let on_tag: Vec<Point3<f64>> = sweep
        .cloud
        .points
        .iter()
        .zip(&sweep.sources)
        .filter(|(_, i)| caster.material(**i).is_tag)
        .map(|(p, _)| p.cast())
        .collect();
    let tag_points = on_tag.len();
    let tag_points_centroid = (!on_tag.is_empty()).then(|| {
        (on_tag.iter().map(|p| p.coords).sum::<Vector3<f64>>() / tag_points as f64).into()
    });
    let tag = Point3::from(drawn.truth.tag_center);
    let normal = Vector3::from(drawn.truth.backing_normal);
    let foot = Point3::from(drawn.truth.backing_foot);
    let backing_points = sweep
        .cloud
        .points
        .iter()
        .zip(&sweep.sources)
        .filter(|(p, i)| {
            let p: Point3<f64> = p.cast();
            !caster.material(**i).is_tag
                && (p - foot).dot(&normal).abs() < 0.015
                && (p - tag).xy().norm() < 0.5
        })
        .count();
    GeneratedScene {
        image: picture.image,
        calibration: drawn.camera.calibration(),
        target: Point3::from(drawn.target),
        visibility: Visibility {
            tag_pixels: picture.tag_pixels,
            tag_points,
            backing_points,
            cloud_points: sweep.cloud.len(),
            tag_points_centroid,
        },
        cloud: sweep.cloud,
        depth_mm: sweep.depth_mm,
        drawn,
        render_ms,
    }
}

/// The RGB-D camera's depth of the surfaces its colour pixels saw, the dense cloud the robot
/// makes of it, and each point's primitive.
fn sense_depth(
    drawn: &DrawnScene,
    sensor: &depth_sensor::DepthSensorModel,
    surfaces: &[Option<camera::PixelSurface>],
    caster: &RayCaster,
    seed: u64,
) -> Sensed {
    let (w, h) = (drawn.camera.width, drawn.camera.height);
    let millimetres = sensor.measure(
        surfaces,
        w as usize,
        drawn.camera.fx,
        caster,
        &mut NoiseSource::new(seed, 13),
    );
    let depth = depth_sensor::depth_image(w, h, &millimetres);
    let range = DepthRange::default();
    let cloud = cloud_from_depth(&depth, &drawn.camera.calibration(), &range)
        .expect("the depth is the colour image's size");
    // The conversion keeps a pixel exactly when its depth is in range, in pixel order.
    let sources = millimetres
        .iter()
        .zip(surfaces)
        .filter(|(mm, _)| {
            let z = f32::from(**mm) * 1e-3;
            z >= range.near && z <= range.far
        })
        .map(|(_, s)| s.map_or(u32::MAX, |s| s.primitive))
        .collect::<Vec<_>>();
    debug_assert_eq!(sources.len(), cloud.len());
    Sensed { cloud, sources, depth_mm: Some(millimetres) }
}
