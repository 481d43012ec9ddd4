//! What the synthesized-profile checks share: the pooled Welch PSD against its target in
//! octave bands.

use crate::base::signal::WelchPsd;

use super::CheckRow;

/// One row per octave band from 10 bins up to `n2`: the band mean of `psd / target(n)`
/// against 1. Hann, 50 % overlap: the average of K periodograms has relative sd
/// `sqrt((1 + 2 x 0.167^2) / K)` (Welch 1967); a band of b correlated bins counts as b / 3
/// independent ones; the window's smoothing of a falling spectrum biases by
/// `bias (df / n)^2` (`bias` 1 for n^-2, about 4 for n^-4). Tolerance: 5 sd + that bias.
pub(super) fn octave_rows(
    group: &str,
    what: &str,
    reference: &str,
    psd: &WelchPsd,
    target: impl Fn(f64) -> f64,
    n2: f64,
    bias: f64,
) -> Vec<CheckRow> {
    let sigma = ((1.0 + 2.0 * 0.167f64.powi(2)) / psd.segments as f64).sqrt();
    let df = psd.frequencies[0];
    let mut rows = Vec::new();
    let mut lo = 10.0 * df;
    while lo < n2 - 3.0 * df {
        let hi = (2.0 * lo).min(n2 - 3.0 * df);
        let ratios: Vec<f64> = psd
            .frequencies
            .iter()
            .zip(&psd.density)
            .filter(|(&n, _)| n >= lo && n < hi)
            .map(|(&n, &g)| g / target(n))
            .collect();
        let bins = ratios.len() as f64;
        rows.push(CheckRow::relative(
            group,
            format!(
                "Welch PSD / target{what}, n in [{lo:.3}, {hi:.3}) cycle/m, {} bins, {} segments",
                ratios.len(),
                psd.segments
            ),
            reference,
            1.0,
            ratios.iter().sum::<f64>() / bins,
            5.0 * sigma / (bins / 3.0).sqrt() + bias * (df / lo).powi(2),
        ));
        lo = hi;
    }
    rows
}
