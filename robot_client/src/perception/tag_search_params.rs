//! What the tag search looks for: the knobs of the paper's §III-B, and how the home's own
//! tags and the depth sensor's noise bound them.

use pps_schema::TagSize;

use super::depth_noise::DepthNoise;
use super::hsv::HsvThresholds;
use super::projection::OcclusionTest;

/// The knobs of the tag search. The defaults are the paper's where it gives a number (1 cm
/// voxels) and EL-E-like otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct TagSearchParams {
    /// The tag's colour, from the entry's robot-specific `color_segmentation`.
    pub thresholds: HsvThresholds,
    /// Half-size of the square closing element, pixels: bridges folds and glints.
    pub close_radius_px: usize,
    /// Half-size of the square opening element, pixels: removes specks of noise.
    pub open_radius_px: usize,
    pub occlusion: OcclusionTest,
    /// Edge of the occupancy grid's voxels, metres.
    pub voxel_size: f32,
    /// Fewest laser points a red component needs to count as a tag, not a speck.
    pub min_points: usize,
    /// A tag further than this from the target (metres, to its nearest point) is not the one the
    /// person meant.
    pub max_distance: f64,
    /// Two tags whose distances to the target differ by less than this (metres) are ambiguous.
    pub ambiguity_margin: f64,
    /// Centroids closer than this (metres) are one tag cut in two by a depth step (its edge seen
    /// against the surface behind), never two tags.
    pub min_tag_separation: f64,
    /// Components in one red region of the image that come this near each other (metres) are
    /// fragments of one tag the laser sampled too sparsely to join in the grid.
    pub fragment_gap: f64,
    /// How far the largest tag in the home reaches from its middle (half its diagonal),
    /// metres: a red region reaching further is never a tag as a whole.
    pub max_tag_radius: f64,
    /// Half the narrower side of the widest tag in the home, metres, when the home's tags'
    /// sizes are known: a disc a little wider rolls over a red thing too large to be a tag and
    /// over none of a tag standing out of it ([`super::tag_shape`]).
    pub widest_tag_half_width: Option<f64>,
    /// The sizes of the home's tags, when registered: a tag lying against a red thing by a
    /// whole side is the rectangle of one of them ([`super::tag_against_a_side`]).
    pub home_tags: Vec<TagSize>,
}

impl Default for TagSearchParams {
    fn default() -> Self {
        Self {
            thresholds: HsvThresholds::default(),
            close_radius_px: 2,
            open_radius_px: 1,
            occlusion: OcclusionTest::default(),
            voxel_size: 0.01,
            min_points: 10,
            max_distance: 0.5,
            ambiguity_margin: 0.08,
            min_tag_separation: 0.12,
            fragment_gap: 0.03,
            // The largest tag of the paper's materials: a towel over a wide drawer's handle,
            // 60 × 35 cm and a fold 3 cm deep.
            max_tag_radius: 0.35,
            widest_tag_half_width: None,
            home_tags: Vec::new(),
        }
    }
}

impl TagSearchParams {
    /// These parameters bounded by the home's own tags, of `sizes`: a red region reaching
    /// further from its middle than the largest tag's half diagonal by more than a tag's own
    /// fragments may lie apart (`fragment_gap`) is never a tag as a whole, and the widest tag's
    /// half width sizes the disc that finds a tag standing out of such a region. Unchanged
    /// when no size is given, since an unknown tag may be as large as a towel.
    pub fn for_home_tags(&self, sizes: impl IntoIterator<Item = TagSize>) -> Self {
        let sizes: Vec<TagSize> = sizes
            .into_iter()
            .filter(|s| [s.width, s.height].iter().all(|x| x.is_finite() && *x > 0.0))
            .collect();
        let mut params = self.clone();
        if let Some(largest) = sizes.iter().map(TagSize::reach).reduce(f64::max) {
            params.max_tag_radius = largest + self.fragment_gap;
        }
        params.widest_tag_half_width =
            sizes.iter().map(|s| s.width.min(s.height) / 2.0).reduce(f64::max);
        params.home_tags = sizes;
        params
    }

    /// These parameters for depths scattering with standard deviation `sigma` (metres) about
    /// the target: the occlusion test lets a point lie as far behind its cell's nearest depth
    /// as two draws of the noise can part, and a tag's points reach as much further from its
    /// middle as the noise stretches them along the rays. Below the laser's noise, unchanged.
    pub fn for_depth_noise(&self, sigma: f64) -> Self {
        let mut params = self.clone();
        params.occlusion.tolerance = params.occlusion.tolerance.max((5.0 * sigma) as f32);
        let beyond_laser = (sigma - DepthNoise::LASER.floor).max(0.0);
        params.max_tag_radius = self.max_tag_radius + 3.0 * beyond_laser;
        params
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_homes_largest_tag_bounds_a_tag_and_no_size_leaves_the_towels() {
        let params = TagSearchParams::default();
        // A rocker's 5 × 8 cm patch and a flip switch's 4 × 3 cm tube.
        let patch = TagSize { width: 0.05, height: 0.08 };
        let tube = TagSize { width: 0.04, height: 0.03 };
        let small = params.for_home_tags([patch, tube]);
        assert!((small.max_tag_radius - (patch.reach() + params.fragment_gap)).abs() < 1e-12);
        assert_eq!(small.widest_tag_half_width, Some(0.025));
        assert_eq!(small.home_tags, vec![patch, tube]);
        assert_eq!(params.for_home_tags([]), params);
        assert_eq!(params.for_home_tags([TagSize { width: f64::NAN, height: 0.05 }]), params);
    }
}
