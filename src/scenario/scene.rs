//! The 3D scene's values, resolved once: how many deflected shapes per update, and the
//! factor the deflections are drawn with (`docs/output.md` section 14).

use super::resolved::ResolvedVehicle;
use super::Scenario;
use crate::base::units::GRAVITY_M_S2;
use crate::error::{num, Error, Result};
use crate::record::SceneInfo;

/// Default of `output.scene_rate_hz`: smooth enough to follow a vehicle across a span
/// (a truck at 25 m/s moves 2.5 m between updates) at a small cost in file size.
pub const DEFAULT_SCENE_RATE_HZ: f64 = 10.0;

/// The expected peak deflection is drawn as this fraction of the span: visible at a
/// glance from a camera framing the whole bridge, far from touching the supports' feet.
pub const SCENE_PEAK_FRACTION_OF_SPAN: f64 = 1.0 / 30.0;

/// Reference weight when the scenario has no vehicle at all (ambient excitation only), N:
/// a 10 t truck, so that the factor stays that of a loaded bridge of the same stiffness.
pub const SCENE_FALLBACK_WEIGHT_N: f64 = 10_000.0 * GRAVITY_M_S2;

impl Scenario {
    /// The scene of the run, `None` when `output.scene_rate_hz` is 0.
    pub(super) fn resolve_scene(&self, vehicles: &[ResolvedVehicle]) -> Result<Option<SceneInfo>> {
        let rate_hz = self.output.scene_rate_hz.unwrap_or(DEFAULT_SCENE_RATE_HZ);
        if !(rate_hz.is_finite() && (0.0..=1e6).contains(&rate_hz)) {
            return Err(Error::invalid(
                "output.scene_rate_hz",
                num(rate_hz),
                "must be a finite rate in [0, 1e6] Hz (0: no scene)",
            ));
        }
        if rate_hz == 0.0 {
            return Ok(None);
        }
        let shape_rate_hz = self.output.bridge_state_rate_hz;
        let every_shapes = (shape_rate_hz / rate_hz).round().max(1.0) as u64;
        let listed_n = vehicles
            .iter()
            .map(|v| v.dynamics.gross_weight_n())
            .fold(0.0, f64::max);
        let traffic_n = match &self.traffic {
            Some(t) => t.heaviest_gross_weight_t("traffic")? * 1000.0 * GRAVITY_M_S2,
            None => 0.0,
        };
        let reference_n = match listed_n.max(traffic_n) {
            w if w > 0.0 => w,
            _ => SCENE_FALLBACK_WEIGHT_N,
        };
        // Static midspan deflection of a simply supported beam under a central point
        // load, P L^3 / (48 EI) (e.g. Timoshenko and Gere, Mechanics of Materials), on the
        // longest span: an upper bound for a continuous girder, whose spans are stiffer.
        let span_m = self.bridge.girder().longest_span_m();
        let expected_peak_m =
            reference_n * span_m.powi(3) / (48.0 * self.bridge.flexural_rigidity_n_m2);
        let listed_lanes = vehicles.iter().map(|v| v.lane + 1).max().unwrap_or(1);
        let traffic_lanes = self.traffic.as_ref().map_or(1, |t| t.lanes.len() as u32);
        Ok(Some(SceneInfo {
            every_shapes,
            rate_hz: shape_rate_hz / every_shapes as f64,
            exaggeration: exaggeration_for(span_m, expected_peak_m),
            expected_peak_m,
            lanes: listed_lanes.max(traffic_lanes).max(1),
        }))
    }
}

/// The factor that draws `peak_m` as about [`SCENE_PEAK_FRACTION_OF_SPAN`] of `span_m`,
/// rounded down to 1, 2 or 5 times a power of ten (a factor a reader takes in at once),
/// and at least 1.
pub fn exaggeration_for(span_m: f64, peak_m: f64) -> f64 {
    let ideal = SCENE_PEAK_FRACTION_OF_SPAN * span_m / peak_m;
    if !(ideal.is_finite() && ideal > 1.0) {
        return 1.0;
    }
    let decade = 10f64.powf(ideal.log10().floor());
    let mantissa = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|&m| m * decade <= ideal * (1.0 + 1e-12))
        .unwrap_or(1.0);
    mantissa * decade
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_is_the_largest_1_2_5_step_below_the_ideal() {
        // 30 m span, 4 mm: ideal 1 m / 4 mm = 250 -> 200.
        assert_eq!(exaggeration_for(30.0, 0.004), 200.0);
        // ideal exactly 500 -> 500; 999 -> 500; 1000 -> 1000; 1999 -> 1000.
        assert_eq!(exaggeration_for(30.0, 1.0 / 500.0), 500.0);
        assert_eq!(exaggeration_for(30.0, 1.0 / 999.0), 500.0);
        assert_eq!(exaggeration_for(30.0, 1.0 / 1000.0), 1000.0);
        assert_eq!(exaggeration_for(30.0, 1.0 / 1999.0), 1000.0);
        assert_eq!(exaggeration_for(30.0, 1.0 / 2000.0), 2000.0);
        // A peak already larger than the target, or none: drawn as it is.
        assert_eq!(exaggeration_for(30.0, 5.0), 1.0);
        assert_eq!(exaggeration_for(30.0, 0.0), 1.0);
    }

    #[test]
    fn default_scene_uses_the_heaviest_vehicle_and_every_second_shape() {
        let resolved = Scenario::default_scenario().resolve().unwrap();
        let scene = resolved.scene.expect("the scene is on by default");
        // 20 Hz shapes at 10 Hz: every second one.
        assert_eq!(scene.every_shapes, 2);
        assert_eq!(scene.rate_hz, 10.0);
        let s = &resolved.scenario;
        let heaviest = resolved
            .vehicles
            .iter()
            .map(|v| v.dynamics.gross_weight_n())
            .fold(0.0, f64::max);
        let l = s.bridge.length_m();
        let expected = heaviest * l * l * l / (48.0 * s.bridge.flexural_rigidity_n_m2);
        assert!((scene.expected_peak_m - expected).abs() <= 1e-12 * expected);
        // The factor draws the peak between a tenth and the whole of the target height
        // (a 1-2-5 step loses at most 2.5x).
        let drawn_m = scene.exaggeration * scene.expected_peak_m;
        let target_m = SCENE_PEAK_FRACTION_OF_SPAN * l;
        assert!(drawn_m <= target_m && drawn_m > target_m / 2.5, "{drawn_m}");
    }

    #[test]
    fn scene_rate_zero_turns_it_off_and_bad_rates_name_the_field() {
        let mut s = Scenario::default_scenario();
        s.output.scene_rate_hz = Some(0.0);
        assert!(s.resolve().unwrap().scene.is_none());
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            s.output.scene_rate_hz = Some(bad);
            let err = s.resolve().unwrap_err().to_string();
            assert!(err.contains("output.scene_rate_hz"), "{err}");
        }
    }
}
