//! Axle groups and the axle pattern ("1-1-3") a WIM system derives from axle spacings.

/// Largest spacing between two axles of one group, m: axles closer than this form a tandem
/// or tridem (docs/sensors.md section 3; EU Directive 96/53/EC also counts axles under 2.0 m as
/// a tandem, 1.3-1.8 m being typical).
pub const GROUP_SPACING_MAX_M: f64 = 2.1;

pub use crate::record::AxleGroup;

/// Groups of axles with loads `axle_load_n` and spacings `axle_spacing_m` (one fewer): a
/// spacing strictly below `group_spacing_max_m` joins two axles into one group.
///
/// # Panics
/// If `axle_spacing_m.len() + 1 != axle_load_n.len()` (a caller bug).
pub fn axle_groups(
    axle_spacing_m: &[f64],
    axle_load_n: &[f64],
    group_spacing_max_m: f64,
) -> Vec<AxleGroup> {
    assert_eq!(
        axle_spacing_m.len() + 1,
        axle_load_n.len(),
        "one spacing fewer than axles"
    );
    let mut groups: Vec<AxleGroup> = Vec::new();
    for (i, &load_n) in axle_load_n.iter().enumerate() {
        let joins_previous = i > 0 && axle_spacing_m[i - 1] < group_spacing_max_m;
        match groups.last_mut() {
            Some(group) if joins_previous => {
                group.axle_count += 1;
                group.load_n += load_n;
            }
            _ => groups.push(AxleGroup {
                first_axle: i,
                axle_count: 1,
                load_n,
            }),
        }
    }
    groups
}

/// The axle pattern, group sizes front to rear joined by `-` ("1-1-3").
pub fn axle_pattern(groups: &[AxleGroup]) -> String {
    groups
        .iter()
        .map(|g| g.axle_count.to_string())
        .collect::<Vec<_>>()
        .join("-")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn five_axle_tractor_with_tridem_is_1_1_3() {
        // docs/sensors.md section 4 spacings.
        let groups = axle_groups(
            &[3.24, 5.43, 1.20, 1.21],
            &[60e3, 100e3, 70e3, 71e3, 72e3],
            GROUP_SPACING_MAX_M,
        );
        assert_eq!(axle_pattern(&groups), "1-1-3");
        assert_eq!(groups[2].first_axle, 2);
        assert_eq!(groups[2].axles(), 2..5);
        assert_eq!(groups[2].load_n, 213e3);
    }

    #[test]
    fn boundary_spacing_starts_a_new_group() {
        // "< 2.1 m" is strict: 2.1 m apart are two single axles.
        let groups = axle_groups(&[2.1, 2.0999], &[1.0, 1.0, 1.0], GROUP_SPACING_MAX_M);
        assert_eq!(axle_pattern(&groups), "1-2");
    }

    #[test]
    fn one_axle_is_one_group() {
        let groups = axle_groups(&[], &[5.0], GROUP_SPACING_MAX_M);
        assert_eq!(axle_pattern(&groups), "1");
    }
}
