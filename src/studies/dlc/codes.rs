//! The design codes' impact factors the DLC is compared with (docs/physics.md section 8).

/// Impact factor `1 + mu` of the Chinese code JTG D60-2015 (docs/physics.md section 8):
/// mu = 0.05 below 1.5 Hz, `0.1767 ln f - 0.0157` from 1.5 to 14 Hz, 0.45 above.
pub fn china_jtg_d60_factor(f1_hz: f64) -> f64 {
    let mu = if f1_hz < 1.5 {
        0.05
    } else if f1_hz <= 14.0 {
        0.1767 * f1_hz.ln() - 0.0157
    } else {
        0.45
    };
    1.0 + mu
}

/// The design codes' allowed amplification at the bridge's f1 (the paper's Table 5;
/// the first three are the values those codes give for f1 = 3.78 Hz).
pub fn design_codes(f1_hz: f64) -> Vec<(&'static str, f64)> {
    vec![
        ("AASHTO", 1.33),
        ("Australia", 1.4),
        ("Switzerland", 1.8),
        ("China JTG D60", china_jtg_d60_factor(f1_hz)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chinese_factor_follows_jtg_d60() {
        // docs/physics.md section 8: 1.22 at 3.78 Hz (two decimals); the branches at the ends.
        assert!((china_jtg_d60_factor(3.78) - 1.22).abs() < 0.005);
        assert_eq!(china_jtg_d60_factor(1.0), 1.05);
        assert_eq!(china_jtg_d60_factor(20.0), 1.45);
    }
}
