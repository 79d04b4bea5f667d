//! How wrong a user's noise model may be: the RGB-D scenes keep their sensor's true noise while
//! perception is given another model (the datasheet's σ scaled, or none at all, i.e. the
//! laser's), and each model's scenes are judged as the corpus test judges them. A measurement,
//! not a test: each scene is rendered once and perceived once per model.

use pps_robot::navigation::{ApproachParams, plan_approach};
use pps_robot::perception::DepthNoise;

use crate::{DeviceKind, RgbdVariants, generate_rgbd, judge};

/// The noise model perception is given for a scene whose sensor has its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GivenModel {
    /// The sensor's model with its growth with range (σ at 1 m, the datasheet's figure) times
    /// this; the floor, the surfaces' own texture, stays.
    Scaled(f64),
    /// No camera model: the laser's, as a user who names no depth camera gives.
    Laser,
}

impl GivenModel {
    pub fn applied_to(self, truth: DepthNoise) -> DepthNoise {
        match self {
            Self::Scaled(factor) => DepthNoise { growth: truth.growth * factor, ..truth },
            Self::Laser => DepthNoise::LASER,
        }
    }

    pub fn label(self) -> String {
        match self {
            Self::Scaled(factor) => format!("×{factor}"),
            Self::Laser => "laser".to_string(),
        }
    }
}

/// A scene some model got wrong, and what was wrong.
#[derive(Debug, Clone)]
pub struct Miss {
    pub kind: DeviceKind,
    pub seed: u64,
    pub model: GivenModel,
    pub problems: String,
    /// The scene's drawn parameters, as the corpus test prints them.
    pub scene: String,
}

/// Per model (in the order given) and per device kind (in the order of [`DeviceKind::ALL`]), how many
/// of the scenes were right, and every miss.
#[derive(Debug, Clone)]
pub struct Sensitivity {
    pub models: Vec<GivenModel>,
    pub per_kind: u64,
    pub right: Vec<[u64; DeviceKind::ALL.len()]>,
    pub misses: Vec<Miss>,
}

/// Renders seeds `0..per_kind` of every kind with `variants` and perceives each with every model.
pub fn measure(per_kind: u64, variants: RgbdVariants, models: &[GivenModel]) -> Sensitivity {
    let mut right = vec![[0; DeviceKind::ALL.len()]; models.len()];
    let mut misses = Vec::new();
    for (k, &kind) in DeviceKind::ALL.iter().enumerate() {
        for seed in 0..per_kind {
            let scene = generate_rgbd(seed, Some(kind), variants);
            let truth = scene.depth_noise();
            for (m, &model) in models.iter().enumerate() {
                let params = ApproachParams {
                    depth_noise: model.applied_to(truth),
                    ..ApproachParams::default()
                };
                let plan = plan_approach(
                    &scene.image,
                    &scene.cloud,
                    &scene.calibration,
                    &scene.target,
                    &params,
                );
                let problems = match plan {
                    Ok(plan) => judge(scene.truth(), &plan).problems.join(", "),
                    Err(e) => format!("perception failed: {e}"),
                };
                if problems.is_empty() {
                    right[m][k] += 1;
                } else {
                    let scene = scene.parameters().summary();
                    misses.push(Miss { kind, seed, model, problems, scene });
                }
            }
        }
    }
    Sensitivity { models: models.to_vec(), per_kind, right, misses }
}

impl Sensitivity {
    /// The table in Markdown: a row per model, a column per kind, right of `per_kind`.
    pub fn table(&self) -> String {
        let kinds: Vec<&str> = DeviceKind::ALL.iter().map(|k| k.name()).collect();
        let mut out = format!("| model given | {} |\n", kinds.join(" | "));
        out += &format!("|---|{}\n", "---|".repeat(kinds.len()));
        for (model, right) in self.models.iter().zip(&self.right) {
            let cells: Vec<String> = right.iter().map(|r| r.to_string()).collect();
            out += &format!("| {} | {} |\n", model.label(), cells.join(" | "));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scaled_model_scales_only_the_growth_with_range() {
        let truth = DepthNoise::from_one_metre(0.004);
        let doubled = GivenModel::Scaled(2.0).applied_to(truth);
        assert_eq!(doubled.floor, truth.floor);
        assert!((doubled.sigma_at(3.0) - truth.floor - 2.0 * 0.004 * 9.0).abs() < 1e-12);
        assert_eq!(GivenModel::Laser.applied_to(truth), DepthNoise::LASER);
    }
}
