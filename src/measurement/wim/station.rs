//! A WIM station: one measurement record per vehicle passage.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::fhwa::fhwa_class;
use super::groups::{axle_groups, axle_pattern, GROUP_SPACING_MAX_M};
use super::physics::strip_errors;
use super::spec::{Model, WimLimits, WimModelSpec};
use crate::error::Result;
pub use crate::record::{AppliedErrors, LoadReference, WimMeasurement};

/// Flag: another vehicle was on the station at the same time.
pub const FLAG_MULTIPLE_PRESENCE: &str = "multiple_presence";
/// Flag: an axle load or the gross weight exceeds the station's capacity.
pub const FLAG_OFF_SCALE: &str = "off_scale";
/// Flag: the measured speed is below the station's low-speed limit.
pub const FLAG_LOW_SPEED: &str = "low_speed";

/// What the simulation knows about one vehicle crossing a station.
#[derive(Debug, Clone, PartialEq)]
pub struct WimPassage {
    pub vehicle_id: u32,
    /// Lane number, from 0.
    pub lane: u32,
    /// Time the first axle crossed the strip, ns since the run start.
    pub t_first_axle_ns: u64,
    /// True speed, m/s.
    pub speed_m_s: f64,
    /// True distances between consecutive axles, front to rear, m (one fewer than axles).
    pub axle_spacing_m: Vec<f64>,
    /// Static load of each axle, front to rear, N.
    pub static_axle_load_n: Vec<f64>,
    /// Dynamic tyre force of each axle as it crossed the strip, front to rear, N.
    pub dynamic_axle_load_n: Vec<f64>,
    /// Another vehicle was on the station at the same time (the simulation decides).
    pub multiple_presence: bool,
}

/// A validated station model with its flag limits.
#[derive(Debug, Clone, PartialEq)]
pub struct WimStation {
    model: Model,
    limits: WimLimits,
}

impl WimStation {
    /// A station with model `spec` and default [`WimLimits`]. Errors name
    /// `<field_prefix>.<field>` (e.g. `wim_stations.0.model.class`) and the value.
    pub fn new(spec: &WimModelSpec, field_prefix: &str) -> Result<Self> {
        Ok(Self {
            model: spec.validate(field_prefix)?,
            limits: WimLimits::default(),
        })
    }

    /// The same station with flag limits `limits`; errors name `<field_prefix>.<field>`.
    pub fn with_limits(mut self, limits: WimLimits, field_prefix: &str) -> Result<Self> {
        limits.validate(field_prefix)?;
        self.limits = limits;
        Ok(self)
    }

    /// The flag limits in force.
    pub fn limits(&self) -> &WimLimits {
        &self.limits
    }

    /// Measures one passage, drawing from `rng` (the station's own stream, e.g.
    /// `child_rng(seed, "wim/<id>")`). Draw order per vehicle: the speed error, then the
    /// model's load errors front to rear (`cost323`: gross, groups, axles), so the same
    /// seed and passages give the same records. `ideal` draws nothing.
    ///
    /// # Panics
    /// If the passage has no axle, or its spacings and loads do not have `n - 1`, `n`, `n`
    /// entries (a caller bug).
    pub fn measure(&self, passage: &WimPassage, rng: &mut ChaCha8Rng) -> WimMeasurement {
        check_shape(passage);
        let speed_rel = self.draw_speed_error(rng);
        let axle_spacing_m: Vec<f64> = passage
            .axle_spacing_m
            .iter()
            .map(|s| s * (1.0 + speed_rel))
            .collect();
        let (reference, axle_rel) = self.draw_load_errors(passage, &axle_spacing_m, rng);
        let reference_n = match reference {
            LoadReference::Static => &passage.static_axle_load_n,
            LoadReference::Dynamic => &passage.dynamic_axle_load_n,
        };
        let axle_load_n: Vec<f64> = reference_n
            .iter()
            .zip(&axle_rel)
            .map(|(load, e)| load * (1.0 + e))
            .collect();
        let speed_m_s = passage.speed_m_s * (1.0 + speed_rel);
        let gross_weight_n: f64 = axle_load_n.iter().sum();
        let reference_gross_n: f64 = reference_n.iter().sum();
        let groups = axle_groups(&axle_spacing_m, &axle_load_n, GROUP_SPACING_MAX_M);
        WimMeasurement {
            vehicle_id: passage.vehicle_id,
            lane: passage.lane,
            t_ns: passage.t_first_axle_ns,
            speed_m_s,
            axle_pattern: axle_pattern(&groups),
            fhwa_class: fhwa_class(&axle_spacing_m, &groups, gross_weight_n),
            flags: self.flags(passage, speed_m_s, &axle_load_n, gross_weight_n),
            groups,
            axle_spacing_m,
            axle_load_n,
            gross_weight_n,
            truth: AppliedErrors {
                reference,
                speed_rel,
                gross_rel: relative_error(gross_weight_n, reference_gross_n),
                axle_rel,
            },
        }
    }

    /// The relative speed error (the first draw of every vehicle; none for `ideal`).
    fn draw_speed_error(&self, rng: &mut ChaCha8Rng) -> f64 {
        match self.model {
            Model::Ideal => 0.0,
            Model::Cost323 {
                speed_sigma_rel, ..
            }
            | Model::Physics {
                speed_sigma_rel, ..
            } => speed_error(speed_sigma_rel, rng),
        }
    }

    /// The reference the load errors apply to and the relative error of each axle, drawn
    /// after the speed error. `cost323` groups the axles as the station sees them, from
    /// the measured spacings `axle_spacing_m`.
    fn draw_load_errors(
        &self,
        passage: &WimPassage,
        axle_spacing_m: &[f64],
        rng: &mut ChaCha8Rng,
    ) -> (LoadReference, Vec<f64>) {
        let axle_count = passage.static_axle_load_n.len();
        let mut axle_rel = Vec::with_capacity(axle_count);
        match self.model {
            Model::Ideal => {
                axle_rel.resize(axle_count, 0.0);
                (LoadReference::Dynamic, axle_rel)
            }
            Model::Cost323 { class, .. } => {
                let static_n = &passage.static_axle_load_n;
                let groups = axle_groups(axle_spacing_m, static_n, GROUP_SPACING_MAX_M);
                class.plan(static_n, &groups).draw(rng, &mut axle_rel);
                (LoadReference::Static, axle_rel)
            }
            Model::Physics { noise_rel, .. } => {
                strip_errors(axle_count, noise_rel, rng, &mut axle_rel);
                (LoadReference::Dynamic, axle_rel)
            }
        }
    }

    /// Flags in sorted order, judged on the measured values as a real station would.
    fn flags(
        &self,
        passage: &WimPassage,
        speed_m_s: f64,
        axle_load_n: &[f64],
        gross_weight_n: f64,
    ) -> Vec<&'static str> {
        let mut flags = Vec::new();
        if speed_m_s < self.limits.low_speed_m_s {
            flags.push(FLAG_LOW_SPEED);
        }
        if passage.multiple_presence {
            flags.push(FLAG_MULTIPLE_PRESENCE);
        }
        let axle_over = axle_load_n.iter().any(|l| *l > self.limits.axle_capacity_n);
        if axle_over || gross_weight_n > self.limits.gross_capacity_n {
            flags.push(FLAG_OFF_SCALE);
        }
        flags
    }
}

/// Relative speed error `sigma * z`: a speed trap times the vehicle between two sensors a
/// known distance apart, and the spacings are speed times the axles' time gaps, so they
/// carry the same relative error.
fn speed_error(sigma_rel: f64, rng: &mut ChaCha8Rng) -> f64 {
    let z: f64 = rng.sample(StandardNormal);
    sigma_rel * z
}

/// `measured / reference - 1`, and 0 when the reference is zero: a vehicle whose every
/// tyre is off the road at the strip has a zero dynamic reference, and its measured loads,
/// being the reference scaled, are zero too, so there is no error to report (0 / 0 would
/// put a NaN in the truth stream).
fn relative_error(measured: f64, reference: f64) -> f64 {
    if reference == 0.0 {
        0.0
    } else {
        measured / reference - 1.0
    }
}

fn check_shape(passage: &WimPassage) {
    let n = passage.static_axle_load_n.len();
    assert!(n >= 1, "vehicle {} has no axle", passage.vehicle_id);
    assert_eq!(
        passage.dynamic_axle_load_n.len(),
        n,
        "vehicle {}: one dynamic load per axle",
        passage.vehicle_id
    );
    assert_eq!(
        passage.axle_spacing_m.len() + 1,
        n,
        "vehicle {}: one spacing fewer than axles",
        passage.vehicle_id
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn truck(speed_m_s: f64, rear_axle_n: f64) -> WimPassage {
        WimPassage {
            vehicle_id: 7,
            lane: 1,
            t_first_axle_ns: 1_500_000_000,
            speed_m_s,
            axle_spacing_m: vec![5.5],
            static_axle_load_n: vec![50e3, rear_axle_n],
            dynamic_axle_load_n: vec![52e3, rear_axle_n * 0.95],
            multiple_presence: false,
        }
    }

    #[test]
    fn ideal_station_reports_the_dynamic_force_unchanged() {
        let station = WimStation::new(&WimModelSpec::Ideal, "m").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let m = station.measure(&truck(24.0, 100e3), &mut rng);
        assert_eq!(m.axle_load_n, vec![52e3, 95e3]);
        assert_eq!(m.gross_weight_n, 147e3);
        assert_eq!(m.speed_m_s, 24.0);
        assert_eq!(m.axle_spacing_m, vec![5.5]);
        assert_eq!(m.t_ns, 1_500_000_000);
        assert_eq!(m.axle_pattern, "1-1");
        assert_eq!(m.fhwa_class, Some(5));
        assert!(m.flags.is_empty());
        assert_eq!(m.truth.gross_rel, 0.0);
        assert_eq!(m.truth.reference, LoadReference::Dynamic);
    }

    #[test]
    fn a_vehicle_airborne_at_the_strip_has_no_gross_error() {
        // Found by the property test: a light vehicle on a class D road can have every
        // tyre off the road as it crosses the strip.
        let station = WimStation::new(&WimModelSpec::Ideal, "m").unwrap();
        let mut passage = truck(24.0, 100e3);
        passage.dynamic_axle_load_n = vec![0.0, 0.0];
        let m = station.measure(&passage, &mut ChaCha8Rng::seed_from_u64(3));
        assert_eq!(m.gross_weight_n, 0.0);
        assert_eq!(m.truth.gross_rel, 0.0);
        assert_eq!(m.truth.axle_rel, vec![0.0, 0.0]);
    }

    #[test]
    fn flags_follow_the_limits() {
        let station = WimStation::new(&WimModelSpec::Ideal, "m").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        // 2 m/s < 10 km/h; rear dynamic force 0.95 x 330 kN = 313.5 kN > 30 t x 9.81.
        let mut p = truck(2.0, 330e3);
        p.multiple_presence = true;
        let m = station.measure(&p, &mut rng);
        assert_eq!(m.flags, vec!["low_speed", "multiple_presence", "off_scale"]);
        // Raising the axle capacity clears off_scale; a gross cap of 300 kN sets it again.
        let limits = WimLimits {
            axle_capacity_n: 400e3,
            ..WimLimits::default()
        };
        let station = station.with_limits(limits, "l").unwrap();
        let m = station.measure(&truck(20.0, 330e3), &mut rng);
        assert!(m.flags.is_empty(), "{:?}", m.flags);
        let limits = WimLimits {
            gross_capacity_n: 300e3,
            ..limits
        };
        let station = station.with_limits(limits, "l").unwrap();
        let m = station.measure(&truck(20.0, 330e3), &mut rng);
        assert_eq!(m.flags, vec!["off_scale"]);
    }

    #[test]
    #[should_panic(expected = "one spacing fewer than axles")]
    fn inconsistent_passage_is_a_bug() {
        let station = WimStation::new(&WimModelSpec::Ideal, "m").unwrap();
        let mut p = truck(20.0, 100e3);
        p.axle_spacing_m.push(1.3);
        station.measure(&p, &mut ChaCha8Rng::seed_from_u64(0));
    }
}
