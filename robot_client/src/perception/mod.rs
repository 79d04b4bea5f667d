//! Perception: finding a PPS-tag in a registered colour image and laser cloud (paper §III-B),
//! and telling from brightness whether a light changed (§IV-B.2.b).
//!
//! The steps, in the paper's order: [`segment_color`] (HSV thresholds with hue wrap-around),
//! [`Mask::fill_holes`], [`Mask::close`], [`Mask::open`], [`points_on_mask`] (project the cloud
//! into the segmented image), [`OccupancyGrid`] (1 cm³), its connected components, and the one
//! closest to the target; [`locate_tag`] runs them all. It projects the cloud first
//! ([`ProjectedCloud`]) and segments only the red regions laser points fall on
//! ([`segment_seeded`]): the mask is only ever read where a point lands.
//!
//! [`cloud_from_depth`] turns an RGB-D camera's aligned depth image into the same cloud.
//!
//! Perception works on data, never on devices: it takes images and clouds, not traits, and it
//! never touches the simulator, so recorded data from a real robot runs through the same code.

mod blobs;
mod bounded_tag;
mod brightness;
mod core_colour;
mod depth_cloud;
mod depth_noise;
mod edge_strips;
pub(crate) mod flood_fill;
mod hsv;
mod mask;
mod occupancy;
mod organised_cloud;
mod projection;
mod ray_smoothing;
mod seeded_segmentation;
mod tag;
mod tag_against_a_side;
mod tag_bound;
mod tag_colour_stats;
mod tag_colours;
mod tag_extent;
mod tag_search_params;
mod tag_shape;
mod tag_sighting;
mod two_clusters;
mod two_colours;
mod unmistakable_red;
pub(crate) mod voxel_coords;

pub use blobs::Blobs;
pub use brightness::{BrightnessChange, LightChange, brightness_change};
pub use depth_cloud::{
    DepthEncoding, DepthImage, DepthRange, DepthSizeMismatch, PixelWindow, cloud_from_depth,
    cloud_from_depth_in,
};
pub use depth_noise::{DepthNoise, NotADepthNoise};
pub use hsv::{HsvThresholds, ThresholdError, chroma_point, hsv_of, segment_color};
pub use mask::Mask;
pub use occupancy::{Component, OccupancyGrid};
pub use organised_cloud::{OrganisedCloud, organised_cloud_from_depth_in};
pub use projection::{OcclusionTest, ProjectedCloud, Reach, points_on_mask};
pub use ray_smoothing::RaySmoothing;
pub use seeded_segmentation::segment_seeded;
pub use tag::{PerceptionError, TagSearch, locate_tag, search_tag};
pub use tag_colour_stats::tag_color;
pub use tag_colours::{covering_colour, describe_colour};
pub use tag_extent::tag_size;
pub use tag_search_params::TagSearchParams;
pub use tag_sighting::{TagDetection, TagSighting};
pub use unmistakable_red::UNMISTAKABLE_HUES;
