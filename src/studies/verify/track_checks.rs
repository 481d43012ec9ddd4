//! Track irregularity synthesis: the closed-form band variance of each spectrum against a
//! numerical integral of its PSD, the RMS of generated tracks against it, and their Welch
//! PSD against the target in octave bands.

use std::f64::consts::PI;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::base::signal::{welch_psd, WelchPsd};
use crate::error::{Error, Result};
use crate::physics::road::{
    RoadProfile, RoadProfileSpec, TrackClass, DEFAULT_SAMPLE_SPACING_M, DEFAULT_TRACK_N1_CYCLES_M,
    DEFAULT_TRACK_N2_CYCLES_M,
};

use super::spectra::octave_rows;
use super::CheckRow;

const GROUP: &str = "track";

/// `G(n) = 2 pi S(2 pi n)`: the PSD per cycle/m (m^3).
fn g(class: TrackClass, n: f64) -> f64 {
    2.0 * PI * class.psd_m2_per_rad_m(2.0 * PI * n)
}

/// `integral of G(n)^p dn` over [a, b] by the midpoint rule on a log grid.
fn integral(class: TrackClass, a: f64, b: f64, p: i32) -> f64 {
    let m = 100_000;
    let h = (b / a).ln() / m as f64;
    (0..m)
        .map(|i| {
            let n = (a.ln() + (i as f64 + 0.5) * h).exp();
            g(class, n).powi(p) * n * h
        })
        .sum()
}

/// The track spectra: band variance, generated RMS, Welch PSD.
pub fn track_profiles() -> Result<Vec<CheckRow>> {
    let (n1, n2, dx) = (
        DEFAULT_TRACK_N1_CYCLES_M,
        DEFAULT_TRACK_N2_CYCLES_M,
        DEFAULT_SAMPLE_SPACING_M,
    );
    let (length_m, seeds, segment) = (4000.0, 8u64, 4096usize);
    let mut rows = Vec::new();
    for class in [
        TrackClass::Fra4,
        TrackClass::Fra6,
        TrackClass::GermanLow,
        TrackClass::GermanHigh,
    ] {
        let target = class.band_variance_m2(n1, n2);
        // Midpoint rule, 1e5 points on a log grid: relative error ~ h^2 / 24 ~ 1e-10.
        let numeric = integral(class, n1, n2, 1);
        rows.push(CheckRow::relative(
            GROUP,
            format!("band variance, {}", class.label()),
            "integral of the PSD, midpoint rule (m^2)",
            numeric,
            target,
            1e-8,
        ));
        let mut mean_square_ratio = 0.0;
        let mut pooled: Option<WelchPsd> = None;
        for seed in 0..seeds {
            let mut rng = ChaCha8Rng::seed_from_u64(1900 + 10 * class as u64 + seed);
            let spec = RoadProfileSpec::Track {
                class,
                n1_cycles_m: n1,
                n2_cycles_m: n2,
                sample_spacing_m: dx,
                features: Vec::new(),
            };
            let profile = RoadProfile::build(&spec, 0.0, length_m, &mut rng)?;
            let z: Vec<f64> = profile.sample_points().map(|(_, z)| z).collect();
            mean_square_ratio +=
                z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64 / target / seeds as f64;
            let psd = welch_psd(&z, dx, segment)?;
            match &mut pooled {
                None => pooled = Some(psd),
                Some(total) => total.merge(&psd)?,
            }
        }
        // The mean square of one window of length T of a Gaussian process with one-sided
        // PSD G has relative variance (1/T) int G^2 / (int G)^2; 4 sd of the mean of the
        // seeds, halved for the RMS.
        let rel_var = integral(class, n1, n2, 2) / (length_m * numeric * numeric);
        rows.push(CheckRow::relative(
            GROUP,
            format!(
                "rms of {seeds} tracks x {} km, {}",
                length_m / 1e3,
                class.label()
            ),
            "sqrt of the band variance (m)",
            target.sqrt(),
            (target * mean_square_ratio).sqrt(),
            0.5 * 4.0 * (rel_var / seeds as f64).sqrt(),
        ));
        if class == TrackClass::GermanLow {
            let psd = pooled.ok_or_else(|| Error::invalid("seeds", 0, "must be positive"))?;
            let what = format!(", {}", class.label());
            let target = |n| g(class, n);
            // The spectrum falls as n^-4 above Omega_c: window bias 4 (df / n)^2.
            rows.extend(octave_rows(
                GROUP,
                &what,
                "G(n) = 2 pi S(2 pi n)",
                &psd,
                target,
                n2,
                4.0,
            ));
        }
    }
    Ok(rows)
}
