//! Waviness: how much a plane's patch bends beyond its noise, the evidence that tells a slab
//! tangent to a curved surface (a lamp shade) from a flat front (see [`super::plane_evidence`]).

use nalgebra::{Matrix6, Vector2, Vector6};

/// The near points of one cell of a patch, by their residuals from the plane.
pub(super) struct CellResiduals {
    /// Mean in-plane position, metres.
    pub(super) at: Vector2<f64>,
    pub(super) mean: f64,
    /// Sum of squared residuals about `mean`.
    pub(super) square_sum: f64,
    pub(super) points: f64,
}

/// How much the cells' mean residuals bend: the RMS difference between the best quadratic
/// surface through them and the best plane (a slightly misfitted plane), less what the noise of
/// the means alone would make a quadratic fit bend. A slab tangent to a lamp shade sags like a
/// quadratic; a flat front does not, however its scan lines jitter or its drawers step by a few
/// millimetres, which a plain RMS about the plane mistook for curvature.
pub(super) fn waviness_beyond_noise(cells: &[CellResiduals]) -> f64 {
    if cells.len() < 8 {
        return 0.0;
    }
    let k = cells.len() as f64;
    let centre = cells.iter().map(|c| c.at).sum::<Vector2<f64>>() / k;
    let terms = |c: &CellResiduals| {
        let q = c.at - centre;
        Vector6::new(1.0, q.x, q.y, q.x * q.x, q.x * q.y, q.y * q.y)
    };
    let (mut normal, mut rhs) = (Matrix6::zeros(), Vector6::zeros());
    for c in cells {
        let x = terms(c);
        normal += x * x.transpose();
        rhs += x * c.mean;
    }
    let linear = normal.fixed_view::<3, 3>(0, 0).try_inverse().map(|inverse| {
        let fit = inverse * rhs.fixed_rows::<3>(0);
        Vector6::new(fit[0], fit[1], fit[2], 0.0, 0.0, 0.0)
    });
    let (Some(linear), Some(quadratic)) =
        (linear, normal.try_inverse().map(|inverse| inverse * rhs))
    else {
        return 0.0;
    };
    let bend: f64 =
        cells.iter().map(|c| (quadratic - linear).dot(&terms(c)).powi(2)).sum::<f64>() / k;
    // Pooled within-cell variance, what it makes the cell means scatter by, and the share of that
    // scatter three more fitted terms take up.
    let (square_sum, freedom) =
        cells.iter().fold((0.0, 0.0), |(s, f), c| (s + c.square_sum, f + c.points - 1.0));
    let variance = if freedom > 0.0 { square_sum / freedom } else { 0.0 };
    let noise = variance * cells.iter().map(|c| 1.0 / c.points).sum::<f64>() / k;
    (bend - 3.0 / k * noise).max(0.0).sqrt()
}
