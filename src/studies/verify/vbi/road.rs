//! ISO 8608 road synthesis: band RMS, generated RMS and the Welch PSD against the target.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::base::signal::{welch_psd, WelchPsd};
use crate::error::{Error, Result};
use crate::physics::road::{
    iso8608_band_rms_m, iso8608_psd_m3, IsoClass, RoadProfile, RoadProfileSpec,
    DEFAULT_N1_CYCLES_M, DEFAULT_N2_CYCLES_M, DEFAULT_SAMPLE_SPACING_M,
};
use crate::studies::verify::CheckRow;

/// ISO 8608 synthesis: the closed-form band RMS against docs/physics.md's table, the RMS of
/// generated profiles (classes A-D, 8 seeds of 4 km each) against it, and the Welch PSD
/// of all 32 profiles (each divided by its class's sqrt(G_d(n0))) against the target in
/// octave bands.
pub fn road_profiles() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_road";
    let (n1, n2, dx) = (
        DEFAULT_N1_CYCLES_M,
        DEFAULT_N2_CYCLES_M,
        DEFAULT_SAMPLE_SPACING_M,
    );
    let (length_m, seeds, segment) = (4000.0, 8u64, 4096usize);
    let mut rows = Vec::new();
    // Relative sd of the mean square of one window of length T of a stationary process
    // with one-sided PSD G ~ n^-2 on [n1, n2] (Gaussian approximation, as in
    // tests/suite/road_profiles.rs): var = (1/T) int G^2 / (int G)^2
    // = (1/3)(n1^-3 - n2^-3) / (T (1/n1 - 1/n2)^2), i.e. 1 / sqrt(3 T n1) = 9.1 %.
    let rel_var_one =
        (n1.powi(-3) - n2.powi(-3)) / (3.0 * length_m * (1.0 / n1 - 1.0 / n2).powi(2));
    let mut pooled_psd: Option<WelchPsd> = None;
    for (class, table_mm) in [
        (IsoClass::A, 3.99),
        (IsoClass::B, 7.99),
        (IsoClass::C, 15.98),
        (IsoClass::D, 31.96),
    ] {
        let gd = class.gd_n0_m3();
        let target_m = iso8608_band_rms_m(gd, n1, n2);
        // The table is rounded to 0.01 mm.
        rows.push(CheckRow::with_error(
            GROUP,
            format!("band rms class {}", class.letter()),
            "docs/physics.md table (mm)",
            table_mm,
            1e3 * target_m,
            (1e3 * target_m - table_mm).abs(),
            0.005,
        ));
        let mut mean_square_ratio = 0.0;
        for seed in 0..seeds {
            let mut rng = ChaCha8Rng::seed_from_u64(100 * class.gd_n0_micro_m3() as u64 + seed);
            let profile =
                RoadProfile::build(&RoadProfileSpec::iso8608(class), 0.0, length_m, &mut rng)?;
            let z: Vec<f64> = profile.sample_points().map(|(_, z)| z).collect();
            let ms = z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64;
            mean_square_ratio += ms / (target_m * target_m) / seeds as f64;
            let normalised: Vec<f64> = z.iter().map(|v| v / gd.sqrt()).collect();
            let psd = welch_psd(&normalised, dx, segment)?;
            match &mut pooled_psd {
                None => pooled_psd = Some(psd),
                Some(total) => total.merge(&psd)?,
            }
        }
        // 4 sd of the mean of 8 windows in mean square, halved for the RMS: 6.5 %.
        let tolerance = 0.5 * 4.0 * (rel_var_one / seeds as f64).sqrt();
        rows.push(CheckRow::relative(
            GROUP,
            format!(
                "rms of {seeds} profiles x {} km, class {}",
                length_m / 1e3,
                class.letter()
            ),
            "sqrt(G_d(n0) n0^2 (1/n1 - 1/n2)) (m)",
            target_m,
            target_m * mean_square_ratio.sqrt(),
            tolerance,
        ));
    }
    let psd = pooled_psd.ok_or_else(|| Error::invalid("seeds", 0, "must be positive"))?;
    rows.extend(crate::studies::verify::spectra::octave_rows(
        GROUP,
        "",
        "G_d(n) / G_d (1)",
        &psd,
        |n| iso8608_psd_m3(1.0, n),
        n2,
        1.0,
    ));
    Ok(rows)
}
