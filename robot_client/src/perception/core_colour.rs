//! The colour of a red region's part nearest the target, and the region's points of it: the
//! first division of a red region larger than any tag ([`super::bounded_tag`]), and how the
//! tag's own pixels are told from what the search joined to them.

use nalgebra::Point3;
use rustc_hash::FxHashMap;

use super::voxel_coords::cube_of;

/// How far a point's colour may lie from the tag's, in standard deviations of the tag's own
/// colour: three hold all but 0.3 % of its pixels.
const COLOUR_SPREAD_SIGMAS: f32 = 3.0;

/// The median distance of two-dimensional normal noise from its middle, over its standard
/// deviation along each axis (the Rayleigh distribution's median, √(2 ln 2)): a spread that the
/// few odd points a core may hold do not inflate.
const MEDIAN_DISTANCE_PER_SIGMA: f32 = 1.1774;

/// The points of the tag's colour, and that colour's spread.
pub(super) struct ColourSplit {
    pub kept: Vec<Point3<f32>>,
    /// The core's standard deviation of colour, a distance on the chroma disc.
    pub spread: f32,
}

/// The colour of some points: the median of theirs on the chroma disc, and its spread.
pub(super) struct ColourOf {
    pub middle: [f32; 2],
    /// A robust standard deviation, a distance on the chroma disc.
    pub spread: f32,
}

impl ColourOf {
    /// The colour of the points `which`; `None` when fewer than half of them are in the
    /// picture.
    pub fn of(colours: &[Option<[f32; 2]>], which: &[usize]) -> Option<Self> {
        let theirs: Vec<[f32; 2]> = which.iter().filter_map(|&i| colours[i]).collect();
        if theirs.len() < which.len() / 2 || theirs.is_empty() {
            return None;
        }
        let middle = [median(theirs.iter().map(|c| c[0])), median(theirs.iter().map(|c| c[1]))];
        let distance = |c: &[f32; 2]| (c[0] - middle[0]).hypot(c[1] - middle[1]);
        let spread = median(theirs.iter().map(distance)) / MEDIAN_DISTANCE_PER_SIGMA;
        Some(Self { middle, spread })
    }

    /// Whether `colour` is this colour: within `COLOUR_SPREAD_SIGMAS` of its spreads.
    pub fn holds(&self, colour: [f32; 2]) -> bool {
        let distance = (colour[0] - self.middle[0]).hypot(colour[1] - self.middle[1]);
        distance <= COLOUR_SPREAD_SIGMAS * self.spread
    }
}

/// The points whose colour in the image is the colour of the `core` points (within
/// `COLOUR_SPREAD_SIGMAS` robust standard deviations of the core's median on the chroma disc)
/// and that lie in a voxel (of edge `voxel_size`) most of whose points have it. A red thing of
/// nearly the tag's colour has pixels of it scattered all over, as the camera's noise takes a
/// few of its pixels across the line; kept, they would join the tag to the whole red thing,
/// while the tag's own voxels are all of its colour. `None` when that keeps them all, or too
/// few of the core are in the picture.
pub(super) fn tag_coloured(
    points: &[Point3<f32>],
    colours: &[Option<[f32; 2]>],
    core: &[usize],
    voxel_size: f32,
) -> Option<ColourSplit> {
    let colour = ColourOf::of(colours, core)?;
    let kept = of_a_colour(points, colours, |c| colour.holds(c), voxel_size);
    (kept.len() < points.len()).then_some(ColourSplit { kept, spread: colour.spread })
}

/// The points whose colour `holds` and that lie in a voxel (of edge `voxel_size`) most of
/// whose points have such a colour: the camera's noise scatters a few pixels of a colour over
/// a thing of another, and the thing's own voxels are all of its colour.
pub(super) fn of_a_colour(
    points: &[Point3<f32>],
    colours: &[Option<[f32; 2]>],
    holds: impl Fn([f32; 2]) -> bool,
    voxel_size: f32,
) -> Vec<Point3<f32>> {
    let of_colour: Vec<bool> = colours.iter().map(|c| c.is_some_and(&holds)).collect();
    // Per voxel: its points, and those of the colour.
    let mut voxels: FxHashMap<[i64; 3], (u32, u32)> = FxHashMap::default();
    for (p, &is) in points.iter().zip(&of_colour) {
        let voxel = voxels.entry(cube_of(p, voxel_size)).or_default();
        voxel.0 += 1;
        voxel.1 += u32::from(is);
    }
    let mostly_of_colour = |p: &Point3<f32>| {
        let (all, of) = voxels[&cube_of(p, voxel_size)];
        2 * of > all
    };
    points
        .iter()
        .zip(&of_colour)
        .filter(|(p, is)| **is && mostly_of_colour(p))
        .map(|(p, _)| *p)
        .collect()
}

fn median(values: impl Iterator<Item = f32>) -> f32 {
    let mut values: Vec<f32> = values.collect();
    values.sort_by(f32::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f32::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 6 × 6 cm tag (y < 0) against the side of a box 20 cm wide and 40 cm tall (y ≥ 0), on
    /// the plane x = 1, 16 points a 1 cm voxel.
    fn tag_and_box() -> (Vec<Point3<f32>>, Vec<Point3<f32>>) {
        let (mut tag, mut red_box) = (Vec::new(), Vec::new());
        let at = |k: i32| k as f32 * 0.0025 + 0.00125;
        for i in -24..80 {
            for j in -80..80 {
                let p = Point3::new(1.0, at(i), at(j));
                if p.y < 0.0 && p.z.abs() < 0.03 {
                    tag.push(p);
                } else if p.y >= 0.0 {
                    red_box.push(p);
                }
            }
        }
        (tag, red_box)
    }

    #[test]
    fn a_red_things_pixels_of_the_tags_colour_scattered_over_it_are_not_the_tags() {
        // The tag's colour at 0.77 on the disc's red axis; a red box beside it 0.06 away, and
        // one pixel in four of the box of the tag's colour, as a camera's noise takes some.
        let (tag, red_box) = tag_and_box();
        let mut colours: Vec<Option<[f32; 2]>> = tag.iter().map(|_| Some([0.77, 0.0])).collect();
        for (k, _) in red_box.iter().enumerate() {
            colours.push(Some(if k % 4 == 0 { [0.77, 0.0] } else { [0.71, 0.0] }));
        }
        let all: Vec<Point3<f32>> = tag.iter().chain(&red_box).copied().collect();
        let core: Vec<usize> = (0..tag.len()).filter(|&i| tag[i].y < -0.04).collect();
        let split = tag_coloured(&all, &colours, &core, 0.01).expect("divided");
        let of_the_box = split.kept.iter().filter(|p| p.y >= 0.0).count();
        assert_eq!(of_the_box, 0, "scattered pixels of the box were kept");
        assert_eq!(split.kept.len(), tag.len());
    }
}
