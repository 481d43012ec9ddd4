//! The supports' condition (`[[support_condition]]`): settlement against the closed forms
//! of a continuous beam's statics, bearing degradation and scour against the exact
//! frequencies of a beam on a softened support, and their announcements.

use bridgetwin::record::ModalRecord;
use bridgetwin::sim::Record;
use bridgetwin::studies::analytic::continuous_beam::{Condition, ContinuousBeam};

use crate::common::{records_of, sensor_samples, shape_reactions};

const EI: f64 = 5.629e10;
const MASS: f64 = 12000.0;

/// Two 20 m spans on `supports` (TOML list), `condition` (TOML tables), `sensors` (TOML
/// tables), no traffic, for `duration_s`.
fn two_spans(
    supports: &str,
    model: &str,
    condition: &str,
    sensors: &str,
    duration_s: f64,
) -> String {
    format!(
        r#"
seed = 1
duration_s = {duration_s}
[bridge]
spans_m = [20.0, 20.0]
supports = {supports}
flexural_rigidity_n_m2 = {EI}
mass_per_length_kg_m = {MASS}
model = {model}
[output]
bridge_state_rate_hz = 10.0
{condition}
{sensors}
"#
    )
}

/// (t s, support reactions) of every `/truth/bridge` shape.
fn reactions(records: &[Record]) -> Vec<(f64, Vec<f64>)> {
    shape_reactions(records)
        .into_iter()
        .map(|(t, r)| (t as f64 * 1e-9, r))
        .collect()
}

/// Every modal record, with its time (s).
fn modal_records(records: &[Record]) -> Vec<(f64, ModalRecord)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::BridgeShape {
                t_ns,
                modal: Some(m),
                ..
            } => Some((*t_ns as f64 * 1e-9, (**m).clone())),
            _ => None,
        })
        .collect()
}

fn events(records: &[Record]) -> Vec<(f64, String)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::Event { t_ns, text, .. } => Some((*t_ns as f64 * 1e-9, text.clone())),
            _ => None,
        })
        .collect()
}

const SENSORS: &str = r#"
[[sensors]]
id = "R_A"
kind = "load_cell"
position_m = 0.0
rate_hz = 10.0
noise_density = 0.0
[[sensors]]
id = "R_B"
kind = "load_cell"
position_m = 20.0
rate_hz = 10.0
noise_density = 0.0
[[sensors]]
id = "S_B"
kind = "strain"
position_m = 20.0
fibre = "top"
gauge_depth_m = 0.5
rate_hz = 10.0
noise_density = 0.0
[[sensors]]
id = "D_B"
kind = "displacement"
position_m = 20.0
rate_hz = 10.0
noise_density = 0.0
[[sensors]]
id = "T_A"
kind = "inclinometer"
position_m = 0.0
rate_hz = 10.0
noise_density = 0.0
"#;

#[test]
fn a_settled_pier_moves_the_reactions_and_moments_of_the_closed_form() {
    // Two equal spans L, the pier settling d: without it the girder would be a simple
    // beam of 2L, whose midspan deflects P (2L)^3 / 48EI under the pier's force P, so the
    // pier sheds R = 6 EI d / L^3 to the abutments (3 EI d / L^3 each) and its moment
    // rises by 3 EI d / L^2 (sagging). The left end rotates by the slope of that simple
    // beam, P (2L)^2 / 16 EI = 3 d / (2 L), the girder dipping towards the pier.
    // Cubic Hermite elements hold the exact field (piecewise cubic): round-off only.
    let (l, d) = (20.0f64, 0.01);
    let condition = "[[support_condition]]\nposition_m = 20.0\nkind = \"settlement\"\n\
                     settlement_m = 0.01\nonset_s = 1.0\n";
    for model in [
        "{ kind = \"finite_element\", elements = 40 }",
        "{ kind = \"modal\", modes = 10, elements = 40 }",
    ] {
        let records = records_of(&two_spans(
            "[\"pinned\", \"roller\", \"roller\"]",
            model,
            condition,
            SENSORS,
            2.0,
        ));
        let shed = 6.0 * EI * d / l.powi(3);
        let expected = [0.5 * shed, -shed, 0.5 * shed];
        for (t, r) in reactions(&records)
            .into_iter()
            .filter(|(_, r)| !r.is_empty())
        {
            let want = if t >= 1.0 { expected } else { [0.0; 3] };
            for (got, want) in r.iter().zip(want) {
                assert!(
                    (got - want).abs() <= 1e-9 * shed,
                    "{model} t {t}: {got} vs {want}"
                );
            }
        }
        let after = |i: usize| {
            sensor_samples(&records, i)
                .into_iter()
                .filter(|s| s.0 as f64 * 1e-9 >= 1.0)
                .map(|s| s.3)
                .collect::<Vec<_>>()
        };
        let moment = 3.0 * EI * d / (l * l);
        for q in after(2) {
            assert!(
                (q.moment_n_m - moment).abs() <= 1e-9 * moment,
                "{}",
                q.moment_n_m
            );
            // Top fibre, sagging: compression.
            let strain = -1e6 * 0.5 * moment / EI;
            assert!((q.strain_microstrain - strain).abs() <= 1e-9 * strain.abs());
        }
        for q in after(1) {
            assert!(
                (q.reaction_n + shed).abs() <= 1e-9 * shed,
                "{}",
                q.reaction_n
            );
        }
        for q in after(3) {
            assert!(
                (q.displacement_m - d).abs() <= 1e-12,
                "{}",
                q.displacement_m
            );
        }
        for q in after(4) {
            let rotation = 1.5 * d / l;
            assert!(
                (q.rotation_rad - rotation).abs() <= 1e-9 * rotation,
                "{}",
                q.rotation_rad
            );
        }
        let announced = events(&records)
            .into_iter()
            .filter(|(_, text)| text.starts_with("support_condition.0 begins"))
            .collect::<Vec<_>>();
        assert_eq!(announced.len(), 1, "{announced:?}");
        assert_eq!(announced[0].0, 1.0);
        assert!(
            announced[0].1.contains("settles 10 mm"),
            "{}",
            announced[0].1
        );
        let last = modal_records(&records).pop().expect("modal records");
        assert_eq!(last.1.support_settlement_m, [0.0, 0.01, 0.0]);
    }
}

#[test]
fn a_settled_end_of_a_simple_span_tilts_it_without_stress() {
    // A statically determinate girder follows a settlement as a rigid body: no moment, no
    // reaction; the midspan goes down by half of it. The negative control is the
    // continuous girder above, which does bend.
    let toml = r#"
seed = 1
duration_s = 2.0
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
[[support_condition]]
position_m = 0.0
kind = "settlement"
settlement_m = 0.02
onset_s = 0.5
growth = { kind = "linear", duration_s = 1.0 }
[[sensors]]
id = "D"
kind = "displacement"
position_m = 15.0
rate_hz = 10.0
noise_density = 0.0
[[sensors]]
id = "S"
kind = "strain"
position_m = 15.0
rate_hz = 10.0
noise_density = 0.0
"#;
    let records = records_of(toml);
    for (t, _, _, q) in sensor_samples(&records, 0) {
        let t = t as f64 * 1e-9;
        let progress = ((t - 0.5) / 1.0).clamp(0.0, 1.0);
        // Settlements are re-evaluated once a simulated second (as temperature and
        // damage): the reading holds the value of the last whole second.
        let evaluated = ((t.floor() - 0.5) / 1.0).clamp(0.0, 1.0);
        assert!(
            (q.displacement_m - 0.01 * evaluated).abs() <= 1e-12,
            "t {t}: {} (progress {progress})",
            q.displacement_m
        );
    }
    for (_, _, _, q) in sensor_samples(&records, 1) {
        assert!(
            q.strain_microstrain.abs() < 1e-9,
            "{}",
            q.strain_microstrain
        );
    }
    for (_, r) in reactions(&records) {
        assert!(r.iter().all(|r| r.abs() < 1e-3), "{r:?}");
    }
}

/// The lowest frequency of two 20 m spans on a pier with springs (kv, kr), exact.
fn exact_f1(kv: f64, kr: f64) -> f64 {
    let beam = ContinuousBeam {
        pieces_m: vec![20.0, 20.0],
        conditions: vec![
            Condition::Pinned,
            Condition::Springs {
                vertical_n_m: kv,
                rotational_n_m_rad: kr,
            },
            Condition::Pinned,
        ],
        flexural_rigidity_n_m2: EI,
        mass_per_length_kg_m: MASS,
    };
    beam.frequencies_hz(1).expect("exact modes")[0]
}

#[test]
fn bearing_degradation_and_scour_lower_the_frequency_to_the_exact_one() {
    // An elastic pier (2e8 N/m, 1e9 N m/rad) loses half its stiffness linearly over 4 s
    // from t = 1 s: the model is rebuilt whenever a factor has moved 0.2 % (the damage
    // rule), and at the end its f1 is the exact beam's on the softened pier, within the
    // finite-element error of 40 elements (1e-4 measured on the intact pier).
    let (kv, kr) = (2e8, 1e9);
    let pier = format!(
        "[\"pinned\", {{ elastic = {{ vertical_n_m = {kv}, rotational_n_m_rad = {kr} }} }}, \
         \"roller\"]"
    );
    for (kind, soft) in [
        ("bearing_degradation", (0.5 * kv, kr)),
        ("scour", (0.5 * kv, 0.5 * kr)),
    ] {
        let condition = format!(
            "[[support_condition]]\nposition_m = 20.0\nkind = \"{kind}\"\nreduction = 0.5\n\
             onset_s = 1.0\ngrowth = {{ kind = \"linear\", duration_s = 4.0 }}\n"
        );
        let records = records_of(&two_spans(
            &pier,
            "{ kind = \"finite_element\", elements = 40 }",
            &condition,
            "",
            6.0,
        ));
        let modal = modal_records(&records);
        let first = &modal.first().expect("the start's record").1;
        let last = &modal.last().expect("records").1;
        let f_before = first.natural_frequency_hz[0];
        let f_after = last.natural_frequency_hz[0];
        let (exact_before, exact_after) = (exact_f1(kv, kr), exact_f1(soft.0, soft.1));
        assert!(
            (f_before / exact_before - 1.0).abs() < 3e-4,
            "{kind}: {f_before} vs {exact_before}"
        );
        assert!(
            (f_after / exact_after - 1.0).abs() < 3e-4,
            "{kind}: {f_after} vs {exact_after}"
        );
        assert!(
            exact_after < 0.99 * exact_before,
            "{kind}: the pier matters"
        );
        assert_eq!(last.support_stiffness_ratio, [1.0, 0.5, 1.0], "{kind}");
        // One rebuild per second while it grows (the condition's update interval).
        let rebuilds = modal.len();
        assert!(
            (5..=8).contains(&rebuilds),
            "{kind}: {rebuilds} modal records"
        );
        let text = events(&records)
            .into_iter()
            .find(|(_, t)| t.starts_with("support_condition.0 begins"))
            .expect("announced");
        assert!(
            text.1.contains(kind) && text.1.contains("50.0 %"),
            "{}",
            text.1
        );
    }
}

#[test]
fn traffic_wim_ambient_temperature_and_damage_work_on_a_girder() {
    // Everything a single span takes, on three spans with an overhang: two-way traffic
    // crossing every span, a WIM strip, ambient excitation, a temperature cycle and damage
    // over the central span, together, for 40 s. Each leaves its trace in the records.
    let toml = r#"
seed = 5
duration_s = 40.0
[bridge]
spans_m = [24.0, 30.0, 24.0]
supports = ["pinned", "roller", "roller", "roller"]
overhang_right_m = 3.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
model = { kind = "finite_element", elements = 60 }
[road]
profile = { kind = "iso8608", class = "A" }
approach_m = 60.0
exit_m = 30.0
[traffic]
lanes = [{ direction = 1, flow_per_hour = 900.0 }, { direction = -1, flow_per_hour = 900.0 }]
[ambient]
target_rms_m_s2 = 0.003
[environment]
temperature = { kind = "daily", mean_c = 18.0, amplitude_c = 6.0, peak_hour = 15.0 }
[[damage]]
start_m = 36.0
end_m = 42.0
reduction = 0.3
onset_s = 10.0
[[wim_stations]]
id = "WIM1"
position_m = -20.0
model = { kind = "cost323", class = "B+(7)" }
[[sensors]]
id = "A_MID"
kind = "accelerometer"
position_m = 39.0
rate_hz = 100.0
[[sensors]]
id = "D_TIP"
kind = "displacement"
position_m = 81.0
rate_hz = 100.0
noise_density = 0.0
"#;
    let records = records_of(toml);
    let count = |f: &dyn Fn(&Record) -> bool| records.iter().filter(|r| f(r)).count();
    let vehicles = count(&|r| matches!(r, Record::Vehicle { .. }));
    let wim = count(&|r| matches!(r, Record::Wim { .. }));
    assert!(
        vehicles >= 3 && wim >= 3,
        "{vehicles} vehicles, {wim} WIM records"
    );
    let texts: Vec<String> = events(&records).into_iter().map(|e| e.1).collect();
    assert!(
        texts.iter().any(|t| t.starts_with("damage.0 begins")),
        "{texts:?}"
    );
    // Traffic both ways reached the far end: some axle state past the third span.
    let far = records.iter().any(|r| match r {
        Record::AxleLoads { axles, .. } => axles.iter().any(|a| a.on_bridge && a.position_m > 60.0),
        _ => false,
    });
    assert!(far, "no axle on the third span");
    // The damage softened the model: f1 after is below f1 before.
    let modal = modal_records(&records);
    let (first, last) = (&modal[0].1, &modal[modal.len() - 1].1);
    assert!(last.natural_frequency_hz[0] < first.natural_frequency_hz[0]);
    assert!(last.damage_fraction == [0.3], "{:?}", last.damage_fraction);
    // The overhang tip moves (up when a span beside its support is loaded, down under a
    // load on it), and the ambient field shakes the central span.
    let tip = sensor_samples(&records, 1);
    let moved = tip
        .iter()
        .map(|s| s.3.displacement_m.abs())
        .fold(0.0, f64::max);
    assert!(moved > 1e-5, "tip {moved}");
    let accel = sensor_samples(&records, 0);
    let rms = (accel
        .iter()
        .map(|s| s.3.acceleration_m_s2.powi(2))
        .sum::<f64>()
        / accel.len() as f64)
        .sqrt();
    assert!(rms > 1e-3, "rms {rms}");
}
