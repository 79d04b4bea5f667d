//! Waviness: how much a plane's patch bends beyond its noise, the evidence that tells a slab
//! tangent to a curved surface (a lamp shade) from a flat front (see [`super::plane_evidence`]).

use nalgebra::{SMatrix, SVector, Vector2};

type Matrix7 = SMatrix<f64, 7, 7>;
type Vector7 = SVector<f64, 7>;

/// The near points of one cell of a patch, by their residuals from the plane.
pub(super) struct CellResiduals {
    /// Mean in-plane position, metres.
    pub(super) at: Vector2<f64>,
    pub(super) mean: f64,
    /// Sum of squared residuals about `mean`.
    pub(super) square_sum: f64,
    pub(super) points: f64,
}

/// Least share of the cells, and least cells, on either side of a step: a surface of its own
/// beside the front (a dozen cells is some 14 cm square), not a few cells of clutter at its edge
/// nor a part of a small patch, which a step and a quadratic together could fit whatever its
/// shape.
const MIN_STEP_SIDE: f64 = 0.1;
const MIN_STEP_SIDE_CELLS: f64 = 12.0;

/// How much the cells' mean residuals bend: the RMS difference between the best quadratic
/// surface through them and the best plane (a slightly misfitted plane), less what the noise of
/// the means alone would make a quadratic fit bend. A slab tangent to a lamp shade sags like a
/// quadratic; a flat front does not, however its scan lines jitter or its drawers step by a few
/// millimetres, which a plain RMS about the plane mistook for curvature.
///
/// A front rarely stands alone, and the band can take in a second surface a couple of
/// centimetres behind it (a neighbouring cabinet's front, a door's frame). Such a step is not a
/// bend, but a quadratic half follows it. So when the plain bend exceeds `enough`, the fits are
/// also tried with a step between two parts of the patch (split across either in-plane axis at
/// a boundary between columns or rows of cells `cell` wide): a curved surface still bends
/// beside a step, a front and its neighbour do not.
pub(super) fn waviness_beyond_noise(cells: &[CellResiduals], enough: f64, cell: f64) -> f64 {
    if cells.len() < 8 {
        return 0.0;
    }
    let k = cells.len() as f64;
    let centre = cells.iter().map(|c| c.at).sum::<Vector2<f64>>() / k;
    // Pooled within-cell variance, what it makes the cell means scatter by, and the share of that
    // scatter three more fitted terms take up: the bend noise alone gives a quadratic fit.
    let (square_sum, freedom) =
        cells.iter().fold((0.0, 0.0), |(s, f), c| (s + c.square_sum, f + c.points - 1.0));
    let variance = if freedom > 0.0 { square_sum / freedom } else { 0.0 };
    let noise_bend = 3.0 / k * variance * cells.iter().map(|c| 1.0 / c.points).sum::<f64>() / k;
    let beyond_noise = |bend: f64| (bend - noise_bend).max(0.0).sqrt();
    let plain = mean_square_bend(cells, &centre, |_| false).unwrap_or(0.0);
    if beyond_noise(plain) <= enough {
        return beyond_noise(plain);
    }
    let least_side = (MIN_STEP_SIDE * k).ceil().max(MIN_STEP_SIDE_CELLS) as usize;
    let mut bend = plain;
    for axis in (0..2).filter(|_| cells.len() >= 2 * least_side) {
        let mut along: Vec<f64> = cells.iter().map(|c| c.at[axis]).collect();
        along.sort_by(f64::total_cmp);
        for pair in along[least_side - 1..along.len() + 1 - least_side].windows(2) {
            // A boundary between columns (or rows) of cells, not a split within one.
            if pair[1] - pair[0] < cell / 2.0 {
                continue;
            }
            let split = (pair[0] + pair[1]) / 2.0;
            if let Some(stepped) = mean_square_bend(cells, &centre, |c| c.at[axis] > split) {
                bend = bend.min(stepped);
            }
        }
    }
    beyond_noise(bend)
}

/// The mean square difference, over the cells, between the best quadratic surface and the best
/// plane through the cells' means, each allowed a step where `beyond` holds (none where it
/// never does). `None` when the cells do not determine the fits.
fn mean_square_bend(
    cells: &[CellResiduals],
    centre: &Vector2<f64>,
    beyond: impl Fn(&CellResiduals) -> bool,
) -> Option<f64> {
    // The plane's terms (with the step's) lead, so the plane's fit is the leading block.
    let terms = |c: &CellResiduals| {
        let q = c.at - centre;
        let step = if beyond(c) { 1.0 } else { 0.0 };
        Vector7::from([1.0, q.x, q.y, step, q.x * q.x, q.x * q.y, q.y * q.y])
    };
    let (mut normal, mut rhs) = (Matrix7::zeros(), Vector7::zeros());
    for c in cells {
        let x = terms(c);
        normal += x * x.transpose();
        rhs += x * c.mean;
    }
    if normal[(3, 3)] == 0.0 {
        // No step: its term is zero for every cell, and a unit on the diagonal fits it a zero
        // coefficient without touching the others.
        normal[(3, 3)] = 1.0;
    }
    let quadratic = normal.try_inverse()? * rhs;
    let plane = normal.fixed_view::<4, 4>(0, 0).try_inverse()? * rhs.fixed_rows::<4>(0);
    let plane = Vector7::from([plane[0], plane[1], plane[2], plane[3], 0.0, 0.0, 0.0]);
    let bend: f64 = cells.iter().map(|c| (quadratic - plane).dot(&terms(c)).powi(2)).sum();
    Some(bend / cells.len() as f64)
}
