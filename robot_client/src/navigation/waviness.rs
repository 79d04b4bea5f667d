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
/// also tried with a step between two parts of the patch, where a plane and a step fit the cells
/// best (split across either in-plane axis at a boundary between columns or rows of cells
/// `cell` wide): a curved surface still bends beside a step, a front and its neighbour do not.
/// Both surfaces must run along the plane: a plane tilted against them by more than its `±band`
/// across the patch holds only strips of them (a slab cut at a slant through a bin's front and
/// the wall behind it), which a plane and a step fit as well as a front beside its neighbour.
pub(super) fn waviness_beyond_noise(
    cells: &[CellResiduals],
    enough: f64,
    cell: f64,
    band: f64,
) -> f64 {
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
    let plain = fits(cells, &centre, |_| false).map_or(0.0, |fit| fit.bend);
    if beyond_noise(plain) <= enough {
        return beyond_noise(plain);
    }
    // Where the step is: the split a plane and a step fit best.
    let least_side = (MIN_STEP_SIDE * k).ceil().max(MIN_STEP_SIDE_CELLS) as usize;
    let mut step: Option<Fits> = None;
    for axis in (0..2).filter(|_| cells.len() >= 2 * least_side) {
        let mut along: Vec<f64> = cells.iter().map(|c| c.at[axis]).collect();
        along.sort_by(f64::total_cmp);
        for pair in along[least_side - 1..along.len() + 1 - least_side].windows(2) {
            // A boundary between columns (or rows) of cells, not a split within one.
            if pair[1] - pair[0] < cell / 2.0 {
                continue;
            }
            let split = (pair[0] + pair[1]) / 2.0;
            if let Some(fit) = fits(cells, &centre, |c| c.at[axis] > split)
                && step.as_ref().is_none_or(|best| fit.misfit < best.misfit)
            {
                step = Some(fit);
            }
        }
    }
    match step {
        Some(step) if step.rise <= band => beyond_noise(plain.min(step.bend)),
        _ => beyond_noise(plain),
    }
}

/// The best quadratic surface and the best plane through the cells' means, compared.
struct Fits {
    /// The mean square difference between the two over the cells.
    bend: f64,
    /// The mean square of the cells' means about the plane.
    misfit: f64,
    /// How far the plane rises across the cells, relative to the one judged.
    rise: f64,
}

/// Fits the best quadratic surface and the best plane through the cells' means, each allowed a
/// step where `beyond` holds (none where it never does). `None` when the cells do not determine
/// the fits.
fn fits(
    cells: &[CellResiduals],
    centre: &Vector2<f64>,
    beyond: impl Fn(&CellResiduals) -> bool,
) -> Option<Fits> {
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
    let height =
        |c: &CellResiduals| plane[1] * (c.at.x - centre.x) + plane[2] * (c.at.y - centre.y);
    let (low, high) = cells
        .iter()
        .map(height)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| (lo.min(h), hi.max(h)));
    let misfit: f64 = cells.iter().map(|c| (c.mean - plane.dot(&terms(c))).powi(2)).sum();
    let k = cells.len() as f64;
    Some(Fits { bend: bend / k, misfit: misfit / k, rise: high - low })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells 4 cm apart over 0.8 m × 0.4 m, their means `mean(x, y)`, each of 20 points with 2 mm
    /// of noise.
    fn cells(mean: impl Fn(f64, f64) -> f64) -> Vec<CellResiduals> {
        let mut cells = Vec::new();
        for i in 0..20 {
            for j in 0..10 {
                let at = Vector2::new(0.02 + 0.04 * f64::from(i), 0.02 + 0.04 * f64::from(j));
                let points = 20.0;
                cells.push(CellResiduals {
                    at,
                    mean: mean(at.x, at.y),
                    square_sum: (points - 1.0) * 0.002f64.powi(2),
                    points,
                });
            }
        }
        cells
    }

    const ENOUGH: f64 = 0.004;
    const CELL: f64 = 0.04;
    const BAND: f64 = 0.03;

    #[test]
    fn a_front_beside_a_surface_set_back_is_flat_but_a_bowl_is_not() {
        // A quarter of the patch 22 mm further back.
        let step = |x: f64, _: f64| if x > 0.6 { -0.022 } else { 0.0 };
        let plain = waviness_beyond_noise(&cells(step), f64::INFINITY, CELL, BAND);
        assert!(plain > ENOUGH, "a plain quadratic follows the step: {plain}");
        assert!(waviness_beyond_noise(&cells(step), ENOUGH, CELL, BAND) < 0.001);
        // A bowl 2 cm deep, with or without the step beside it.
        let bowl = |x: f64, y: f64| 0.02 * (((x - 0.4) / 0.4).powi(2) + ((y - 0.2) / 0.2).powi(2));
        assert!(waviness_beyond_noise(&cells(bowl), ENOUGH, CELL, BAND) > ENOUGH);
        let both = |x: f64, y: f64| bowl(x, y) + step(x, y);
        assert!(waviness_beyond_noise(&cells(both), ENOUGH, CELL, BAND) > ENOUGH);
    }

    #[test]
    fn two_surfaces_the_plane_cuts_at_a_slant_are_no_step() {
        // Two parallel surfaces, one 25 mm behind the other, tilted against the plane so that
        // it rises 38 mm across the patch, more than its band: the band holds strips of them.
        let cut = |x: f64, _: f64| 0.05 * (x - 0.4) + if x > 0.6 { -0.025 } else { 0.0 };
        let plain = waviness_beyond_noise(&cells(cut), f64::INFINITY, CELL, BAND);
        assert!(plain > ENOUGH, "{plain}");
        assert_eq!(waviness_beyond_noise(&cells(cut), ENOUGH, CELL, BAND), plain);
        // The same pair along the plane, within its band across the patch: a step.
        let along = |x: f64, _: f64| 0.02 * (x - 0.4) + if x > 0.6 { -0.025 } else { 0.0 };
        assert!(waviness_beyond_noise(&cells(along), ENOUGH, CELL, BAND) < 0.001);
    }
}
