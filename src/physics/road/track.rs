//! Vertical railway track irregularity spectra: the FRA track classes and the German
//! high-speed spectra of low and high interference, one-sided PSDs `S(Omega)` in
//! m^2 / (rad/m) of the angular spatial frequency `Omega = 2 pi n`.
//!
//! - FRA (US Federal Railroad Administration), classes 1 (worst) to 6 (best):
//!   `S = k A_v Omega_c^2 / (Omega^2 (Omega^2 + Omega_c^2))`, k = 0.25,
//!   `Omega_c = 0.8245` rad/m, `A_v` = 1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339
//!   cm^2 rad/m (as given in TTB-2D's options, Cantero 2022, citing Berawi's thesis).
//! - German high-speed: `S = A_v Omega_c^2 / ((Omega^2 + Omega_r^2)(Omega^2 + Omega_c^2))`,
//!   `Omega_c = 0.8246`, `Omega_r = 0.0206` rad/m, `A_v` = 4.032e-7 m^2 rad/m (low
//!   interference, as in TTB-2D citing Guo, Xia, De Roeck & Liu 2012) and 1.080e-6 (high
//!   interference, the value widely quoted with it; not confirmed in a second source
//!   here).
//!
//! Both are rational in `Omega^2`, so their integral over a band is closed form (partial
//! fractions into `1/Omega^2` and `1/(Omega^2 + a^2)` terms): the synthesis gives each
//! FFT line exactly its bin's variance, as for ISO 8608.

use std::f64::consts::PI;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A track irregularity spectrum (`class` of `kind = "track"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TrackClass {
    #[serde(rename = "fra_1")]
    Fra1,
    #[serde(rename = "fra_2")]
    Fra2,
    #[serde(rename = "fra_3")]
    Fra3,
    #[serde(rename = "fra_4")]
    Fra4,
    #[serde(rename = "fra_5")]
    Fra5,
    #[serde(rename = "fra_6")]
    Fra6,
    GermanLow,
    GermanHigh,
}

const FRA_K: f64 = 0.25;
const FRA_OMEGA_C: f64 = 0.8245;
/// FRA `A_v` of classes 1-6 (cm^2 rad/m).
const FRA_AV_CM2: [f64; 6] = [1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339];
const GERMAN_OMEGA_C: f64 = 0.8246;
const GERMAN_OMEGA_R: f64 = 0.0206;

impl TrackClass {
    /// Every class, worst FRA first.
    pub const ALL: [TrackClass; 8] = [
        TrackClass::Fra1,
        TrackClass::Fra2,
        TrackClass::Fra3,
        TrackClass::Fra4,
        TrackClass::Fra5,
        TrackClass::Fra6,
        TrackClass::GermanLow,
        TrackClass::GermanHigh,
    ];

    /// "FRA class 4", "German high-speed, low interference".
    pub fn label(self) -> String {
        match self {
            TrackClass::GermanLow => "German high-speed spectrum, low interference".into(),
            TrackClass::GermanHigh => "German high-speed spectrum, high interference".into(),
            fra => format!("FRA class {}", fra as usize + 1),
        }
    }

    /// `S(Omega)`, m^2 / (rad/m).
    pub fn psd_m2_per_rad_m(self, omega: f64) -> f64 {
        let w2 = omega * omega;
        match self.german_av() {
            Some(av) => {
                let c2 = GERMAN_OMEGA_C * GERMAN_OMEGA_C;
                av * c2 / ((w2 + GERMAN_OMEGA_R * GERMAN_OMEGA_R) * (w2 + c2))
            }
            None => {
                let c2 = FRA_OMEGA_C * FRA_OMEGA_C;
                FRA_K * self.fra_av_m2() * c2 / (w2 * (w2 + c2))
            }
        }
    }

    /// The variance in the band `[a, b]` cycle/m (m^2): `integral of S dOmega` over
    /// `[2 pi a, 2 pi b]`, in closed form.
    pub fn band_variance_m2(self, a_cycles_m: f64, b_cycles_m: f64) -> f64 {
        let primitive = |omega: f64| match self.german_av() {
            // A c^2 / (c^2 - r^2) [1/(W^2 + r^2) - 1/(W^2 + c^2)].
            Some(av) => {
                let (c, r) = (GERMAN_OMEGA_C, GERMAN_OMEGA_R);
                av * c * c / (c * c - r * r) * ((omega / r).atan() / r - (omega / c).atan() / c)
            }
            // k A [1/W^2 - 1/(W^2 + c^2)].
            None => {
                let c = FRA_OMEGA_C;
                FRA_K * self.fra_av_m2() * (-1.0 / omega - (omega / c).atan() / c)
            }
        };
        primitive(2.0 * PI * b_cycles_m) - primitive(2.0 * PI * a_cycles_m)
    }

    fn german_av(self) -> Option<f64> {
        match self {
            TrackClass::GermanLow => Some(4.032e-7),
            TrackClass::GermanHigh => Some(1.080e-6),
            _ => None,
        }
    }

    /// FRA `A_v` in m^2 rad/m (only for FRA classes).
    fn fra_av_m2(self) -> f64 {
        FRA_AV_CM2[(self as usize).min(5)] * 1e-4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_variance_is_the_integral_of_the_psd() {
        // Against a midpoint rule on a log grid (relative error ~ h^2 / 24, 1e-9 at
        // 200 000 points).
        for class in TrackClass::ALL {
            let (a, b): (f64, f64) = (1.0 / 150.0, 1.0);
            let m = 200_000;
            let h = (b / a).ln() / m as f64;
            let numeric: f64 = (0..m)
                .map(|i| {
                    let n = (a.ln() + (i as f64 + 0.5) * h).exp();
                    class.psd_m2_per_rad_m(2.0 * PI * n) * 2.0 * PI * n * h
                })
                .sum();
            let closed = class.band_variance_m2(a, b);
            assert!(
                (closed / numeric - 1.0).abs() < 1e-8,
                "{class:?}: {closed} vs {numeric}"
            );
        }
    }

    #[test]
    fn classes_are_ordered_and_of_the_expected_size() {
        // FRA class 6 (the best) to 1 (the worst) grow; over 1-150 m wavelengths the
        // German low-interference track is about 2 mm RMS, a high-speed line.
        let rms: Vec<f64> = TrackClass::ALL
            .iter()
            .map(|c| c.band_variance_m2(1.0 / 150.0, 1.0).sqrt())
            .collect();
        for w in rms[..6].windows(2) {
            assert!(w[0] > w[1], "{rms:?}");
        }
        assert!((1e-3..4e-3).contains(&rms[6]), "{}", rms[6]);
        assert!(rms[7] > rms[6]);
    }
}
