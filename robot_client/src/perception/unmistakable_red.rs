//! The red no home material has (issue 34). The table of home materials
//! (`robot_client/scenes/FINDINGS.md`, "Home materials and the default colour") puts every
//! tag's red at hue 7.7° at most, under any light, and every wood, terracotta, brick, leather
//! and skin of saturation 0.6 or more at 12.3° and beyond; the factory colour, hue 340–20°,
//! lets them in under warm light. So where a red region larger than any tag has, nearest the
//! pointed location, a hue only such a material has, the person's pointing landed on the wood
//! beside the tag, and the colour anchored there would keep the wood and lose the tag: the
//! region is searched for its points of the red no material has instead.

use nalgebra::Point3;

use super::core_colour::{ColourOf, of_a_colour};
use super::hsv::{HsvThresholds, hue_of_chroma_point};
use super::two_colours::colours_around;
use crate::hal::{CameraCalibration, ColorImage};

/// The hues, degrees, of a tag's red and of no home material: midway between the tags' 7.7°
/// and the nearest material's 12.3° on one side; on the other, the factory colour's own edge.
pub const UNMISTAKABLE_HUES: [f64; 2] = [340.0, 10.0];

/// A region's points of the unmistakable red, and the hue of its part nearest the target.
pub(super) struct UnmistakablyRed {
    pub kept: Vec<Point3<f32>>,
    /// Degrees, 0..360.
    pub nearest_hue: f32,
}

/// `points`, of a red region, narrowed to those of the unmistakable red (hue within
/// [`UNMISTAKABLE_HUES`], saturation and value as `thresholds` take them, in voxels mostly of
/// it), when its points nearest the target (`core`) have a hue outside it and `thresholds`
/// take such hues at all. `None` otherwise: a household's learned colour lies within those
/// hues already, and a core of the tag's red, or of a red thing's, is divided as before.
/// `reach` is how many pixels around each point's own its colour is averaged over.
pub(super) fn unmistakably_red(
    points: &[Point3<f32>],
    core: &[usize],
    image: &ColorImage,
    calibration: &CameraCalibration,
    thresholds: &HsvThresholds,
    voxel_size: f32,
    reach: u32,
) -> Option<UnmistakablyRed> {
    let red = thresholds.with_hues(UNMISTAKABLE_HUES);
    if !thresholds.takes_more_hues_than(&red) {
        return None;
    }
    let core: Vec<Point3<f32>> = core.iter().map(|&i| points[i]).collect();
    let core_colours = colours_around(&core, image, calibration, reach);
    let everyone: Vec<usize> = (0..core.len()).collect();
    let nearest_hue = hue_of_chroma_point(ColourOf::of(&core_colours, &everyone)?.middle);
    if red.contains_hue(nearest_hue) {
        return None;
    }
    let colours = colours_around(points, image, calibration, reach);
    let kept = of_a_colour(points, &colours, |c| red.chroma_distance(c) == 0.0, voxel_size);
    (!kept.is_empty()).then_some(UnmistakablyRed { kept, nearest_hue })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::chroma_point;

    #[test]
    fn the_factory_colour_takes_more_hues_than_the_unmistakable_red_and_a_learned_one_not() {
        let factory = HsvThresholds::default();
        let red = factory.with_hues(UNMISTAKABLE_HUES);
        assert!(factory.takes_more_hues_than(&red));
        assert!(!red.takes_more_hues_than(&red));
        // A household's colour learned from its towels: 346–8°.
        assert!(!factory.with_hues([346.0, 8.0]).takes_more_hues_than(&red));
        // Every hue takes more than any range; a range wrapping the other way round does not.
        assert!(factory.with_hues([0.0, 360.0]).takes_more_hues_than(&red));
        assert!(!factory.with_hues([10.0, 340.0]).takes_more_hues_than(&red));
    }

    #[test]
    fn a_wood_and_a_tag_fall_either_side_of_the_unmistakable_hues() {
        let red = HsvThresholds::default().with_hues(UNMISTAKABLE_HUES);
        // An orange-brown plywood the factory colour lets in (hue 16°, saturation 0.74), and
        // the corpus's towel (hue 4°, saturation 0.85).
        let (wood, towel) = (chroma_point([175, 80, 45]), chroma_point([200, 30, 20]));
        assert!(HsvThresholds::default().contains([175, 80, 45]));
        assert!(!red.contains_hue(hue_of_chroma_point(wood)));
        assert_eq!(red.chroma_distance(towel), 0.0);
    }
}
