//! FHWA 13-class vehicle classification from axle count, spacings, groups and weight.
//!
//! The classes are the FHWA definitions (Traffic Monitoring Guide 2016, Appendix C; the
//! "Scheme F" of older equipment). Field classifiers implement them with per-state decision
//! tables on axle count, spacings and, with WIM, weight. The thresholds below are typical
//! values of such Scheme F-style tables (the LTPP WIM rule set, FHWA-HRT-13-091, 2014, works
//! with spacing bins and weight splits of this kind), not copied from one official table:
//! 6.0 ft (motorcycle), 10.1 ft (car), 23.1 ft (longest 2-axle single unit, shorter than a
//! bus), 40 ft, and 8 / 12 kips gross separating light vehicles (alone or with a light
//! trailer) from trucks.
//! Trucks are told apart by their axle groups (spacing < 2.1 m): a single unit truck has a
//! steering group and one rear group, a tractor-trailer three or more groups, a multi-trailer
//! five or more (six-axle: four or more). This is a simplified table, approximate like every
//! axle-based scheme (buses against trucks, pickups with trailers, spread-axle trailers);
//! it answers `None` where it cannot decide.

use super::AxleGroup;

const FT_M: f64 = 0.3048;
const KIP_N: f64 = 4_448.221_615;

/// Longest motorcycle wheelbase, m (6.0 ft).
const MOTORCYCLE_MAX_SPACING_M: f64 = 6.0 * FT_M;
/// Longest passenger-car wheelbase, m (10.1 ft).
const CAR_MAX_SPACING_M: f64 = 10.1 * FT_M;
/// Longest wheelbase of a 2-axle single unit; buses are longer, m (23.1 ft).
const SINGLE_UNIT_MAX_SPACING_M: f64 = 23.1 * FT_M;
/// Longest plausible 2-axle wheelbase, m (40 ft).
const TWO_AXLE_MAX_SPACING_M: f64 = 40.0 * FT_M;
/// Heaviest 2-axle light vehicle (car, pickup, van), N (8 kips, 3.6 t).
const LIGHT_MAX_GROSS_N: f64 = 8.0 * KIP_N;
/// Heaviest light vehicle towing a light trailer, N (12 kips, 5.4 t).
const LIGHT_TOWING_MAX_GROSS_N: f64 = 12.0 * KIP_N;

/// FHWA class (1-13) of a vehicle with measured spacings `axle_spacing_m`, axle groups
/// `groups` and gross weight `gross_weight_n`; `None` where the table cannot decide (one
/// axle, implausible spacing or grouping).
pub fn fhwa_class(axle_spacing_m: &[f64], groups: &[AxleGroup], gross_weight_n: f64) -> Option<u8> {
    let axle_count = axle_spacing_m.len() + 1;
    let first_spacing_m = *axle_spacing_m.first()?;
    if axle_spacing_m.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    match axle_count {
        2 => two_axle_class(first_spacing_m, gross_weight_n),
        3 | 4 if gross_weight_n < LIGHT_TOWING_MAX_GROSS_N => light_class(first_spacing_m),
        3 => three_axle_class(first_spacing_m, groups),
        4 => Some(if groups.len() <= 2 { 7 } else { 8 }),
        5 => Some(match groups.len() {
            0..=2 => 7,
            3 | 4 => 9,
            _ => 11,
        }),
        6 => Some(match groups.len() {
            0..=2 => 7,
            3 => 10,
            _ => 12,
        }),
        _ => Some(match groups.len() {
            0..=2 => 7,
            3 => 10,
            _ => 13,
        }),
    }
}

/// Classes 1-5 by wheelbase and weight.
fn two_axle_class(spacing_m: f64, gross_weight_n: f64) -> Option<u8> {
    if spacing_m < MOTORCYCLE_MAX_SPACING_M {
        return Some(1);
    }
    if spacing_m > TWO_AXLE_MAX_SPACING_M {
        return None;
    }
    if gross_weight_n < LIGHT_MAX_GROSS_N {
        return light_class(spacing_m);
    }
    Some(if spacing_m > SINGLE_UNIT_MAX_SPACING_M {
        4
    } else {
        5
    })
}

/// A car (2) or pickup/van (3), alone or with a light trailer, by its wheelbase.
fn light_class(first_spacing_m: f64) -> Option<u8> {
    if first_spacing_m < CAR_MAX_SPACING_M {
        Some(2)
    } else if first_spacing_m <= SINGLE_UNIT_MAX_SPACING_M {
        Some(3)
    } else {
        None
    }
}

/// Heavy 3-axle vehicles: bus (4), single unit (6), tractor with a 1-axle semitrailer (8).
fn three_axle_class(first_spacing_m: f64, groups: &[AxleGroup]) -> Option<u8> {
    let sizes: Vec<usize> = groups.iter().map(|g| g.axle_count).collect();
    match sizes.as_slice() {
        [1, 2] if first_spacing_m > SINGLE_UNIT_MAX_SPACING_M => Some(4),
        [1, 2] | [2, 1] => Some(6),
        [1, 1, 1] => Some(8),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::groups::{axle_groups, GROUP_SPACING_MAX_M};
    use super::*;

    const TONNE_N: f64 = 9_810.0;

    fn class_of(spacings_m: &[f64], gross_t: f64) -> Option<u8> {
        let loads = vec![gross_t * TONNE_N / (spacings_m.len() + 1) as f64; spacings_m.len() + 1];
        let groups = axle_groups(spacings_m, &loads, GROUP_SPACING_MAX_M);
        fhwa_class(spacings_m, &groups, gross_t * TONNE_N)
    }

    #[test]
    fn common_vehicles_get_their_textbook_class() {
        assert_eq!(class_of(&[1.45], 0.3), Some(1), "motorcycle");
        assert_eq!(class_of(&[2.70], 1.5), Some(2), "car");
        assert_eq!(class_of(&[3.40], 2.6), Some(3), "pickup");
        assert_eq!(class_of(&[5.53], 15.0), Some(5), "2-axle truck");
        assert_eq!(class_of(&[7.60], 16.0), Some(4), "2-axle bus");
        assert_eq!(class_of(&[4.50, 1.35], 24.0), Some(6), "3-axle rigid");
        assert_eq!(
            class_of(&[2.70, 3.50], 2.2),
            Some(2),
            "car + 1-axle trailer"
        );
        assert_eq!(
            class_of(&[1.95, 4.2, 1.35], 32.0),
            Some(7),
            "8x4 tipper 2-2"
        );
        assert_eq!(class_of(&[3.6, 6.5, 1.3], 30.0), Some(8), "2-S2");
        assert_eq!(class_of(&[3.24, 5.43, 1.20, 1.21], 40.0), Some(9), "2-S3");
        assert_eq!(class_of(&[3.8, 1.35, 7.5, 1.3], 40.0), Some(9), "3-S2");
        assert_eq!(
            class_of(&[3.8, 1.35, 6.0, 1.3, 1.3], 44.0),
            Some(10),
            "3-S3"
        );
        assert_eq!(class_of(&[3.3, 6.8, 2.8, 6.8], 36.0), Some(11), "2-S1-2");
        assert_eq!(
            class_of(&[3.8, 1.35, 6.8, 2.8, 6.8], 40.0),
            Some(12),
            "3-S1-2"
        );
        assert_eq!(
            class_of(&[3.8, 1.35, 6.8, 2.8, 6.8, 2.8, 6.8], 50.0),
            Some(13),
            "triple"
        );
    }

    #[test]
    fn undecidable_vehicles_get_none() {
        assert_eq!(class_of(&[], 1.0), None, "one axle");
        assert_eq!(class_of(&[13.0], 20.0), None, "wheelbase over 40 ft");
        assert_eq!(class_of(&[1.3, 1.3], 20.0), None, "a lone tridem");
    }
}
