//! Units from key names: every physical scalar of a scenario carries its unit in its name
//! (`span_m`, `rate_hz`, `flexural_rigidity_n_m2`), so the schema's units are read from
//! the names, the one place they are written.

/// Name endings and their units, the longer ending first where one ends another
/// (`_n_s_m` before `_s_m`... before `_m`).
const SUFFIXES: &[(&str, &str)] = &[
    ("_n_m_rad", "N m/rad"),
    ("_n_s_m", "N s/m"),
    ("_kg_m2", "kg m^2"),
    ("_n_m2", "N m^2"),
    ("_m_s2", "m/s^2"),
    ("_cycles_m", "cycle/m"),
    ("_per_degc", "1/degC"),
    ("_per_hour", "1/h"),
    ("_per_c", "1/degC"),
    ("_kg_m", "kg/m"),
    ("_n_m", "N/m"),
    ("_m_s", "m/s"),
    ("_m3", "m^3"),
    ("_hz", "Hz"),
    ("_kg", "kg"),
    ("_ppm", "ppm"),
    ("_rad", "rad"),
    ("_db", "dB"),
    ("_hour", "h"),
    ("_samples", "samples"),
    ("_m", "m"),
    ("_s", "s"),
    ("_n", "N"),
    ("_t", "t"),
    ("_c", "degC"),
];

/// The unit that `key` names by its ending, if any (`speed_m_s` -> `m/s`).
pub fn unit_of(key: &str) -> Option<&'static str> {
    SUFFIXES
        .iter()
        .find(|(suffix, _)| key.len() > suffix.len() && key.ends_with(suffix))
        .map(|&(_, unit)| unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_ending_names_the_unit() {
        let cases = [
            ("span_m", Some("m")),
            ("speed_m_s", Some("m/s")),
            ("target_rms_m_s2", Some("m/s^2")),
            ("flexural_rigidity_n_m2", Some("N m^2")),
            ("pitch_inertia_kg_m2", Some("kg m^2")),
            ("mass_per_length_kg_m", Some("kg/m")),
            ("suspension_damping_n_s_m", Some("N s/m")),
            ("tyre_stiffness_n_m", Some("N/m")),
            ("rotational_n_m_rad", Some("N m/rad")),
            ("n1_cycles_m", Some("cycle/m")),
            ("gd_n0_m3", Some("m^3")),
            ("slope_above_knee_per_c", Some("1/degC")),
            ("bias_tempco_per_degc", Some("1/degC")),
            ("flow_per_hour", Some("1/h")),
            ("value_c", Some("degC")),
            ("mean_t", Some("t")),
            ("axle_loads_n", Some("N")),
            ("mean_burst_samples", Some("samples")),
            ("dt_s", Some("s")),
            ("rate_hz", Some("Hz")),
            ("gamma", None),
            ("elements", None),
            ("noise_rel", None),
            // An ending alone is no name.
            ("_m", None),
        ];
        for (key, unit) in cases {
            assert_eq!(unit_of(key), unit, "{key}");
        }
    }

    #[test]
    fn no_ending_hides_a_longer_one_listed_after_it() {
        for (i, (early, _)) in SUFFIXES.iter().enumerate() {
            for (late, _) in &SUFFIXES[i + 1..] {
                assert!(!late.ends_with(early), "{late} is listed after {early}");
            }
        }
    }
}
