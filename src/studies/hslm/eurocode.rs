//! The EN 1991-2 (2003) section 6.4.6 rules the HSLM study applies. The values are those
//! commonly quoted from the standard (its text was not at hand here; two independent
//! recollections agree); each is used where stated and printed in the summary.

/// Deck acceleration limits (m/s^2): ballasted track, direct fastening (EN 1990 A2.4.4.2.1).
pub const LIMIT_BALLASTED_M_S2: f64 = 3.5;
pub const LIMIT_DIRECT_FASTENING_M_S2: f64 = 5.0;

/// Modes to keep for the deck acceleration: every mode up to `max(30 Hz, 1.5 n0, n3)`
/// (6.4.6.3.3).
pub fn cutoff_frequency_hz(n0_hz: f64, n3_hz: f64) -> f64 {
    30.0f64.max(1.5 * n0_hz).max(n3_hz)
}

/// Dynamic factor for carefully maintained track, `Phi2 = 1.44 / (sqrt(L) - 0.2) + 0.82`,
/// within [1.00, 1.67] (6.4.5.2).
pub fn phi2(determinant_length_m: f64) -> f64 {
    (1.44 / (determinant_length_m.sqrt() - 0.2) + 0.82).clamp(1.0, 1.67)
}

/// Dynamic factor for standard track, `Phi3 = 2.16 / (sqrt(L) - 0.2) + 0.73`, within
/// [1.00, 2.00].
pub fn phi3(determinant_length_m: f64) -> f64 {
    (2.16 / (determinant_length_m.sqrt() - 0.2) + 0.73).clamp(1.0, 2.0)
}

/// Lower-bound damping (Table 6.6), as a ratio.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeckType {
    SteelComposite,
    PrestressedConcrete,
    ReinforcedConcrete,
}

impl DeckType {
    pub fn damping_ratio(self, span_m: f64) -> f64 {
        let short = (20.0 - span_m).max(0.0);
        let percent = match self {
            DeckType::SteelComposite => 0.5 + 0.125 * short,
            DeckType::PrestressedConcrete => 1.0 + 0.07 * short,
            DeckType::ReinforcedConcrete => 1.5 + 0.07 * short,
        };
        percent / 100.0
    }

    pub fn label(self) -> &'static str {
        match self {
            DeckType::SteelComposite => "steel or composite",
            DeckType::PrestressedConcrete => "prestressed concrete",
            DeckType::ReinforcedConcrete => "reinforced concrete",
        }
    }
}

/// Figure 6.10's band of first frequencies within which a span up to 200 km/h needs no
/// dynamic analysis: upper `94.76 L^-0.748`, lower `80 / L` (4-20 m) or `23.58 L^-0.592`
/// (20-100 m).
pub fn frequency_band_hz(span_m: f64) -> (f64, f64) {
    let lower = if span_m <= 20.0 {
        80.0 / span_m
    } else {
        23.58 * span_m.powf(-0.592)
    };
    (lower, 94.76 * span_m.powf(-0.748))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_and_bounds() {
        // Phi2 of a 15 m span: 1.44 / (3.873 - 0.2) + 0.82 = 1.212; Phi3 1.318.
        assert!((phi2(15.0) - 1.2120).abs() < 1e-3 && (phi3(15.0) - 1.3181).abs() < 1e-3);
        assert_eq!(phi2(1.0), 1.67);
        assert_eq!(phi3(1.0), 2.0);
        assert!((DeckType::PrestressedConcrete.damping_ratio(15.0) - 0.0135).abs() < 1e-12);
        assert!((DeckType::ReinforcedConcrete.damping_ratio(30.0) - 0.015).abs() < 1e-12);
        let (lo, hi) = frequency_band_hz(20.0);
        assert!(
            (lo - 4.0).abs() < 1e-12 && (hi - 10.0).abs() < 0.1,
            "{lo} {hi}"
        );
    }
}
