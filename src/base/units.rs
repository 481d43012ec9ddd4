//! Physical constants shared by every layer, and units written for people.

/// Standard gravity used for all static loads and weights (m/s^2): the rounded 9.81 of
/// the paper and of the WIM and traffic literature it is compared with.
pub const GRAVITY_M_S2: f64 = 9.81;

/// A byte count for people: `950 B`, `12.3 KiB`, `812.4 MiB`, `8.9 GiB`, `1.2 TiB`
/// (binary prefixes, one decimal).
pub fn bytes_text(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_read_with_binary_prefixes() {
        assert_eq!(bytes_text(0), "0 B");
        assert_eq!(bytes_text(1023), "1023 B");
        assert_eq!(bytes_text(1024), "1.0 KiB");
        assert_eq!(bytes_text(5_000_000), "4.8 MiB");
        assert_eq!(bytes_text(9_556_302_848), "8.9 GiB");
        assert_eq!(bytes_text(3 << 40), "3.0 TiB");
    }
}
