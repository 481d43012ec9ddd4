//! `bridgetwin study hslm --quick`: the files, and what the envelope must show.

use bridgetwin::studies::hslm;

#[test]
fn the_quick_hslm_study_finds_the_resonances_and_writes_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let report = hslm::run(dir.path(), true, &mut |_| {}).unwrap();
    for file in [
        "hslm.csv",
        "envelope.csv",
        "acceleration_short_15m.svg",
        "acceleration_paper_30m.svg",
        "interaction.svg",
        "closed_forms.svg",
        "dynamic_factor.svg",
        "summary.md",
    ] {
        let len = std::fs::metadata(dir.path().join(file)).unwrap().len();
        assert!(len > 200, "{file}: {len} bytes");
    }
    // 3 trains x 13 speeds x 2 bridges as moving forces, 1 train as vehicles.
    assert_eq!(report.rows.len(), (3 + 1) * 13 * 2);
    // A1 (D = 18 m) on the short span (n0 = 5 Hz): its worst speed on the 25 km/h grid is
    // the grid point nearest n0 D = 324 km/h, far above the acceleration limit, and the
    // closed forms agree there within 5 %.
    let a1: Vec<_> = report
        .rows
        .iter()
        .filter(|r| r.bridge == 0 && r.train == 1 && !r.vehicles)
        .collect();
    let worst = a1
        .iter()
        .max_by(|a, b| {
            a.peaks
                .acceleration_m_s2
                .total_cmp(&b.peaks.acceleration_m_s2)
        })
        .unwrap();
    assert_eq!(worst.speed_km_h, 325.0);
    assert!(worst.peaks.acceleration_m_s2 > 10.0 * hslm::LIMIT_BALLASTED_M_S2);
    assert!((worst.peaks.acceleration_m_s2 / worst.lir_m_s2 - 1.0).abs() < 0.05);
    // Far from resonance the dynamic moment stays near the static one.
    let slow = a1.iter().find(|r| r.speed_km_h == 100.0).unwrap();
    assert!(
        (1.0..1.2).contains(&slow.moment_factor()),
        "{}",
        slow.moment_factor()
    );
    // The vehicle models (unilateral contact) take some of the resonance off, and their
    // wheels unload at it.
    let vehicles = report
        .rows
        .iter()
        .find(|r| r.bridge == 0 && r.train == 1 && r.vehicles && r.speed_km_h == 325.0)
        .unwrap();
    assert!(vehicles.peaks.acceleration_m_s2 < worst.peaks.acceleration_m_s2);
    assert!(
        vehicles.peaks.min_wheel_ratio < 0.5,
        "{}",
        vehicles.peaks.min_wheel_ratio
    );
    let summary = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
    assert!(summary.contains("| short_15m | 5.000 |"), "{summary}");
}
