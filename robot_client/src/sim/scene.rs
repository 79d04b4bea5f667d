//! The simulated world's geometry and materials, and ray casting against them with parry.

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use parry3d::query::Ray;
use parry3d::shape::{CompositeShapeRef, Compound, SharedShape};

use super::noise::wood_grain;

/// The light sources a surface can belong to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightSource {
    Ceiling,
    Lamp,
}

/// What a surface looks like to the camera and the laser.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// A flat colour: linear-light reflectance per channel, 0..1.
    Matte([f32; 3]),
    /// Reddish-brown wood: hue drifts toward red along dark grain lines.
    Wood,
    /// Orange-brown plywood as a real capture measured it (issue 34: hue 14–24°, saturation
    /// 0.45–0.86, value 0.3–0.6): its darker grain passes the factory's red thresholds.
    Plywood,
    /// A lamp shade or light fixture: matte, and glowing while its light is on.
    Glowing { reflectance: [f32; 3], source: LightSource, radiance: f32 },
    /// Lacquer or glazed tile: a matte colour under a clear coat that mirrors the flash back
    /// where it faces the camera; `shine` is the highlight's peak relative to a white surface.
    Glossy { reflectance: [f32; 3], shine: f32 },
}

/// One solid of the scene.
#[derive(Debug, Clone)]
pub struct Part {
    pub name: &'static str,
    pub shape: SharedShape,
    pub pose: Isometry3<f32>,
    pub surface: Surface,
}

/// Where a ray met the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub distance: f32,
    pub point: Point3<f32>,
    /// Unit normal of the surface, facing the ray's origin.
    pub normal: Vector3<f32>,
    /// Index of the part hit.
    pub part: usize,
}

/// All solids of the world, in one parry compound for ray casting through its BVH.
#[derive(Clone)]
pub struct Scene {
    parts: Vec<Part>,
    compound: Compound,
}

impl std::fmt::Debug for Scene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Scene({} parts)", self.parts.len())
    }
}

impl Scene {
    pub fn new(parts: Vec<Part>) -> Self {
        let compound = Compound::new(parts.iter().map(|p| (p.pose, p.shape.clone())).collect());
        Self { parts, compound }
    }

    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// The nearest surface along the ray from `origin` in unit direction `dir`, within `max`.
    pub fn cast(&self, origin: &Point3<f32>, dir: &Vector3<f32>, max: f32) -> Option<Hit> {
        let ray = Ray::new(*origin, *dir);
        let (part, hit) =
            CompositeShapeRef(&self.compound).cast_local_ray_and_get_normal(&ray, max, true)?;
        let normal = if hit.normal.dot(dir) > 0.0 { -hit.normal } else { hit.normal };
        Some(Hit {
            distance: hit.time_of_impact,
            point: ray.point_at(hit.time_of_impact),
            normal,
            part: part as usize,
        })
    }

    /// Whether `p` is inside any solid, and how deep, with the direction out: for the fingers'
    /// contact forces.
    pub fn penetration(&self, p: &Point3<f32>) -> Option<(f32, Vector3<f32>)> {
        self.penetration_of(p, |_| true)
    }

    /// Moves parts to new poses (a drawer sliding, a lever flipping) and rebuilds the ray-casting
    /// tree; parts already where they are asked to be cost nothing.
    pub fn move_parts(&mut self, poses: &[(usize, Isometry3<f32>)]) {
        let mut changed = false;
        for (index, pose) in poses {
            let part = &mut self.parts[*index];
            if part.pose != *pose {
                part.pose = *pose;
                changed = true;
            }
        }
        if changed {
            self.compound =
                Compound::new(self.parts.iter().map(|p| (p.pose, p.shape.clone())).collect());
        }
    }

    /// Like [`Scene::penetration`], over the parts `include` accepts.
    pub fn penetration_of(
        &self,
        p: &Point3<f32>,
        include: impl Fn(&Part) -> bool,
    ) -> Option<(f32, Vector3<f32>)> {
        let mut deepest: Option<(f32, Vector3<f32>)> = None;
        for part in self.parts.iter().filter(|part| include(part)) {
            if !part.shape.contains_point(&part.pose, p) {
                continue;
            }
            let boundary = part.shape.project_point(&part.pose, p, false).point;
            let out = boundary - p;
            let depth = out.norm();
            if deepest.is_none_or(|(d, _)| depth > d) {
                deepest = Some((depth, out.try_normalize(1e-9).unwrap_or(Vector3::z())));
            }
        }
        deepest
    }

    /// Linear-light reflectance of the surface at a hit point.
    pub fn reflectance(&self, hit: &Hit) -> [f32; 3] {
        match self.parts[hit.part].surface {
            Surface::Matte(rgb)
            | Surface::Glowing { reflectance: rgb, .. }
            | Surface::Glossy { reflectance: rgb, .. } => rgb,
            Surface::Wood => {
                let g = wood_grain(hit.point.x, hit.point.y, hit.point.z);
                // Defined in the camera's sRGB HSV, where the tag thresholds live: hue 28° down
                // to 21° on the darkest grain, just above the red bound of 20°.
                srgb_hsv_to_linear(28.0 - 7.0 * g, 0.62 + 0.06 * g, 0.58 - 0.12 * g)
            }
            Surface::Plywood => {
                let g = wood_grain(hit.point.x, hit.point.y, hit.point.z);
                // Hue 24° down to 14° and saturation 0.62 up to 0.82 on the darkest grain:
                // the grain lines lie inside the factory's 340..20°, saturation ≥ 0.6.
                srgb_hsv_to_linear(24.0 - 10.0 * g, 0.62 + 0.2 * g, 0.55 - 0.2 * g)
            }
        }
    }
}

/// Linear reflectance of a colour given as sRGB hue (degrees), saturation and value.
pub fn srgb_hsv_to_linear(h: f32, s: f32, v: f32) -> [f32; 3] {
    hsv_to_srgb(h, s, v).map(srgb_to_linear)
}

/// sRGB channels (0..1) of a colour given as hue (degrees), saturation and value.
pub fn hsv_to_srgb(h: f32, s: f32, v: f32) -> [f32; 3] {
    let c = v * s;
    let hp = h.rem_euclid(360.0) / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r + m, g + m, b + m]
}

pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// Builds parts in a frame on a wall: `along` the wall, `out` of it into the room, and up.
#[derive(Debug, Clone, Copy)]
pub struct WallFrame {
    /// A point on the wall's surface at floor level, world frame.
    pub origin: Point3<f32>,
    /// Unit horizontal normal of the wall, into the room.
    pub out: Vector3<f32>,
}

impl WallFrame {
    pub fn along(&self) -> Vector3<f32> {
        Vector3::z().cross(&self.out)
    }

    /// The world point `along` metres along the wall, `out` metres into the room, `up` high.
    pub fn point(&self, along: f32, out: f32, up: f32) -> Point3<f32> {
        self.origin + self.along() * along + self.out * out + Vector3::z() * up
    }

    /// A box centred at (along, out, up) with half extents along those same axes.
    pub fn cuboid(
        &self,
        name: &'static str,
        center: [f32; 3],
        half: [f32; 3],
        surface: Surface,
    ) -> Part {
        // Local x is `out` and local y `along`, the order that makes the basis right-handed.
        let rotation =
            UnitQuaternion::from_basis_unchecked(&[self.out, self.along(), Vector3::z()]);
        Part {
            name,
            shape: SharedShape::cuboid(half[1], half[0], half[2]),
            pose: Isometry3::from_parts(
                self.point(center[0], center[1], center[2]).coords.into(),
                rotation,
            ),
            surface,
        }
    }

    /// A cylinder centred at (along, out, up) whose axis is `axis` in (along, out, up) terms.
    pub fn cylinder(
        &self,
        name: &'static str,
        center: [f32; 3],
        axis: [f32; 3],
        half_height: f32,
        radius: f32,
        surface: Surface,
    ) -> Part {
        let axis_world =
            (self.along() * axis[0] + self.out * axis[1] + Vector3::z() * axis[2]).normalize();
        // parry's cylinders run along their local y axis.
        let rotation =
            UnitQuaternion::rotation_between(&Vector3::y(), &axis_world).unwrap_or_else(|| {
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f32::consts::PI)
            });
        Part {
            name,
            shape: SharedShape::cylinder(half_height, radius),
            pose: Isometry3::from_parts(
                self.point(center[0], center[1], center[2]).coords.into(),
                rotation,
            ),
            surface,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_hit_the_nearest_part_with_its_normal() {
        let wall = WallFrame { origin: Point3::new(3.0, 0.0, 0.0), out: -Vector3::x() };
        let scene = Scene::new(vec![
            wall.cuboid("wall", [0.0, -0.05, 1.0], [2.0, 0.05, 1.0], Surface::Matte([0.7; 3])),
            wall.cuboid(
                "patch",
                [0.0, 0.002, 1.0],
                [0.05, 0.002, 0.05],
                Surface::Matte([0.5, 0.02, 0.02]),
            ),
        ]);
        let hit = scene.cast(&Point3::new(0.0, 0.0, 1.0), &Vector3::x(), 10.0).unwrap();
        assert_eq!(scene.parts()[hit.part].name, "patch");
        assert!((hit.distance - 2.996).abs() < 1e-4);
        assert!((hit.normal - -Vector3::x()).norm() < 1e-5);
        let beside = scene.cast(&Point3::new(0.0, 0.5, 1.0), &Vector3::x(), 10.0).unwrap();
        assert_eq!(scene.parts()[beside.part].name, "wall");
        assert!(scene.cast(&Point3::new(0.0, 0.0, 1.0), &-Vector3::x(), 10.0).is_none());
        let (depth, out) = scene.penetration(&Point3::new(3.01, 0.5, 1.0)).unwrap();
        assert!((depth - 0.01).abs() < 1e-4 && out.x < -0.99);
    }

    #[test]
    fn hsv_colours_survive_the_round_trip() {
        let red = srgb_hsv_to_linear(0.0, 0.8, 0.8).map(linear_to_srgb);
        assert!((red[0] - 0.8).abs() < 1e-4 && (red[1] - 0.16).abs() < 1e-4);
    }
}
