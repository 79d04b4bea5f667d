//! A tag lying against a red thing by a whole side, found by the registered tag's rectangle
//! (issue 34).
//!
//! Where a red plastic of the tag's colour lies on the tag's surface and touches it along a
//! side as long as the disc of [`super::tag_shape`] is wide, the disc rolls over the tag too
//! and nothing stands out. What still tells the tag apart is its outline: the home's tags are
//! rectangles of registered sizes, and a tag beside a thing borders nothing red on three of
//! its sides and the thing on the fourth. A rectangle of a tag's size inside a red thing too
//! large to be one borders red on two sides at least, at a corner of the thing as anywhere
//! else. So the rectangle of a registered size that fits the red region near the pointed
//! location with three sides free is the tag; when two such places lie apart, which one the
//! person meant is not known, and nothing is taken.

use nalgebra::{Point3, Vector3};
use pps_schema::TagSize;
use rustc_hash::FxHashSet;

use super::tag_shape::{CELL, HOLE_CELLS, SurfaceGrid};

/// The rectangle is tried turned by this many degrees at a time: at 3° its far corner moves
/// under a cell (0.5 cm) on a 10 cm side.
const ANGLE_STEP_DEG: usize = 3;

/// How much of the rectangle the red region must fill: its own outline is ragged by a cell.
const FILLED: f64 = 0.85;

/// How much of a free side's band may be red: the outline's ragged cells and a fleck.
const STRAY: f64 = 0.1;

/// How much of the fourth side's band the thing fills, at least: a tag that touches the thing
/// only at a corner borders nothing on that side either, and is found as standing out.
const ATTACHED: f64 = 0.5;

/// A side's band lies this many cells past the rectangle, so that a registered size a
/// centimetre off, or the outline's ragged cells, still leave it empty.
const BAND_CELLS: [f64; 2] = [2.5, 4.0];

/// Where the rectangle hugs the tag's outline, the cells just past its free sides are empty
/// too: of the rectangles that fit, slid a cell or two, the one that does is the tag's.
const HUGGING_CELLS: [f64; 2] = [0.5, 1.0];

/// The narrowest registered size whose rectangle is tried, metres. A foam tube is round, not a
/// rectangle lying on its surface, and a rectangle as thin as a tube (2.4–3.6 cm) fits along
/// a fabric hanging against it as well as on the tube: a lamp's tube was taken 5 cm off so.
/// Patches and towels are 4.2 cm wide and more.
const NARROWEST: f64 = 0.04;

/// The rectangle is first tried at every other cell, and then at the cells around each place
/// it fitted: a tag's rectangle fits over a range of places two cells wide and more (its far
/// side's band lies 2.5 cells out).
const COARSE_CELLS: i64 = 2;

/// The rectangle found: which points lie in it, and its size.
#[derive(Debug)]
pub(super) struct AgainstASide {
    pub kept: Vec<usize>,
    pub size: TagSize,
}

/// The points of `points` (a red region on one surface, `normal` its normal through `centre`)
/// in the one rectangle of a size of `sizes` (no thinner than a patch) within `reach` of
/// `target` that the region fills and that borders nothing red on three sides and the region
/// on the fourth; `None` when no rectangle does, or two lie apart. Past a free side the
/// picture shows no red either (`seen_red`, at a place on the surface): a red thing nearer the
/// camera hides the surface there, and beside a hidden place nothing is known.
pub(super) fn against_a_side(
    points: &[Point3<f32>],
    centre: &Vector3<f64>,
    normal: &Vector3<f64>,
    sizes: &[TagSize],
    target: &Point3<f64>,
    reach: f64,
    seen_red: &dyn Fn(&Point3<f64>) -> bool,
) -> Option<AgainstASide> {
    let surface = SurfaceGrid::of(points, centre, normal, HOLE_CELLS)?;
    let target = surface.flat_of(target);
    let farthest = sizes.iter().map(|s| s.width.hypot(s.height) / 2.0).fold(0.0, f64::max);
    let red = RedMap::around(target, reach + farthest + BAND_CELLS[1] * CELL, |p| {
        surface.occupied(p) || seen_red(&surface.point_at(p))
    });
    // A rectangle with three sides free has its middle within half its narrower side, and the
    // cells that hug it, of the region's outline: the region's inside holds none.
    let to_outline = surface.distances_to_outline();
    let steps = (reach / CELL).ceil() as i64;
    let within_reach = |i: i64, j: i64| ((i * i + j * j) as f64).sqrt() * CELL <= reach;
    let place = |i: i64, j: i64| [target[0] + i as f64 * CELL, target[1] + j as f64 * CELL];
    let mut fits: Vec<Fit> = Vec::new();
    for &size in sizes.iter().filter(|s| s.width.min(s.height) >= NARROWEST) {
        let near_outline = size.width.min(size.height) / 2.0 + 2.0 * CELL;
        let candidate =
            |i: i64, j: i64| within_reach(i, j) && to_outline(place(i, j)) <= near_outline;
        for angle in (0..180).step_by(ANGLE_STEP_DEG) {
            let rectangle = Rectangle::new(size, (angle as f64).to_radians());
            let samples = Samples::of(&rectangle);
            let mut tried = FxHashSet::default();
            let mut fits_at = |i: i64, j: i64, fits: &mut Vec<Fit>| {
                if !tried.insert([i, j]) || !candidate(i, j) {
                    return false;
                }
                let at = place(i, j);
                let Some(score) = samples.fit_at(at, &red) else { return false };
                fits.push(Fit { at, rectangle, score });
                true
            };
            let coarse = (-steps..=steps).step_by(COARSE_CELLS as usize);
            for i in coarse.clone() {
                for j in coarse.clone() {
                    if fits_at(i, j, &mut fits) {
                        for (di, dj) in (-1..=1).flat_map(|di| (-1..=1).map(move |dj| (di, dj))) {
                            fits_at(i + di, j + dj, &mut fits);
                        }
                    }
                }
            }
        }
    }
    let best = fits.iter().max_by(|a, b| a.score.total_cmp(&b.score))?;
    // Every fit lies on the best one's tag, the rectangle slid or turned a little; one further
    // off than the tag's narrower side is another place a tag could be.
    let narrow = best.rectangle.size.width.min(best.rectangle.size.height);
    let apart = |f: &Fit| (f.at[0] - best.at[0]).hypot(f.at[1] - best.at[1]) > narrow;
    if fits.iter().any(apart) {
        return None;
    }
    let kept: Vec<usize> = (0..points.len())
        .filter(|&i| best.rectangle.holds(best.at, surface.flat[i], CELL))
        .collect();
    (!kept.is_empty()).then_some(AgainstASide { kept, size: best.rectangle.size })
}

/// A rectangle that fits, where, and how well.
struct Fit {
    at: [f64; 2],
    rectangle: Rectangle,
    score: f64,
}

/// Where the region or the picture shows red on the surface, looked up once for each half
/// cell of a square around a place.
struct RedMap {
    origin: [f64; 2],
    side: usize,
    red: Vec<bool>,
}

impl RedMap {
    /// What `red` says of the places within `reach` of `middle` (in a square).
    fn around(middle: [f64; 2], reach: f64, red: impl Fn([f64; 2]) -> bool) -> Self {
        let step = CELL / 2.0;
        let side = (2.0 * reach / step).ceil() as usize + 1;
        let origin = [middle[0] - reach, middle[1] - reach];
        let red = (0..side * side)
            .map(|k| {
                let (i, j) = (k % side, k / side);
                red([origin[0] + (i as f64 + 0.5) * step, origin[1] + (j as f64 + 0.5) * step])
            })
            .collect();
        Self { origin, side, red }
    }

    /// Whether `p` is red; outside the square nothing is known to be.
    fn at(&self, p: [f64; 2]) -> bool {
        let per_step = 2.0 / CELL;
        let (i, j) = ((p[0] - self.origin[0]) * per_step, (p[1] - self.origin[1]) * per_step);
        let inside = i >= 0.0 && j >= 0.0 && (i as usize) < self.side && (j as usize) < self.side;
        inside && self.red[j as usize * self.side + i as usize]
    }
}

/// A tag's rectangle on the surface, turned by an angle.
#[derive(Clone, Copy)]
struct Rectangle {
    size: TagSize,
    along: [f64; 2],
    across: [f64; 2],
}

impl Rectangle {
    fn new(size: TagSize, angle: f64) -> Self {
        let (sin, cos) = angle.sin_cos();
        Self { size, along: [cos, sin], across: [-sin, cos] }
    }

    /// The offset from the middle `s` along and `t` across.
    fn offset(&self, s: f64, t: f64) -> [f64; 2] {
        [s * self.along[0] + t * self.across[0], s * self.along[1] + t * self.across[1]]
    }

    /// Whether `p` lies in the rectangle at `at`, grown by `margin` all round.
    fn holds(&self, at: [f64; 2], p: [f64; 2], margin: f64) -> bool {
        let d = [p[0] - at[0], p[1] - at[1]];
        let s = d[0] * self.along[0] + d[1] * self.along[1];
        let t = d[0] * self.across[0] + d[1] * self.across[1];
        s.abs() <= self.size.width / 2.0 + margin && t.abs() <= self.size.height / 2.0 + margin
    }
}

/// The offsets from a rectangle's middle at which it is sampled: inside, every other cell, and
/// for each side, the band past it and the cells that hug it. A side is sampled only along its
/// own length, inset by a cell: past the corners lie the other sides' bands.
struct Samples {
    inside: Vec<[f64; 2]>,
    bands: [Vec<[f64; 2]>; 4],
    hugging: [Vec<[f64; 2]>; 4],
}

impl Samples {
    fn of(rectangle: &Rectangle) -> Self {
        let (half_w, half_h) = (rectangle.size.width / 2.0, rectangle.size.height / 2.0);
        let (steps_s, steps_t) =
            ((half_w / (2.0 * CELL)).floor() as i64, (half_h / (2.0 * CELL)).floor() as i64);
        let inside = (-steps_s..=steps_s)
            .flat_map(|i| (-steps_t..=steps_t).map(move |j| (i, j)))
            .map(|(i, j)| rectangle.offset(i as f64 * 2.0 * CELL, j as f64 * 2.0 * CELL))
            .collect();
        let normals = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)];
        let side = |(normal_s, normal_t): (f64, f64), cells: &[f64]| {
            let (half_len, half_off) =
                if normal_s != 0.0 { (half_h, half_w) } else { (half_w, half_h) };
            let steps = ((half_len - CELL) / CELL).floor() as i64;
            let mut offsets = Vec::new();
            for band in cells {
                let off = half_off + band * CELL;
                for k in -steps..=steps {
                    let along = k as f64 * CELL;
                    offsets.push(if normal_s != 0.0 {
                        rectangle.offset(normal_s * off, along)
                    } else {
                        rectangle.offset(along, normal_t * off)
                    });
                }
            }
            offsets
        };
        Self {
            inside,
            bands: normals.map(|n| side(n, &BAND_CELLS)),
            hugging: normals.map(|n| side(n, &HUGGING_CELLS)),
        }
    }

    /// How well the rectangle at `at` is a tag against a side of the red region: the share of
    /// it filled and of the cells that hug its three free sides left empty, summed; `None`
    /// when it is not filled, or does not border nothing on three sides and red on the fourth.
    fn fit_at(&self, at: [f64; 2], red: &RedMap) -> Option<f64> {
        let share = |offsets: &[[f64; 2]]| {
            let red_ones = offsets.iter().filter(|o| red.at([at[0] + o[0], at[1] + o[1]])).count();
            red_ones as f64 / offsets.len().max(1) as f64
        };
        let (mut free, mut attached) = ([false; 4], false);
        for (k, band) in self.bands.iter().enumerate() {
            match share(band) {
                r if r <= STRAY => free[k] = true,
                r if r >= ATTACHED && !attached => attached = true,
                // A second side against red, or one neither free nor against it.
                _ => return None,
            }
        }
        let fill = share(&self.inside);
        if !attached || fill < FILLED {
            return None;
        }
        let hugging: f64 =
            (0..4).filter(|&k| free[k]).map(|k| 1.0 - share(&self.hugging[k])).sum::<f64>() / 3.0;
        Some(fill + hugging)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points every 2.5 mm over `[x0, x1] × [y0, y1]` on the plane z = 1 m.
    fn sheet(x: [f64; 2], y: [f64; 2]) -> Vec<Point3<f32>> {
        let step = 0.0025;
        let (nx, ny) = (((x[1] - x[0]) / step) as usize, ((y[1] - y[0]) / step) as usize);
        (0..=nx)
            .flat_map(|i| (0..=ny).map(move |j| (i, j)))
            .map(|(i, j)| {
                Point3::new((x[0] + i as f64 * step) as f32, (y[0] + j as f64 * step) as f32, 1.0)
            })
            .collect()
    }

    const ROCKER: TagSize = TagSize { width: 0.056, height: 0.10 };

    fn found(points: &[Point3<f32>], target: Point3<f64>) -> Option<Vec<Point3<f32>>> {
        found_seeing(points, target, &|_| false)
    }

    fn found_seeing(
        points: &[Point3<f32>],
        target: Point3<f64>,
        seen_red: &dyn Fn(&Point3<f64>) -> bool,
    ) -> Option<Vec<Point3<f32>>> {
        let centre = Vector3::new(0.0, 0.0, 1.0);
        let normal = Vector3::z();
        against_a_side(points, &centre, &normal, &[ROCKER], &target, 0.10, seen_red)
            .map(|found| found.kept.iter().map(|&i| points[i]).collect())
    }

    #[test]
    fn a_tag_against_a_thing_by_its_long_side_is_its_rectangle() {
        // A 20 × 25 cm plastic, and the rocker's patch against its right side, a little below
        // its middle: the disc of the tag's shape would roll over both.
        let mut region = sheet([-0.20, 0.0], [-0.12, 0.13]);
        let tag = sheet([0.0025, 0.0585], [-0.06, 0.04]);
        region.extend(&tag);
        let kept = found(&region, Point3::new(0.04, -0.02, 1.0)).expect("the tag");
        let mean =
            kept.iter().map(|p| p.coords.cast::<f64>()).sum::<Vector3<f64>>() / kept.len() as f64;
        assert!((mean.x - 0.0305).abs() < 0.006 && (mean.y + 0.01).abs() < 0.006, "{mean:?}");
        let of_the_tag = kept.iter().filter(|p| p.x > 0.001).count();
        assert!(of_the_tag as f64 >= 0.95 * tag.len() as f64, "{of_the_tag} of {}", tag.len());
        assert!(
            kept.len() - of_the_tag < tag.len() / 10,
            "{} of the plastic",
            kept.len() - of_the_tag
        );
    }

    #[test]
    fn a_red_thing_alone_has_no_rectangle_with_three_sides_free_even_at_its_corner() {
        let plastic = sheet([-0.20, 0.0], [-0.12, 0.13]);
        assert!(found(&plastic, Point3::new(-0.02, 0.11, 1.0)).is_none());
        assert!(found(&plastic, Point3::new(-0.10, 0.0, 1.0)).is_none());
    }

    #[test]
    fn two_tags_against_the_thing_either_side_of_the_pointed_spot_are_not_guessed_between() {
        let mut region = sheet([-0.06, 0.06], [-0.12, 0.13]);
        region.extend(sheet([0.0625, 0.1185], [-0.05, 0.05]));
        region.extend(sheet([-0.1185, -0.0625], [-0.05, 0.05]));
        assert!(found(&region, Point3::new(0.0, 0.0, 1.0)).is_none());
    }

    #[test]
    fn a_side_the_picture_shows_red_past_is_hidden_not_free() {
        // The same tag and plastic, and a red tube nearer the camera hanging past the tag's
        // far side: the surface there is hidden, so nothing says the tag ends there.
        let mut region = sheet([-0.20, 0.0], [-0.12, 0.13]);
        region.extend(sheet([0.0025, 0.0585], [-0.06, 0.04]));
        let target = Point3::new(0.04, -0.02, 1.0);
        assert!(found(&region, target).is_some());
        let tube = |p: &Point3<f64>| (0.062..0.09).contains(&p.x);
        assert!(found_seeing(&region, target, &tube).is_none());
    }
}
