//! RFID reads from a log-distance path-loss model: every tag within range of an antenna may
//! answer, with noisy RSSI, so a neighbouring tag can be heard as the paper saw (up to ~50 cm).

use nalgebra::{Point3, Vector3};
use rand::Rng;

use super::noise::gaussian;
use super::room::Device;
use crate::hal::{AntennaId, TagRead};

/// The radio link's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RfidModel {
    /// RSSI at 10 cm, on the antenna's boresight, tag facing the antenna, dBm.
    pub rssi_at_10cm: f64,
    /// Path-loss exponent (2 in free space; more near furniture and walls).
    pub path_loss_exponent: f64,
    /// Weakest reply the reader decodes, dBm.
    pub sensitivity: f64,
    /// Standard deviation of each read's RSSI (multipath, orientation), dB.
    pub noise_db: f64,
}

impl Default for RfidModel {
    fn default() -> Self {
        Self { rssi_at_10cm: -40.0, path_loss_exponent: 2.5, sensitivity: -60.0, noise_db: 2.0 }
    }
}

/// An antenna in the world: where it is and where it points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Antenna {
    pub id: AntennaId,
    pub position: Point3<f64>,
    /// Unit boresight direction.
    pub boresight: Vector3<f64>,
}

impl RfidModel {
    /// Mean RSSI of `device`'s tag at `antenna`, dBm, before noise.
    pub fn mean_rssi(&self, antenna: &Antenna, device: &Device) -> f64 {
        let to_tag = device.tag_center - antenna.position;
        let d = to_tag.norm().max(0.01);
        let dir = to_tag / d;
        // Patch antennas and tags lose gain off their axes; neither goes fully deaf.
        let antenna_gain = 10.0 * antenna.boresight.dot(&dir).max(0.05).log10();
        let tag_gain = 5.0 * device.tag_normal.dot(&-dir).max(0.1).log10();
        self.rssi_at_10cm - 10.0 * self.path_loss_exponent * (d / 0.1).log10()
            + antenna_gain
            + tag_gain
    }

    /// One inventory round: every tag each antenna decodes, once per antenna.
    pub fn inventory(
        &self,
        antennas: &[Antenna],
        devices: &[Device],
        rng: &mut impl Rng,
    ) -> Vec<TagRead> {
        let mut reads = Vec::new();
        for antenna in antennas {
            for device in devices {
                let rssi = self.mean_rssi(antenna, device) + self.noise_db * gaussian(rng);
                if rssi >= self.sensitivity {
                    reads.push(TagRead {
                        epc: device.epc.clone(),
                        rssi_dbm: (rssi * 2.0).round() / 2.0,
                        antenna: antenna.id,
                    });
                }
            }
        }
        reads
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::room::DeviceKind;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn tag_at(x: f64) -> Device {
        Device {
            kind: DeviceKind::Lamp,
            epc: DeviceKind::Lamp.epc(),
            tag_center: Point3::new(x, 0.0, 1.0),
            tag_normal: -Vector3::x(),
        }
    }

    #[test]
    fn reads_reach_about_half_a_metre() {
        let model = RfidModel::default();
        let antenna = Antenna {
            id: AntennaId(0),
            position: Point3::new(0.0, 0.0, 1.0),
            boresight: Vector3::x(),
        };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let rate = |x: f64, rng: &mut ChaCha8Rng| {
            (0..200).filter(|_| !model.inventory(&[antenna], &[tag_at(x)], rng).is_empty()).count()
        };
        assert_eq!(rate(0.1, &mut rng), 200);
        assert!(rate(0.45, &mut rng) > 100, "usually read at 45 cm");
        assert!(rate(1.0, &mut rng) < 5, "rarely at a metre");
    }
}
