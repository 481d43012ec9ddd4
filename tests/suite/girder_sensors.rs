//! The sensors that watch a girder's supports: load cells (support reactions) and
//! inclinometers (rotation), against statics on slow crossings of a moving force, where
//! the dynamic part is small and bounded (the tolerances below say by how much).

use bridgetwin::record::AxleState;
use bridgetwin::sim::Record;

use crate::common::{records_of, sensor_samples, shape_reactions as reactions};

/// A moving force of `force_n` crossing a girder at `speed_m_s` from 1 m before it, every
/// output at the solver's 100 Hz; `bridge` and `sensors` are TOML.
fn slow_crossing(bridge: &str, sensors: &str, force_n: f64, speed_m_s: f64) -> String {
    format!(
        r#"
seed = 3
[bridge]
{bridge}
damping_ratio = 0.05
[solver]
dt_s = 0.01
[road]
profile = {{ kind = "smooth" }}
approach_m = 1.0
exit_m = 2.0
[output]
bridge_state_rate_hz = 100.0
axle_load_rate_hz = 100.0
[[vehicles]]
model = {{ kind = "moving_force", axle_loads_n = [{force_n}] }}
speed_m_s = {speed_m_s}
{sensors}
"#
    )
}

/// `[[sensors]]` tables: a load cell at each of `positions_m`, 100 Hz, noise-free.
fn load_cells(positions_m: &[f64]) -> String {
    positions_m
        .iter()
        .enumerate()
        .map(|(i, x)| {
            format!(
                "[[sensors]]\nid = \"R{i}\"\nkind = \"load_cell\"\nposition_m = {x}\n\
                 rate_hz = 100.0\nnoise_density = 0.0\n"
            )
        })
        .collect()
}

/// (t ns, axles) of every `/truth/axle_loads` record.
fn axle_loads(records: &[Record]) -> Vec<(u64, Vec<AxleState>)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::AxleLoads { t_ns, axles } => Some((*t_ns, axles.clone())),
            _ => None,
        })
        .collect()
}

const THREE_SPANS: &str = r#"spans_m = [24.0, 30.0, 24.0]
supports = ["pinned", "roller", "roller", "roller"]
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
model = { kind = "finite_element", elements = 78 }"#;

#[test]
fn reactions_balance_the_load_at_every_step_of_a_slow_crossing() {
    // 100 kN at 1 m/s over 24 + 30 + 24 m: the speed parameter v / (2 f1 L) is 0.003, so
    // the inertia forces are a few 1e-3 of the load; the largest, 3.7e-3, just after the
    // force steps onto the girder at the abutment (a suddenly applied load). The static
    // balance sum R = P holds to that at every one of the 8000 steps.
    let force_n = 1e5;
    let records = records_of(&slow_crossing(
        THREE_SPANS,
        &load_cells(&[0.0, 24.0, 54.0, 78.0]),
        force_n,
        1.0,
    ));
    let shapes = reactions(&records);
    let loads = axle_loads(&records);
    assert_eq!(shapes.len(), loads.len());
    assert!(shapes.len() > 7900, "{} shapes", shapes.len());
    let mut worst = 0.0f64;
    for ((t, r), (t_axles, axles)) in shapes.iter().zip(&loads) {
        assert_eq!(t, t_axles);
        assert_eq!(r.len(), 4, "one reaction per support");
        let on_girder: f64 = axles
            .iter()
            .filter(|a| (0.0..=78.0).contains(&a.position_m))
            .map(|a| a.force_n)
            .sum();
        let sum: f64 = r.iter().sum();
        worst = worst.max((sum - on_girder).abs() / force_n);
    }
    assert!(
        worst < 5e-3,
        "sum of reactions off the load by {worst:.2e} of it"
    );
    // The load cells read the same reactions (their samples fall on solver steps).
    for (i, cell) in (0..4).map(|i| (i, sensor_samples(&records, i))) {
        assert!(cell.len() > 7900, "R{i}: {} samples", cell.len());
        for (t, _, measured, truth) in &cell {
            let (_, r) = shapes
                .iter()
                .find(|(ts, _)| ts == t)
                .unwrap_or_else(|| panic!("no shape at {t} ns"));
            assert_eq!(truth.reaction_n, r[i], "R{i} at {t} ns");
            assert_eq!(*measured, Some(r[i]), "R{i}: ideal chain");
        }
    }
}

/// The interior reaction of two equal spans `l` under a unit load at `a` (from the left
/// end), three-moment equation: `M_B = -a (l^2 - a^2) / (4 l^2)` for a load in span one,
/// `R_B = a / l - 2 M_B / l`; mirrored for span two.
fn pier_reaction_two_spans(a: f64, l: f64) -> f64 {
    let a = if a <= l { a } else { 2.0 * l - a };
    if !(0.0..=l).contains(&a) {
        return 0.0;
    }
    let m_b = -a * (l * l - a * a) / (4.0 * l * l);
    a / l - 2.0 * m_b / l
}

/// The largest error of the pier's load cell against the three-moment influence line
/// over a slow crossing of two 20 m spans with the pier given by `pier`, relative to
/// the load.
fn pier_error(pier: &str) -> f64 {
    let bridge = format!(
        "spans_m = [20.0, 20.0]\nsupports = [\"pinned\", {pier}, \"roller\"]\n\
         flexural_rigidity_n_m2 = 5.629e10\nmass_per_length_kg_m = 12000.0\n\
         model = {{ kind = \"finite_element\", elements = 40 }}"
    );
    let force_n = 2e5;
    let records = records_of(&slow_crossing(&bridge, &load_cells(&[20.0]), force_n, 1.0));
    let loads = axle_loads(&records);
    let cell = sensor_samples(&records, 0);
    let mut worst = 0.0f64;
    for (t, _, _, truth) in &cell {
        let Some(a) = loads
            .iter()
            .find(|(ta, _)| ta == t)
            .and_then(|(_, axles)| axles.first())
        else {
            continue;
        };
        let expected = force_n * pier_reaction_two_spans(a.position_m, 20.0);
        worst = worst.max((truth.reaction_n - expected).abs() / force_n);
    }
    worst
}

#[test]
fn a_pier_load_cell_follows_the_three_moment_influence_line() {
    // Finite elements are exact for a point load at statics; what is left is the inertia
    // of a crossing at 1 m/s (speed parameter 0.004): 1.5e-3 of the load measured.
    let rigid = pier_error("\"roller\"");
    assert!(rigid < 4e-3, "rigid pier: {rigid:.2e} of the load");
    // Negative control: on a soft pier (1e8 N/m: it settles 2 mm under the load) the
    // rigid-support influence line is wrong by far more than the tolerance.
    let soft = pier_error("{ elastic = { vertical_n_m = 1e8, rotational_n_m_rad = 0.0 } }");
    assert!(soft > 10.0 * 4e-3, "soft pier: {soft:.2e} of the load");
}

#[test]
fn a_bearing_inclinometer_reads_the_end_rotation_of_statics() {
    // One 30 m span, P at a: the left end rotates by P a b (L + b) / (6 EI L) (b = L - a),
    // with the deflection growing towards +x: positive. Slow crossing (speed parameter
    // 0.007): the dynamic part is within 1 % of the peak rotation.
    let (l, ei, force_n) = (30.0, 5.629e10, 2e5);
    let bridge = format!(
        "span_m = {l}\nflexural_rigidity_n_m2 = {ei}\nmass_per_length_kg_m = 12000.0\n\
         model = {{ kind = \"finite_element\", elements = 30 }}"
    );
    let sensors = "[[sensors]]\nid = \"T0\"\nkind = \"inclinometer\"\nposition_m = 0.0\n\
                   rate_hz = 100.0\nnoise_density = 0.0\n";
    let records = records_of(&slow_crossing(&bridge, sensors, force_n, 1.0));
    let loads = axle_loads(&records);
    let peak = force_n * l * l / (9.0 * 3f64.sqrt() * ei);
    let mut worst = 0.0f64;
    let mut worst_flipped = 0.0f64;
    for (t, _, measured, truth) in sensor_samples(&records, 0) {
        let Some(a) = loads
            .iter()
            .find(|(ta, _)| *ta == t)
            .and_then(|(_, axles)| axles.first())
            .map(|a| a.position_m)
        else {
            continue;
        };
        let expected = match (0.0..=l).contains(&a) {
            true => force_n * a * (l - a) * (2.0 * l - a) / (6.0 * ei * l),
            false => 0.0,
        };
        assert_eq!(measured, Some(truth.rotation_rad));
        worst = worst.max((truth.rotation_rad - expected).abs() / peak);
        worst_flipped = worst_flipped.max((-truth.rotation_rad - expected).abs() / peak);
    }
    assert!(worst < 1e-2, "end rotation off by {worst:.2e} of its peak");
    // The sign is tested too: the opposite convention misses by twice the peak.
    assert!(worst_flipped > 1.9, "{worst_flipped}");
}
