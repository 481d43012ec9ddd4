//! Statistics over the road realisations of one case: percentiles, the DLC spread per
//! axle, and the static peak the bridge DAF is measured against.

use crate::error::Result;
use crate::physics::bridge::{unit_load_deflection_m_per_n, BeamProperties, BridgeModel};
use crate::physics::vehicle::VehicleDynamics;

use super::{simulate_crossing, Crossing, DlcSetup, Surface};

/// Mean and percentiles of one statistic over the realisations of a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    pub mean: f64,
    /// 5th percentile (linear interpolation between order statistics, Hyndman-Fan type 7).
    pub p5: f64,
    pub p95: f64,
    pub max: f64,
}

impl Spread {
    /// Over `values` (at least one).
    pub fn of(values: &[f64]) -> Spread {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let pct = |p: f64| {
            let h = p * (sorted.len() - 1) as f64;
            let lo = h.floor() as usize;
            let hi = (lo + 1).min(sorted.len() - 1);
            sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
        };
        Spread {
            mean: sorted.iter().sum::<f64>() / sorted.len() as f64,
            p5: pct(0.05),
            p95: pct(0.95),
            max: sorted[sorted.len() - 1],
        }
    }
}

/// The statistics of one (surface, speed) case.
#[derive(Debug, Clone)]
pub struct DlcCase {
    pub surface: Surface,
    pub speed_m_s: f64,
    pub crossings: Vec<Crossing>,
    /// DLC per axle (front, rear).
    pub dlc: [Spread; 2],
    pub sigma_ratio: [Spread; 2],
    /// Midspan deflection DAF against the static peak.
    pub daf: Spread,
    /// Crossings in which a tyre force went negative (contact lost under a real tyre).
    pub crossings_with_tension: usize,
}

/// Runs `realisations` crossings (one for the smooth road) of `surface` at `speed_m_s`.
pub fn run_case(
    setup: &DlcSetup,
    model: &BridgeModel,
    vehicle: &VehicleDynamics,
    surface: Surface,
    speed_m_s: f64,
    realisations: usize,
) -> Result<DlcCase> {
    let count = if surface == Surface::Smooth {
        1
    } else {
        realisations.max(1)
    };
    let static_peak_m = static_peak_midspan_m(&setup.beam, vehicle);
    let mut crossings = Vec::with_capacity(count);
    for r in 0..count {
        let road = setup.road(surface, r)?;
        crossings.push(simulate_crossing(
            setup, model, vehicle, &road, speed_m_s, 0.0,
        )?);
    }
    let per = |f: &dyn Fn(&Crossing) -> f64| -> Spread {
        Spread::of(&crossings.iter().map(f).collect::<Vec<_>>())
    };
    Ok(DlcCase {
        surface,
        speed_m_s,
        dlc: [per(&|c| c.dlc[0]), per(&|c| c.dlc[1])],
        sigma_ratio: [per(&|c| c.sigma_ratio[0]), per(&|c| c.sigma_ratio[1])],
        daf: per(&|c| c.peak_deflection_m / static_peak_m),
        crossings_with_tension: crossings
            .iter()
            .filter(|c| c.min_ratio.iter().any(|&m| m < 0.0))
            .count(),
        crossings,
    })
}

/// Largest static midspan deflection (m, down) as the axles' static loads roll across a
/// uniform beam: the closed-form influence line (docs/physics.md section 2), scanned at 1 cm.
pub fn static_peak_midspan_m(beam: &BeamProperties, vehicle: &VehicleDynamics) -> f64 {
    let l = beam.length_m();
    let positions = ((l + vehicle.wheelbase_m()) / 0.01).ceil() as usize;
    (0..=positions)
        .map(|i| {
            let front = i as f64 * 0.01;
            vehicle
                .axles
                .iter()
                .map(|a| {
                    let x = front - a.offset_m;
                    if (0.0..=l).contains(&x) {
                        a.static_load_n * unit_load_deflection_m_per_n(beam, 0.5 * l, x)
                    } else {
                        0.0
                    }
                })
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// `|a - b| / |b|`.
pub(super) fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_order_statistics() {
        let values: Vec<f64> = (0..=20).map(f64::from).collect();
        let s = Spread::of(&values);
        // Type 7 on 0..=20: p = 0.05 -> rank 1.0, p = 0.95 -> rank 19.0 exactly.
        assert!((s.p5 - 1.0).abs() < 1e-12 && (s.p95 - 19.0).abs() < 1e-12);
        assert_eq!((s.mean, s.max), (10.0, 20.0));
    }

    #[test]
    fn static_peak_of_one_load_is_pl3_over_48ei() {
        // A single axle: the peak is at midspan, P L^3 / (48 EI) (docs/physics.md section 1).
        let beam = BeamProperties::paper_default();
        let force = VehicleDynamics::moving_forces(&[1e5], &[0.0]);
        let expected = 1e5 * 30f64.powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
        assert!((static_peak_midspan_m(&beam, &force) - expected).abs() < 1e-12 * expected);
    }
}
