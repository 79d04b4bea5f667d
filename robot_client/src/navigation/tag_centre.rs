//! The tag's centre on its backing surface.
//!
//! The mean of a tag's laser points is where the laser looked most, not where the tag is: seen
//! at a steep angle, a towel's near half gathers more points than its far half, and the mean
//! slides several centimetres toward the robot. On the backing plane the tag's extent is known
//! from its outline, however unevenly it was sampled: the centre is the middle of that outline
//! (trimmed of stray points at its edges), at the median height of the points above the plane.
//!
//! A depth camera's points are exact in direction and rough in depth: at 4 m and 70° from the
//! surface's normal, 6 cm of depth noise moves a point 5 cm across the surface. When the
//! depth noise is larger than the tag's face is deep, each point is taken where its ray meets
//! the tag's median height instead, so only its direction places it.

use nalgebra::{Point3, Vector3};

use super::backing_plane::BackingPlane;

/// Share of points trimmed off each end of the tag's extent, for edge noise.
const TRIM: f64 = 0.01;
/// Points further than this above or below the tag's median height (metres) are not its face:
/// mixed returns between a thin tag and the wall behind it trail off toward the wall.
pub(super) const FACE_DEPTH: f64 = 0.03;

/// The centre of `members` (a tag's points, base frame) as its outline on `plane` gives it;
/// `None` for fewer than three points. `rays_from` is the camera's position when the points'
/// depths are rougher than the tag's face is deep, `None` when they are not.
pub fn tag_centre_on(
    members: &[Point3<f32>],
    plane: &BackingPlane,
    rays_from: Option<&Point3<f64>>,
) -> Option<Point3<f64>> {
    if members.len() < 3 {
        return None;
    }
    let n = plane.normal;
    let across = n.cross(&Vector3::z());
    let u = across.try_normalize(1e-6).unwrap_or(Vector3::x());
    let v = n.cross(&u);
    let median = |mut values: Vec<f64>| {
        let half = values.len() / 2;
        *values.select_nth_unstable_by(half, f64::total_cmp).1
    };
    let along = |axis: &Vector3<f64>, p: &Point3<f32>| axis.dot(&p.cast::<f64>().coords);
    let cn = median(members.iter().map(|p| along(&n, p)).collect());
    let face: Vec<Point3<f32>> = match rays_from {
        // Where each ray meets the plane at the median height: n·(c + s(p − c)) = cn.
        Some(camera) => members
            .iter()
            .filter_map(|p| {
                let ray = p.cast::<f64>() - camera;
                let toward = n.dot(&ray);
                (toward.abs() > 1e-9)
                    .then(|| (camera + ray * ((cn - n.dot(&camera.coords)) / toward)).cast())
            })
            .collect(),
        None => {
            members.iter().filter(|p| (along(&n, p) - cn).abs() <= FACE_DEPTH).copied().collect()
        }
    };
    if face.is_empty() {
        return None;
    }
    let coordinates =
        |axis: &Vector3<f64>| -> Vec<f64> { face.iter().map(|p| along(axis, p)).collect() };
    let middle = |mut values: Vec<f64>| {
        values.sort_unstable_by(f64::total_cmp);
        let last = values.len() - 1;
        let at = |q: f64| values[(q * last as f64).round() as usize];
        (at(TRIM) + at(1.0 - TRIM)) / 2.0
    };
    // The plane's axes are orthonormal, so the three coordinates give the point.
    let (cu, cv) = (middle(coordinates(&u)), middle(coordinates(&v)));
    Some(Point3::from(u * cu + v * cv + n * cn))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unevenly_sampled_towel_is_centred_by_its_outline() {
        // A wall x = 2 facing -x; a 40 × 30 cm towel 2 cm proud centred at y = 0.1, z = 0.5,
        // sampled four times as densely on its left half (y > 0.1) as on its right.
        let plane = BackingPlane { normal: -Vector3::x(), offset: 2.0, points: 1000 };
        let mut members = Vec::new();
        for i in 0..=40 {
            for j in 0..=30 {
                let y = 0.1 + (f64::from(i) - 20.0) / 100.0;
                let z = 0.5 + (f64::from(j) - 15.0) / 100.0;
                let copies = if y > 0.1 { 4 } else { 1 };
                for _ in 0..copies {
                    members.push(Point3::new(1.98, y, z).cast::<f32>());
                }
            }
        }
        let mean = members.iter().map(|p| p.cast::<f64>().coords).sum::<Vector3<f64>>()
            / members.len() as f64;
        assert!((mean.y - 0.1).abs() > 0.05, "the mean slides toward the dense half");
        let centre = tag_centre_on(&members, &plane, None).unwrap();
        assert!((centre - Point3::new(1.98, 0.1, 0.5)).norm() < 0.01, "{centre}");
    }
}
