//! `bridgetwin study continuous`: its static reference against the three-moment equation,
//! and the quick grid's amplification where the physics puts it.

use bridgetwin::physics::bridge::BeamProperties;
use bridgetwin::physics::vehicle::VehicleDynamics;
use bridgetwin::studies::continuous::{example_beam, run, static_peaks};

#[test]
fn the_static_peaks_are_the_three_moment_equations() {
    // Two equal 24 m spans, one 100 kN force: the pier's hogging peaks at a = L / sqrt(3),
    // M = P L (1 - 1/3) / (4 sqrt(3)) = 0.0962 P L; the first span's midspan moment peaks
    // with the force on it, M = P L / 4 - 3 P L / 64 = 13 P L / 64. Hermite elements are
    // exact at statics for a uniform girder when the force stands on a node: 5 cm
    // elements, so that every 5 cm position is one. (With the force inside an element
    // the recovered moment w'' EI is linear over it and misses the kink: 0.3 % at the
    // node next to it with 0.5 m elements, which a DAF cancels, as the dynamic run reads
    // the same operator.)
    let l = 24.0;
    let mut beam = BeamProperties::simply_supported(2.0 * l, 5.629e10, 12000.0);
    beam.girder = bridgetwin::physics::bridge::Girder {
        spans_m: vec![l, l],
        supports: vec![bridgetwin::physics::bridge::Support::Pinned; 3],
        overhang_left_m: 0.0,
        overhang_right_m: 0.0,
    };
    let force = VehicleDynamics::moving_forces(&[1e5], &[0.0]);
    let (sagging, hogging) = static_peaks(&beam, &force, (0.5 * l, l), 960).unwrap();
    let hog = 1e5 * l * (2.0 / 3.0) / (4.0 * 3f64.sqrt());
    let sag = 13.0 * 1e5 * l / 64.0;
    // The hogging peak sits between the 5 cm positions: the line is flat there (second
    // order), 1e-5.
    assert!((hogging / hog - 1.0).abs() < 1e-5, "{hogging} vs {hog}");
    // 1.5e-7 measured: the round-off of a 960-element solve (condition ~ n^4).
    assert!((sagging / sag - 1.0).abs() < 1e-6, "{sagging} vs {sag}");
}

#[test]
fn the_quick_study_amplifies_where_roughness_and_speed_say() {
    let dir = tempfile::tempdir().unwrap();
    let report = run(dir.path(), true, &mut |_| {}).unwrap();
    // The girder is the example's (one source of truth): f1 4.83 Hz.
    assert!((report.f1_hz - 4.831).abs() < 1e-3, "{}", report.f1_hz);
    let beam = example_beam().unwrap();
    assert_eq!(beam.girder.spans_m, [24.0, 30.0, 24.0]);
    let case = |road: &str, v: f64| {
        report
            .cases
            .iter()
            .find(|c| c.surface.label() == road && c.speed_m_s == v)
            .unwrap_or_else(|| panic!("{road} {v}"))
    };
    // Smooth road, 10 m/s: nearly static (speed parameter v / (2 f1 L) = 0.03): within
    // 1 % of 1 either way (0.9993 sagging: the damped response lags a little behind the
    // load, so its peak may fall short of the static one).
    let slow = case("smooth", 10.0);
    for daf in [slow.daf_sagging.mean, slow.daf_hogging.mean] {
        assert!((daf - 1.0).abs() < 0.01, "{daf}");
    }
    // Roughness drives the amplification: class C above A at every speed, for both
    // moments and the axles.
    for v in [10.0, 20.0, 30.0] {
        let (a, c) = (case("A", v), case("C", v));
        assert!(c.daf_sagging.mean > a.daf_sagging.mean, "{v}");
        assert!(c.daf_hogging.mean > a.daf_hogging.mean, "{v}");
        assert!(c.dlc[1].mean > a.dlc[1].mean, "{v}");
    }
    // Part (a): FE converges on f1 (error falls with n), and every output exists.
    let fe: Vec<f64> = report
        .models
        .iter()
        .filter(|m| m.model == "finite_element")
        .map(|m| m.frequency_error[0])
        .collect();
    assert!(fe.windows(2).all(|w| w[1] < w[0]), "{fe:?}");
    for file in [
        "models.csv",
        "amplification.csv",
        "daf_vs_speed.svg",
        "dlc_vs_speed.svg",
        "models.svg",
        "summary.md",
    ] {
        let text = std::fs::read_to_string(dir.path().join(file)).unwrap();
        assert!(text.len() > 200, "{file}: {} bytes", text.len());
    }
}
