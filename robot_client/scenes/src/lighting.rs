//! The lights of a scene and how a surface point is shaded by them: an ambient term, the room's
//! ceiling lights and the camera's flash, each a point source falling off with the square of the
//! distance, Lambertian plus a Blinn–Phong highlight on shiny materials.
//!
//! No shadows: the flash sits beside the lens, so the shadows it casts are hidden behind what
//! casts them, and the room's light is broad enough that its shadows would be soft and faint.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::materials::Material;

/// Bright daytime light, or a dim evening lit mostly by the flash and one warm lamp.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Lighting {
    Bright,
    Dim,
}

/// A point source: where it is (base frame, metres) and its linear RGB irradiance on a surface
/// facing it 1 m away.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PointLight {
    pub position: [f64; 3],
    pub intensity: [f64; 3],
}

/// The scene's lights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lights {
    /// Irradiance reaching every surface from all around, linear RGB.
    pub ambient: [f64; 3],
    /// Ceiling lights.
    pub room: Vec<PointLight>,
    /// The camera's flash, fired for the picture perception uses (paper §III-B).
    pub flash: Option<PointLight>,
}

impl Lights {
    /// Linear RGB radiance leaving `point` toward the viewer: `normal` is the surface's unit
    /// normal on the viewer's side, `to_viewer` the unit direction to the viewer.
    pub fn shade(
        &self,
        point: &Point3<f64>,
        normal: &Vector3<f64>,
        to_viewer: &Vector3<f64>,
        material: &Material,
    ) -> [f64; 3] {
        let a = material.albedo;
        let mut out = [a[0] * self.ambient[0], a[1] * self.ambient[1], a[2] * self.ambient[2]];
        for light in self.room.iter().chain(&self.flash) {
            let to_light = Point3::from(light.position) - point;
            let d2 = to_light.norm_squared().max(1e-4);
            let l = to_light / d2.sqrt();
            let cos = normal.dot(&l);
            if cos <= 0.0 {
                continue;
            }
            let mut reflect = [a[0] * cos, a[1] * cos, a[2] * cos];
            if material.specular > 0.0 {
                let h = (l + to_viewer).normalize();
                // An integer exponent: powi is a few multiplications, powf a logarithm and an exp.
                let highlight =
                    material.specular * normal.dot(&h).max(0.0).powi(material.shininess as i32);
                reflect = reflect.map(|c| c + highlight);
            }
            for c in 0..3 {
                out[c] += reflect[c] * light.intensity[c] / d2;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::RED_FOAM;

    #[test]
    fn the_flash_falls_off_with_the_square_of_the_distance() {
        let lights = Lights {
            ambient: [0.0; 3],
            room: vec![],
            flash: Some(PointLight { position: [0.0, 0.0, 0.0], intensity: [1.0; 3] }),
        };
        let n = Vector3::new(-1.0, 0.0, 0.0);
        let at = |d: f64| lights.shade(&Point3::new(d, 0.0, 0.0), &n, &n, &RED_FOAM)[0];
        assert!((at(1.0) - 0.5).abs() < 1e-12);
        assert!((at(2.0) - 0.125).abs() < 1e-12);
        // Tilted 60° away from the flash: half the light.
        let tilted = Vector3::new(-0.5, 3f64.sqrt() / 2.0, 0.0);
        let lit = lights.shade(&Point3::new(1.0, 0.0, 0.0), &tilted, &n, &RED_FOAM)[0];
        assert!((lit - 0.25).abs() < 1e-12);
        // From behind, only the ambient (here none).
        assert_eq!(lights.shade(&Point3::new(1.0, 0.0, 0.0), &-n, &n, &RED_FOAM)[0], 0.0);
    }
}
