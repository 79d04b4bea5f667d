//! A tag standing out of a red thing too large to be one, found by its shape (issue 34).
//!
//! Where a red plastic of nearly the tag's colour lies against the tag on the same surface, the
//! two may be one colour and one surface within the camera's noise. But where the home's tags'
//! sizes are registered, every tag is narrower than a disc a little wider than the widest tag,
//! and a red thing too large to be a tag mostly is not: seen along the surface's normal, such a
//! disc rolls over the thing and not over the tag beside it, bar a strip along the edge they
//! share, where the disc straddles the two. What the disc cannot reach (a morphological
//! opening's residue) is the tag, and the slivers the disc leaves in the thing's corners, which
//! are far narrower than a tag. Nothing is found where the tag lies on the thing, inside its
//! outline, or lies against it by a side as long as the disc is wide: the disc straddling the
//! two then takes most of the tag.

use nalgebra::{Point3, Vector3};

/// Edge of the grid's cells on the surface, metres: about a depth camera's pixel at 1.5 m, so a
/// dense frame fills every cell, and a tenth of the narrowest tag (a 3 cm foam tube).
pub(super) const CELL: f64 = 0.005;

/// How far past the widest tag's half width the disc reaches, in cells: the mask's outline is
/// ragged by a pixel or two and the grid rounds by one more.
const OUTLINE_CELLS: f64 = 2.0;

/// The narrowest a residue may be to be a tag, as a share of the disc's radius: the widest tag
/// holds a disc of half of it, the sliver a disc of radius `r` leaves in a right-angled corner
/// one of a fifth of `r` at most.
const TAG_OF_DISC: f64 = 0.5;

/// Cells a point's hole in the grid may be wide and still be filled: a depth image's holes on a
/// surface are single pixels.
pub(super) const HOLE_CELLS: i64 = 1;

/// A piece of a red region no disc wider than a tag reaches.
pub(super) struct StandingOut {
    /// Which of the points, by index.
    pub kept: Vec<usize>,
    /// The disc's diameter, metres.
    pub disc: f64,
}

/// The points of `points` (a red part lying on one surface, `normal` its normal through
/// `centre`) that a disc reaching `half_width` and a little further cannot reach, in the piece
/// of them nearest `target` that is as wide as a tag; `None` when there is none.
pub(super) fn out_of_reach_of_a_disc(
    points: &[Point3<f32>],
    centre: &Vector3<f64>,
    normal: &Vector3<f64>,
    half_width: f64,
    target: &Point3<f64>,
) -> Option<StandingOut> {
    let surface = SurfaceGrid::of(points, centre, normal, HOLE_CELLS)?;
    let target = surface.flat_of(target);
    let SurfaceGrid { grid, flat, occupied, .. } = surface;
    let radius = half_width / CELL + OUTLINE_CELLS;
    // Rolling the disc: the cells it can be centred on lie further than its radius from every
    // empty cell, and it covers those within its radius of one of them.
    let empty: Vec<bool> = occupied.iter().map(|o| !o).collect();
    let centres: Vec<bool> =
        grid.squared_distances_to(&empty).iter().map(|d| *d > radius * radius).collect();
    let rolled = grid.squared_distances_to(&centres).into_iter().map(|d| d <= radius * radius);
    let residue: Vec<bool> = occupied.iter().zip(rolled).map(|(o, r)| *o && !r).collect();
    // The residue's pieces as wide as a tag: those holding a disc of the narrowest a tag is.
    let outside: Vec<bool> = residue.iter().map(|r| !r).collect();
    let narrowest = TAG_OF_DISC * radius;
    let core: Vec<bool> =
        grid.squared_distances_to(&outside).iter().map(|d| *d > narrowest * narrowest).collect();
    let pieces = grid.pieces(&residue);
    let target_cell = grid.cell_at(target);
    // The person pointed at the tag: the spot lies on the piece, or on the strip of the tag the
    // disc took where it straddled the tag's edge with the thing, within its radius of the
    // piece. A piece farther off is a part of the thing the disc did not fit, and the tag, if
    // it is there at all, lies inside the thing's outline.
    let piece = pieces
        .iter()
        .filter(|piece| piece.iter().any(|&c| core[c]))
        .map(|piece| (grid.nearest(piece, target_cell), piece))
        .filter(|(distance, _)| *distance <= radius)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, piece)| piece)?;
    let mut in_piece = vec![false; grid.cells()];
    for &c in piece {
        in_piece[c] = true;
    }
    let kept: Vec<usize> =
        (0..points.len()).filter(|&i| grid.index(flat[i]).is_some_and(|c| in_piece[c])).collect();
    (!kept.is_empty()).then_some(StandingOut { kept, disc: 2.0 * radius * CELL })
}

/// A red region's points seen along its surface's normal: where each lies on the surface, and
/// which of the grid's cells they fill, holes up to a few cells wide filled.
pub(super) struct SurfaceGrid {
    grid: Grid,
    /// Each point's place on the surface, metres from the centre, along two axes across it.
    pub flat: Vec<[f64; 2]>,
    occupied: Vec<bool>,
    centre: Vector3<f64>,
    axes: (Vector3<f64>, Vector3<f64>),
}

impl SurfaceGrid {
    /// `points` on the surface of `normal` through `centre`, their holes up to `holes` cells
    /// wide filled; `None` when there are no points.
    pub fn of(
        points: &[Point3<f32>],
        centre: &Vector3<f64>,
        normal: &Vector3<f64>,
        holes: i64,
    ) -> Option<Self> {
        let axes = axes_of(normal);
        let on = |p: &Point3<f32>| {
            let d = p.cast::<f64>().coords - centre;
            [d.dot(&axes.0), d.dot(&axes.1)]
        };
        let flat: Vec<[f64; 2]> = points.iter().map(on).collect();
        let grid = Grid::of(&flat)?;
        let occupied = grid.closed(&grid.occupancy(&flat), holes);
        Some(Self { grid, flat, occupied, centre: *centre, axes })
    }

    /// Where `p` lies on the surface.
    pub fn flat_of(&self, p: &Point3<f64>) -> [f64; 2] {
        let d = p.coords - self.centre;
        [d.dot(&self.axes.0), d.dot(&self.axes.1)]
    }

    /// The point in space at `p` on the surface.
    pub fn point_at(&self, p: [f64; 2]) -> Point3<f64> {
        Point3::from(self.centre + self.axes.0 * p[0] + self.axes.1 * p[1])
    }

    /// How far each place on the surface lies from the nearest cell not filled, metres: naught
    /// outside the grid.
    pub fn distances_to_outline(&self) -> impl Fn([f64; 2]) -> f64 + '_ {
        let empty: Vec<bool> = self.occupied.iter().map(|o| !o).collect();
        let squared = self.grid.squared_distances_to(&empty);
        move |p| self.grid.index(p).map_or(0.0, |c| squared[c].sqrt() * CELL)
    }

    /// Whether the cell at `p` on the surface is filled; outside the grid nothing is.
    pub fn occupied(&self, p: [f64; 2]) -> bool {
        self.grid.index(p).is_some_and(|c| self.occupied[c])
    }
}

/// Two unit vectors across the surface, at right angles to each other and to `normal`.
fn axes_of(normal: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let n = normal.normalize();
    let other = if n.z.abs() < 0.9 { Vector3::z() } else { Vector3::x() };
    let across = n.cross(&other).normalize();
    (across, n.cross(&across))
}

/// Square cells on the surface over the points' extent, and a ring of empty cells round them:
/// every cell of the region has its nearest empty cell within the grid.
struct Grid {
    origin: [f64; 2],
    columns: i64,
    rows: i64,
}

impl Grid {
    fn of(flat: &[[f64; 2]]) -> Option<Self> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in flat {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        if !(lo[0].is_finite() && lo[1].is_finite()) {
            return None;
        }
        // One empty cell all round: a disc eroding the border meets emptiness there.
        let origin = [lo[0] - CELL, lo[1] - CELL];
        let columns = ((hi[0] - origin[0]) / CELL).floor() as i64 + 2;
        let rows = ((hi[1] - origin[1]) / CELL).floor() as i64 + 2;
        Some(Self { origin, columns, rows })
    }

    fn cells(&self) -> usize {
        (self.columns * self.rows) as usize
    }

    fn cell_at(&self, p: [f64; 2]) -> [i64; 2] {
        [
            ((p[0] - self.origin[0]) / CELL).floor() as i64,
            ((p[1] - self.origin[1]) / CELL).floor() as i64,
        ]
    }

    fn index(&self, p: [f64; 2]) -> Option<usize> {
        self.at(self.cell_at(p))
    }

    fn at(&self, [x, y]: [i64; 2]) -> Option<usize> {
        ((0..self.columns).contains(&x) && (0..self.rows).contains(&y))
            .then(|| (y * self.columns + x) as usize)
    }

    fn xy(&self, c: usize) -> [i64; 2] {
        let c = c as i64;
        [c % self.columns, c / self.columns]
    }

    fn occupancy(&self, flat: &[[f64; 2]]) -> Vec<bool> {
        let mut occupied = vec![false; self.cells()];
        for p in flat {
            if let Some(c) = self.index(*p) {
                occupied[c] = true;
            }
        }
        occupied
    }

    /// `set` with its holes up to `reach` cells wide filled (a closing by a square).
    fn closed(&self, set: &[bool], reach: i64) -> Vec<bool> {
        let square: Vec<[i64; 2]> =
            (-reach..=reach).flat_map(|x| (-reach..=reach).map(move |y| [x, y])).collect();
        self.eroded(&self.dilated(set, &square), &square)
    }

    /// Each cell's squared distance, in cells, to the nearest cell of `set` ([`FAR`] or more
    /// when `set` is empty): along the rows, then along the columns.
    fn squared_distances_to(&self, set: &[bool]) -> Vec<f64> {
        let (columns, rows) = (self.columns as usize, self.rows as usize);
        let mut along_rows = vec![0.0; set.len()];
        for y in 0..rows {
            let row: Vec<f64> =
                (0..columns).map(|x| if set[y * columns + x] { 0.0 } else { FAR }).collect();
            along_rows[y * columns..(y + 1) * columns].copy_from_slice(&distances_along(&row));
        }
        let mut out = vec![0.0; set.len()];
        for x in 0..columns {
            let column: Vec<f64> = (0..rows).map(|y| along_rows[y * columns + x]).collect();
            for (y, d) in distances_along(&column).into_iter().enumerate() {
                out[y * columns + x] = d;
            }
        }
        out
    }

    /// The cells of `set` whose every offset in `shape` lies in `set` too; outside the grid
    /// is outside the set.
    fn eroded(&self, set: &[bool], shape: &[[i64; 2]]) -> Vec<bool> {
        (0..set.len())
            .map(|c| {
                let [x, y] = self.xy(c);
                set[c]
                    && shape
                        .iter()
                        .all(|[dx, dy]| self.at([x + dx, y + dy]).is_some_and(|n| set[n]))
            })
            .collect()
    }

    /// The cells some offset in `shape` from a cell of `set` reaches.
    fn dilated(&self, set: &[bool], shape: &[[i64; 2]]) -> Vec<bool> {
        let mut out = vec![false; set.len()];
        for c in (0..set.len()).filter(|&c| set[c]) {
            let [x, y] = self.xy(c);
            for [dx, dy] in shape {
                if let Some(n) = self.at([x + dx, y + dy]) {
                    out[n] = true;
                }
            }
        }
        out
    }

    /// The pieces of `set`, cells touching by an edge or a corner.
    fn pieces(&self, set: &[bool]) -> Vec<Vec<usize>> {
        let mut seen = vec![false; set.len()];
        let mut pieces = Vec::new();
        for start in 0..set.len() {
            if !set[start] || seen[start] {
                continue;
            }
            seen[start] = true;
            let (mut piece, mut stack) = (Vec::new(), vec![start]);
            while let Some(c) = stack.pop() {
                piece.push(c);
                let [x, y] = self.xy(c);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        if let Some(n) = self.at([x + dx, y + dy])
                            && set[n]
                            && !seen[n]
                        {
                            seen[n] = true;
                            stack.push(n);
                        }
                    }
                }
            }
            pieces.push(piece);
        }
        pieces
    }

    /// The distance from `cell` to the piece's nearest cell, in cells.
    fn nearest(&self, piece: &[usize], cell: [i64; 2]) -> f64 {
        piece
            .iter()
            .map(|&c| {
                let [x, y] = self.xy(c);
                ((x - cell[0]) as f64).hypot((y - cell[1]) as f64)
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// Far enough for any grid: a squared distance no cell pair reaches.
const FAR: f64 = 1e18;

/// Each cell's squared distance, in cells, to the nearest of `values` that is 0 (the rest
/// [`FAR`]) along one row or column: the lower envelope of the parabolas rooted at those
/// (Felzenszwalb and Huttenlocher's distance transform), in time linear in the cells.
fn distances_along(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let (mut roots, mut bounds) = (vec![0usize; n], vec![0.0f64; n + 1]);
    let mut k = 0;
    bounds[0] = f64::NEG_INFINITY;
    bounds[1] = f64::INFINITY;
    let meet = |q: usize, r: usize| {
        let (q2, r2) = ((q * q) as f64, (r * r) as f64);
        ((values[q] + q2) - (values[r] + r2)) / (2.0 * (q as f64 - r as f64))
    };
    for q in 1..n {
        let mut s = meet(q, roots[k]);
        while s <= bounds[k] {
            k -= 1;
            s = meet(q, roots[k]);
        }
        k += 1;
        roots[k] = q;
        bounds[k] = s;
        bounds[k + 1] = f64::INFINITY;
    }
    let mut out = vec![0.0; n];
    k = 0;
    for (q, out) in out.iter_mut().enumerate() {
        while bounds[k + 1] < q as f64 {
            k += 1;
        }
        let d = q as f64 - roots[k] as f64;
        *out = d * d + values[roots[k]];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points every 2.5 mm on the plane x = 1 over the rectangles `(y0, z0, y1, z1)`, metres.
    fn on_the_wall(rectangles: &[[f64; 4]]) -> Vec<Point3<f32>> {
        let mut points = Vec::new();
        for [y0, z0, y1, z1] in rectangles {
            let (columns, rows) = (((y1 - y0) / 0.0025) as usize, ((z1 - z0) / 0.0025) as usize);
            for i in 0..columns {
                for j in 0..rows {
                    let (y, z) = (y0 + (i as f64 + 0.5) * 0.0025, z0 + (j as f64 + 0.5) * 0.0025);
                    points.push(Point3::new(1.0, y as f32, z as f32));
                }
            }
        }
        points
    }

    fn standing_out(points: &[Point3<f32>], target: Point3<f64>) -> Option<StandingOut> {
        let (centre, normal) = (Vector3::new(1.0, 0.1, 0.1), Vector3::x());
        // The widest tag in the home: 6 × 8 cm.
        out_of_reach_of_a_disc(points, &centre, &normal, 0.03, &target)
    }

    #[test]
    fn a_tag_beside_a_red_box_stands_out_of_it() {
        // An 8 × 6 cm tag (y 0.20..0.28) against the side of a 20 × 20 cm box (y 0..0.20), its
        // shorter side along the box's edge: the disc, 8 cm wide, takes 1.4 cm of it.
        let tag = [0.20, 0.07, 0.28, 0.13];
        let points = on_the_wall(&[[0.0, 0.0, 0.20, 0.20], tag]);
        let piece = standing_out(&points, Point3::new(1.0, 0.24, 0.10)).expect("the tag");
        let in_tag = |p: &Point3<f32>| p.y > 0.20 && (0.07..0.13).contains(&p.z);
        let tag_points = points.iter().filter(|p| in_tag(p)).count();
        let kept: Vec<&Point3<f32>> = piece.kept.iter().map(|&i| &points[i]).collect();
        assert!(kept.iter().all(|p| in_tag(p)), "only the tag's points");
        assert!(kept.len() >= tag_points * 3 / 4, "{} of the tag's {tag_points}", kept.len());
        assert!((piece.disc - 0.08).abs() < 1e-9, "a disc of {} m", piece.disc);
    }

    #[test]
    fn the_distance_transform_finds_every_cells_nearest_set_cell() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let grid = Grid { origin: [0.0, 0.0], columns: 23, rows: 17 };
        for share in [0.0, 0.02, 0.3, 0.9] {
            let set: Vec<bool> = (0..grid.cells()).map(|_| rng.random_bool(share)).collect();
            let fast = grid.squared_distances_to(&set);
            for (c, fast) in fast.iter().enumerate() {
                let [x, y] = grid.xy(c);
                let slow = (0..grid.cells())
                    .filter(|&n| set[n])
                    .map(|n| {
                        let [nx, ny] = grid.xy(n);
                        ((nx - x).pow(2) + (ny - y).pow(2)) as f64
                    })
                    .fold(f64::INFINITY, f64::min);
                if slow.is_finite() {
                    assert_eq!(*fast, slow, "cell {c}, {share} set");
                } else {
                    assert!(*fast >= FAR, "cell {c}: nothing is set");
                }
            }
        }
    }

    #[test]
    fn a_tag_standing_out_far_from_the_pointed_spot_is_not_the_one_pointed_at() {
        // The tag and box of the test above, the spot pointed at 6 cm inside the box's edge:
        // 7.4 cm from what the disc left of the tag, farther than its 4 cm radius.
        let points = on_the_wall(&[[0.0, 0.0, 0.20, 0.20], [0.20, 0.07, 0.28, 0.13]]);
        assert!(standing_out(&points, Point3::new(1.0, 0.14, 0.10)).is_none());
        // 2 cm inside it, 3.4 cm from it: where a strip of the tag may lie under the disc.
        assert!(standing_out(&points, Point3::new(1.0, 0.18, 0.10)).is_some());
    }

    #[test]
    fn a_box_alone_leaves_only_slivers_narrower_than_a_tag() {
        let points = on_the_wall(&[[0.0, 0.0, 0.20, 0.20]]);
        assert!(standing_out(&points, Point3::new(1.0, 0.19, 0.19)).is_none());
    }

    #[test]
    fn a_tag_inside_the_boxs_outline_has_no_shape_of_its_own() {
        // The box from the test above, the tag lying on it.
        let points = on_the_wall(&[[0.0, 0.0, 0.20, 0.20], [0.10, 0.06, 0.16, 0.14]]);
        assert!(standing_out(&points, Point3::new(1.0, 0.13, 0.10)).is_none());
    }
}
