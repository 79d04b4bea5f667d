//! Drawing a scene from a seed, across the whole space issue 11 names: the five devices; the
//! backing surface seen up to 75° either side at 0.8–1.6 m; fronts 0.35–1.2 m wide with the
//! towel covering up to half of one and standing 0–3 cm proud; the camera 0.8–1.4 m high pitched
//! 20–45° down; bright and dim light; red things that are not the tag near it; side walls,
//! neighbouring cabinets and things on the floor; the person's pointing error up to 5 cm.
//!
//! Sampling happens in the device frame of [`crate::devices`]; one rigid motion then puts the
//! device, its room and the clutter in front of the robot, whose base frame is the scene's.
//! [`crate::rig`] draws the sensors and lights, [`crate::furnishing`] the clutter.
//!
//! Longer than most files because a scene is drawn in one order, each draw from the one seeded
//! stream: split, the order (and with it every scene of the corpus) would be easy to change by
//! accident.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::camera::CameraModel;
use crate::clutter::{Clutter, Distractor, Room};
use crate::devices::{self, Device, DeviceKind, DeviceParameters};
use crate::draw::Draw;
use crate::furnishing::draw_clutter;
use crate::home_materials::Illuminant;
use crate::laser::LaserModel;
use crate::lighting::Lighting;
use crate::materials;
use crate::rgbd::{self, RgbdParameters, RgbdVariants};
use crate::rig::{draw_laser, draw_lights, optical_pose};
use crate::scene::{Pose, Scene};
use crate::truth::Truth;

/// Image sizes a scene may have.
const IMAGE_SIZES: [[u32; 2]; 5] = [[640, 480], [800, 600], [960, 720], [1024, 768], [1280, 960]];
/// The tag's centre stays within this fraction of the half field of view from the image centre.
const TAG_IN_VIEW: f64 = 0.7;

/// Everything a scene was drawn with, for reproducing and printing a miss.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneParameters {
    pub seed: u64,
    pub kind: DeviceKind,
    /// Draws discarded because the tag was not in plain sight of both sensors.
    pub redraws: u32,
    pub device: DeviceParameters,
    /// Horizontal distance from the camera to the tag, metres.
    pub distance_m: f64,
    /// Angle from the backing surface's normal to the direction of the camera, degrees.
    pub view_angle_deg: f64,
    /// The tag's bearing off the camera's axis, degrees.
    pub bearing_deg: f64,
    pub camera_height_m: f64,
    pub camera_pitch_deg: f64,
    pub image_size: [u32; 2],
    pub horizontal_fov_deg: f64,
    /// From the camera to the laser's head, base frame, metres.
    pub laser_offset_m: [f64; 3],
    pub beam_step_deg: f64,
    pub tilt_step_deg: f64,
    pub lighting: Lighting,
    pub clutter: Vec<Clutter>,
    pub distractor: Option<Distractor>,
    /// The person's pointing error: target minus the tag's centre, metres.
    pub pointing_error_m: [f64; 3],
    /// Seen by an RGB-D camera instead of the flash camera and the laser.
    #[serde(default)]
    pub rgbd: Option<RgbdParameters>,
}

impl SceneParameters {
    /// The parameters in a line.
    pub fn summary(&self) -> String {
        let mut parts = vec![
            self.device.summary(),
            format!(
                "{:.2} m at {:+.0}°, camera {:.2} m pitched {:.0}°, {}×{}",
                self.distance_m,
                self.view_angle_deg,
                self.camera_height_m,
                self.camera_pitch_deg,
                self.image_size[0],
                self.image_size[1]
            ),
            format!(
                "laser {:.0} cm off, {:.2}°×{:.2}°",
                Vector3::from(self.laser_offset_m).norm() * 100.0,
                self.beam_step_deg,
                self.tilt_step_deg
            ),
            match self.lighting {
                Lighting::Bright => "bright".to_string(),
                Lighting::Dim => "dim".to_string(),
            },
        ];
        if let Some(d) = &self.distractor {
            parts.push(
                format!("red {:?} {:.0} cm from the tag", d.kind, d.gap_m * 100.0).to_lowercase(),
            );
        }
        if let Some(r) = &self.rgbd {
            parts.push(format!(
                "{:?} depth, {} K light {:.0} % corrected",
                r.sensor.technique,
                r.illuminant_k,
                r.white_balance_correction * 100.0
            ));
            if let Some(wood) = &r.wood {
                let wall = if r.wooden_wall { " and wall" } else { "" };
                parts.push(format!("furniture{wall} of {wood}"));
            }
            if let Some(t) = &r.red_touching {
                parts.push(format!(
                    "{} {:.0}×{:.0} cm {} the tag",
                    t.material,
                    t.size_m[1] * 100.0,
                    t.size_m[2] * 100.0,
                    if t.overlap_m > 0.0 { "overlapping" } else { "touching" }
                ));
            }
        }
        let clutter: Vec<&str> = self.clutter.iter().map(Clutter::name).collect();
        if !clutter.is_empty() {
            parts.push(clutter.join(", "));
        }
        parts.join("; ")
    }
}

/// A scene drawn but not yet rendered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DrawnScene {
    pub parameters: SceneParameters,
    pub scene: Scene,
    pub camera: CameraModel,
    pub laser: LaserModel,
    pub truth: Truth,
    /// The person's designated point, base frame, metres.
    pub target: [f64; 3],
}

/// The kind a seed gives when none is asked for.
pub fn kind_of_seed(seed: u64) -> DeviceKind {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    DeviceKind::ALL[rng.random_range(0..DeviceKind::ALL.len())]
}

/// Draws scene `seed` of `kind` (of the seed's own kind when `None`); `redraw` counts the draws
/// of the same seed already discarded.
pub fn draw(seed: u64, kind: Option<DeviceKind>, redraw: u32) -> DrawnScene {
    draw_for(seed, kind, redraw, None)
}

/// Draws scene `seed` of `kind` as an RGB-D camera sees it, with the variants allowed.
pub fn draw_rgbd(
    seed: u64,
    kind: Option<DeviceKind>,
    redraw: u32,
    variants: RgbdVariants,
) -> DrawnScene {
    draw_for(seed, kind, redraw, Some(variants))
}

fn draw_for(
    seed: u64,
    kind: Option<DeviceKind>,
    redraw: u32,
    rgbd: Option<RgbdVariants>,
) -> DrawnScene {
    let kind = kind.unwrap_or_else(|| kind_of_seed(seed));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let kind_index = DeviceKind::ALL.iter().position(|k| *k == kind).unwrap_or(0) as u64;
    // RGB-D scenes take streams of their own: seed 3 of the drawers is another drawer there.
    let apart = if rgbd.is_some() { 1 << 32 } else { 0 };
    rng.set_stream(apart + 1 + kind_index + 8 * u64::from(redraw));
    let mut d = Draw { rng };
    let parameters = draw_device(kind, &mut d);
    let device = devices::build(&parameters, &mut d.rng);
    place(seed, redraw, parameters, device, &mut d, rgbd)
}

fn draw_device(kind: DeviceKind, d: &mut Draw) -> DeviceParameters {
    match kind {
        DeviceKind::FlipSwitch => DeviceParameters::FlipSwitch(devices::FlipSwitch {
            plate_height_m: d.u(0.95, 1.25),
            toggle_up: d.chance(0.5),
            tube_radius_m: d.u(0.011, 0.016),
            tube_length_m: d.u(0.035, 0.05),
        }),
        DeviceKind::Rocker => DeviceParameters::Rocker(devices::Rocker {
            plate_height_m: d.u(0.95, 1.25),
            rocker_up: d.chance(0.5),
            patch_width_m: d.u(0.04, 0.07),
            patch_height_m: d.u(0.07, 0.11),
            patch_thickness_m: d.u(0.002, 0.004),
        }),
        DeviceKind::Lamp => {
            let tube_length_m = d.u(0.08, 0.15);
            let tube_height_m = d.u(0.95, 1.25);
            let wall_gap_m = d.u(0.15, 0.35);
            let pole_dx = d.u((0.09 - wall_gap_m).max(-0.06), 0.06);
            let pole_dy = d.sign() * d.u(0.03, 0.07);
            DeviceParameters::Lamp(devices::Lamp {
                tube_height_m,
                tube_radius_m: d.u(0.012, 0.018),
                tube_length_m,
                wall_gap_m,
                pole_offset_m: [pole_dx, pole_dy],
                shade_bottom_m: (tube_height_m + tube_length_m / 2.0 + d.u(0.08, 0.3))
                    .clamp(1.3, 1.7),
                shade_radius_m: d.u(0.15, 0.24),
            })
        }
        DeviceKind::Drawer => {
            let front_width_m = d.u(0.35, 1.2);
            let cabinet_height_m = d.u(0.5, 1.0);
            let max_drawers = ((cabinet_height_m - 0.08) / 0.14).floor().clamp(2.0, 4.0) as u32;
            let drawers = d.rng.random_range(2..=max_drawers);
            let towel_width_m =
                (front_width_m * d.u(0.2, 0.5)).clamp(0.12, 0.6).min(front_width_m / 2.0);
            let slack = (front_width_m - towel_width_m) / 2.0 - 0.03;
            DeviceParameters::Drawer(devices::Drawer {
                front_width_m,
                cabinet_height_m,
                cabinet_depth_m: d.u(0.35, 0.6),
                drawers,
                tag_drawer: d.rng.random_range(0..drawers),
                towel_width_m,
                towel_height_m: d.u(0.12, 0.35),
                towel_proud_m: d.u(0.0, 0.03),
                towel_thickness_m: d.u(0.004, 0.012),
                towel_offset_m: d.u(-slack.max(0.0), slack.max(0.0)),
                wall_gap_m: d.u(0.0, 0.03),
            })
        }
        DeviceKind::TrashCan => {
            let width_m = d.u(0.28, 0.5);
            let height_m = d.u(0.4, 0.75);
            let patch_width_m = d.u(0.10, (width_m - 0.04).min(0.25));
            let patch_height_m = d.u(0.08, (0.4 * height_m).min(0.2));
            let top_level = 1.0 - (patch_height_m / 2.0 + 0.03) / height_m;
            let slack = (width_m - patch_width_m) / 2.0 - 0.02;
            DeviceParameters::TrashCan(devices::TrashCan {
                width_m,
                depth_m: d.u(0.25, 0.4),
                height_m,
                patch_width_m,
                patch_height_m,
                patch_thickness_m: d.u(0.002, 0.008),
                patch_level: d.u(0.45, 0.75).min(top_level),
                patch_offset_m: d.u(-slack.max(0.0), slack.max(0.0)),
                wall_gap_m: d.u(0.01, 0.15),
            })
        }
    }
}

/// The camera and view drawn together, so that the tag is in the picture.
struct View {
    distance: f64,
    angle: f64,
    camera_height: f64,
    pitch: f64,
    size: [u32; 2],
    hfov: f64,
}

fn draw_view(device: &Device, d: &mut Draw, rgbd: Option<RgbdVariants>) -> View {
    let tag = device.tag_center;
    let (near, far, sizes, fov): (f64, f64, &[[u32; 2]], [f64; 2]) = match rgbd {
        // RGB-D colour cameras: 69° (D435) to 90° (Azure Kinect) wide.
        Some(v) => (0.5, v.farthest_m, &rgbd::IMAGE_SIZES, [64.0, 90.0]),
        None => (0.8, 1.6, &IMAGE_SIZES, [55.0, 75.0]),
    };
    loop {
        let distance = d.u(near, far);
        let angle = d.u(-75f64, 75.0).to_radians();
        // The camera stands at least 25 cm before the device and 35 cm before the wall.
        let ahead = tag.x + distance * angle.cos();
        if ahead < device.extent.max.x + 0.25 || ahead < device.wall_x + 0.35 {
            continue;
        }
        let size = sizes[d.rng.random_range(0..sizes.len())];
        let hfov = d.u(fov[0], fov[1]).to_radians();
        let half_vfov = ((hfov / 2.0).tan() * f64::from(size[1]) / f64::from(size[0])).atan();
        for _ in 0..20 {
            let camera_height = d.u(0.8, 1.4);
            let depression = (camera_height - tag.z).atan2(distance);
            let lo = (20f64.to_radians()).max(depression - TAG_IN_VIEW * half_vfov);
            let hi = (45f64.to_radians()).min(depression + TAG_IN_VIEW * half_vfov);
            if lo < hi {
                return View { distance, angle, camera_height, pitch: d.u(lo, hi), size, hfov };
            }
        }
    }
}

fn place(
    seed: u64,
    redraws: u32,
    device_parameters: DeviceParameters,
    device: Device,
    d: &mut Draw,
    rgbd: Option<RgbdVariants>,
) -> DrawnScene {
    let view = draw_view(&device, d, rgbd);
    let tag_d = device.tag_center;
    // The robot: camera yaw, the tag's bearing off it, and where the camera sits on the base.
    let camera_yaw = d.u(-3f64, 3.0).to_radians();
    let bearing = d.u(-8f64, 8.0).to_radians();
    let eye_h = Vector2::new(d.u(0.0, 0.15), d.u(-0.04, 0.04));
    let toward_tag = Vector2::new((camera_yaw + bearing).cos(), (camera_yaw + bearing).sin());
    let tag_h = eye_h + toward_tag * view.distance;
    let normal_h = nalgebra::Rotation2::new(-view.angle) * -toward_tag;
    let device_yaw = normal_h.y.atan2(normal_h.x);
    let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), device_yaw);
    let origin = tag_h - (turn * Vector3::new(tag_d.x, tag_d.y, 0.0)).xy();
    let base_from_device = Isometry3::from_parts(Translation3::new(origin.x, origin.y, 0.0), turn);
    // The camera in the device frame, for keeping clutter out of its way.
    let camera_d = Point3::new(
        tag_d.x + view.distance * view.angle.cos(),
        view.distance * view.angle.sin(),
        view.camera_height,
    );
    let camera_side =
        if view.angle.abs() < 15f64.to_radians() { d.sign() } else { view.angle.signum() };

    let eye = Point3::new(eye_h.x, eye_h.y, view.camera_height);
    let camera_pose = optical_pose(eye, camera_yaw, view.pitch, d.u(-1.5f64, 1.5).to_radians());
    let [w, h] = view.size;
    let fx = f64::from(w) / 2.0 / (view.hfov / 2.0).tan();
    let scale = f64::from(w) / 640.0;
    let mut camera = CameraModel {
        width: w,
        height: h,
        fx,
        fy: fx * d.u(0.995, 1.005),
        cx: f64::from(w) / 2.0 + d.u(-8.0, 8.0) * scale,
        cy: f64::from(h) / 2.0 + d.u(-8.0, 8.0) * scale,
        pose: Pose::from_isometry(&camera_pose),
        exposure_bias_ev: d.u(-0.5, 0.5),
        white_balance: [d.u(0.95, 1.05), 1.0, d.u(0.95, 1.05)],
        vignetting: d.u(0.2, 0.9),
        read_noise: d.u(0.0005, 0.002),
        shot_noise: d.u(0.0002, 0.001),
    };

    let tag_base = base_from_device * tag_d;
    let laser = draw_laser(d, &camera_pose, camera_yaw, &tag_base, w);
    let lighting = if d.chance(0.6) { Lighting::Bright } else { Lighting::Dim };
    // A room of 3.5–6 m by 2.4–8 m, with the robot well inside it.
    let room = Room {
        wall_x_m: device.wall_x,
        depth_m: d.u(3.5, 6.0).max(camera_d.x - device.wall_x + 1.0),
        y_m: [(-d.u(1.2, 4.0)).min(camera_d.y - 0.8), d.u(1.2, 4.0).max(camera_d.y + 0.8)],
        ceiling_m: d.u(2.35, 2.7),
        wall: materials::WALLS[d.rng.random_range(0..materials::WALLS.len())],
        floor: materials::FLOORS[d.rng.random_range(0..materials::FLOORS.len())],
    };
    let (clutter, distractor) =
        draw_clutter(&device_parameters, &device, &camera_d, camera_side, d);

    let mut primitives = room.primitives();
    primitives.extend(device.primitives.iter().cloned());
    for c in &clutter {
        primitives.extend(c.primitives(device.wall_x));
    }
    if let Some(x) = &distractor {
        primitives.extend(x.primitives());
    }
    let mut primitives: Vec<_> =
        primitives.iter().map(|p| p.transformed(&base_from_device)).collect();
    let mut lights = draw_lights(lighting, &room, &base_from_device, &camera_pose, d);

    let normal = Vector3::new(normal_h.x, normal_h.y, 0.0);
    // The device frame's x = 0 plane is the backing surface.
    let foot = base_from_device * Point3::new(0.0, 0.0, tag_d.z);
    let truth =
        Truth::new(device_parameters.kind(), tag_base, normal, foot).with_tag_size(device.tag_size);
    let error = loop {
        let e = Vector3::new(d.u(-1.0, 1.0), d.u(-1.0, 1.0), d.u(-1.0, 1.0));
        if e.norm() <= 1.0 {
            break e * 0.05;
        }
    };
    // What an RGB-D camera's scene has besides, drawn last so the laser corpus stays as it was.
    let rgbd = rgbd.map(|variants| {
        let sensor = rgbd::draw_sensor(d);
        let illuminant = Illuminant::ALL[d.rng.random_range(0..Illuminant::ALL.len())];
        let ceiling: Vec<[f64; 3]> = lights.room.iter().map(|l| l.position).collect();
        lights = rgbd::draw_lights(illuminant, &ceiling, d);
        let correction = d.u(0.5, 1.0);
        let balance = rgbd::white_balance(illuminant, correction);
        camera.white_balance =
            [0, 1, 2].map(|c| balance[c] * camera.white_balance[c] / camera.white_balance[1]);
        let (wood, wooden_wall) = if variants.wood && d.chance(0.6) {
            let (name, wall) = rgbd::make_wooden(&mut primitives, &room.wall, d);
            (Some(name), wall)
        } else {
            (None, false)
        };
        let red_touching = (variants.red_touching && d.chance(0.5)).then(|| {
            let (described, primitive) = rgbd::red_touching(&device, d);
            primitives.push(primitive.transformed(&base_from_device));
            described
        });
        RgbdParameters {
            sensor,
            illuminant_k: illuminant.kelvin(),
            white_balance_correction: correction,
            wood,
            wooden_wall,
            red_touching,
        }
    });
    let parameters = SceneParameters {
        seed,
        kind: device_parameters.kind(),
        redraws,
        device: device_parameters,
        distance_m: view.distance,
        view_angle_deg: view.angle.to_degrees(),
        bearing_deg: bearing.to_degrees(),
        camera_height_m: view.camera_height,
        camera_pitch_deg: view.pitch.to_degrees(),
        image_size: view.size,
        horizontal_fov_deg: view.hfov.to_degrees(),
        laser_offset_m: (laser.head.isometry().translation.vector - eye.coords).into(),
        beam_step_deg: laser.beam_step_deg,
        tilt_step_deg: laser.tilt_step_deg,
        lighting,
        clutter,
        distractor,
        pointing_error_m: error.into(),
        rgbd,
    };
    DrawnScene {
        parameters,
        scene: Scene { primitives, lights },
        camera,
        laser,
        truth,
        target: (tag_base + error).coords.into(),
    }
}
