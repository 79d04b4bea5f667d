//! Finger forces as the behaviours read them: every reading goes through a [`ForceRecorder`],
//! so what a behaviour decided on is also what the trial records.

use pps_schema::{ForceSample, MAX_FORCE_SAMPLES};
use time::OffsetDateTime;

use crate::hal::{Clock, Finger, FingerForceTorque, HalError};

/// One reading of both fingers' force magnitudes, newtons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerForces {
    pub left: f64,
    pub right: f64,
}

impl FingerForces {
    pub fn max(&self) -> f64 {
        self.left.max(self.right)
    }

    pub fn min(&self) -> f64 {
        self.left.min(self.right)
    }
}

/// Samples both fingers' force-torque sensors into trial samples, timed from `started`.
pub struct ForceRecorder<'a> {
    sensor: &'a dyn FingerForceTorque,
    clock: &'a dyn Clock,
    started: OffsetDateTime,
    samples: Vec<pps_schema::ForceSample>,
}

impl std::fmt::Debug for ForceRecorder<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ForceRecorder({} samples)", self.samples.len())
    }
}

impl<'a> ForceRecorder<'a> {
    pub fn new(
        sensor: &'a dyn FingerForceTorque,
        clock: &'a dyn Clock,
        started: OffsetDateTime,
    ) -> Self {
        Self { sensor, clock, started, samples: Vec::new() }
    }

    /// Reads both fingers, keeps the samples, and returns the force magnitudes.
    pub fn sample(&mut self) -> Result<FingerForces, HalError> {
        let t = (self.clock.now() - self.started).as_seconds_f64().max(0.0);
        let mut magnitude = [0.0; 2];
        for (i, (finger, name)) in
            [(Finger::Left, pps_schema::Finger::Left), (Finger::Right, pps_schema::Finger::Right)]
                .into_iter()
                .enumerate()
        {
            let wrench = self.sensor.wrench(finger)?;
            magnitude[i] = wrench.force_magnitude();
            // The cap keeps a long behaviour's trial within the registry's size limit.
            if self.samples.len() < MAX_FORCE_SAMPLES {
                self.samples.push(ForceSample {
                    t: (t * 1000.0).round() / 1000.0,
                    finger: name,
                    force: round3(wrench.force.into()),
                    torque: Some(round3(wrench.torque.into())),
                });
            }
        }
        Ok(FingerForces { left: magnitude[0], right: magnitude[1] })
    }

    pub fn into_samples(self) -> Vec<ForceSample> {
        self.samples
    }
}

fn round3(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| (x * 1000.0).round() / 1000.0)
}
