//! How wide a plane's points are across, through most of them rather than through their variance.
//!
//! The plane search reports a plane's extent from the variance of its points, which a few points
//! far out inflate. A plane through a lamp's pole holds the pole (a line of points a few
//! centimetres across) and a scatter of the shade's rim and the chain beside it; that scatter
//! alone made it 20–24 cm "wide", as broad as a narrow cabinet front, and a plane that is no
//! surface could carry the tag. Through most of its points it is as wide as the pole.

use nalgebra::{Matrix2, Point3, SymmetricEigen, Vector2};

use super::plane::Plane;

/// Points the width is measured on at most: a spread's quartiles need no more.
const SAMPLE: usize = 2048;

/// The width of the points `inliers` names across the plane's narrowest direction (its minor
/// principal axis), metres: twice the interquartile range along it, which for points spread
/// evenly over a width is that width. `None` for fewer than four points.
pub(super) fn width_through_most(
    points: &[Point3<f32>],
    inliers: &[u32],
    plane: &Plane,
) -> Option<f64> {
    if inliers.len() < 4 {
        return None;
    }
    let (u, v) = plane.basis();
    let step = inliers.len().div_ceil(SAMPLE);
    let at: Vec<Vector2<f64>> = inliers
        .iter()
        .step_by(step)
        .map(|&i| {
            let p = points[i as usize].cast::<f64>().coords;
            Vector2::new(u.dot(&p), v.dot(&p))
        })
        .collect();
    let n = at.len() as f64;
    let mean = at.iter().sum::<Vector2<f64>>() / n;
    let scatter = at.iter().fold(Matrix2::zeros(), |s, q| s + (q - mean) * (q - mean).transpose());
    let eigen = SymmetricEigen::new(scatter / n);
    let minor = eigen.eigenvectors.column(eigen.eigenvalues.imin()).into_owned();
    let mut across: Vec<f64> = at.iter().map(|q| minor.dot(q)).collect();
    let quartile =
        |across: &mut [f64], k: usize| *across.select_nth_unstable_by(k, f64::total_cmp).1;
    let (lower, upper) = (across.len() / 4, across.len() * 3 / 4);
    let q1 = quartile(&mut across, lower);
    let q3 = quartile(&mut across, upper);
    Some(2.0 * (q3 - q1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn a_pole_with_a_scatter_beside_it_is_as_wide_as_the_pole() {
        let wall = Plane { normal: -Vector3::x(), offset: 2.0 };
        // A front 40 cm wide and 60 cm tall, evenly covered.
        let front: Vec<Point3<f32>> = (0..1200)
            .map(|i| Point3::new(2.0, 0.4 * (i % 40) as f32 / 40.0, 0.6 * (i / 40) as f32 / 30.0))
            .collect();
        let all: Vec<u32> = (0..front.len() as u32).collect();
        let width = width_through_most(&front, &all, &wall).unwrap();
        assert!((width - 0.4).abs() < 0.02, "{width}");
        // A pole 3 cm across and 90 cm tall, and a fifth as many points scattered 40 cm wide.
        let mut pole: Vec<Point3<f32>> = (0..800)
            .map(|i| Point3::new(2.0, 0.03 * (i % 8) as f32 / 8.0, 0.9 * (i / 8) as f32 / 100.0))
            .collect();
        pole.extend((0..200).map(|i| {
            let side = if i % 2 == 0 { -1.0 } else { 1.0 };
            Point3::new(2.0, side * (0.05 + 0.15 * (i % 10) as f32 / 10.0), 0.8 + 0.001 * i as f32)
        }));
        let all: Vec<u32> = (0..pole.len() as u32).collect();
        let width = width_through_most(&pole, &all, &wall).unwrap();
        assert!(width < 0.06, "{width}");
    }
}
