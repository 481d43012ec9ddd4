//! The solver-paths study in quick mode: it writes its files, its reference passes its own
//! convergence check, and the errors of the FE and lumped paths fall with refinement.

use std::sync::OnceLock;

use bridgetwin::studies::solver_paths::{
    run, PathErrors, SolverPath, SolverPathsReport, MOMENT_TARGET,
};

/// The quick study, run once for every test of this file.
fn report() -> &'static (tempfile::TempDir, SolverPathsReport) {
    static REPORT: OnceLock<(tempfile::TempDir, SolverPathsReport)> = OnceLock::new();
    REPORT.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let report = run(dir.path(), true, &mut |_| {}).unwrap();
        (dir, report)
    })
}

#[test]
fn quick_study_writes_its_files_and_its_reference_converges() {
    let (dir, report) = report();
    for file in [
        "summary.md",
        "solver_paths.csv",
        "reference.csv",
        "errors_vs_dof.svg",
        "spatial_errors_vs_dof.svg",
        "histories.svg",
    ] {
        let text = std::fs::read_to_string(dir.path().join(file)).unwrap();
        assert!(text.len() > 300, "{file} is too short");
    }
    assert_eq!(report.references.len(), 2, "smooth and class A");
    for (surface, reference) in &report.references {
        assert!(
            reference.converged(),
            "road {surface}: check {:?} floor {:?}",
            reference.check,
            reference.time_step_floor
        );
    }
    // 3 paths x 3 sizes x 2 roads.
    assert_eq!(report.points.len(), 18);
    let summary = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
    assert!(summary.contains("**Recommended: `"), "{summary}");
    assert!(summary.contains("**converged** | **yes**"));
}

/// A named error metric.
type Metric = (&'static str, fn(&PathErrors) -> f64);

fn metric_series(
    report: &SolverPathsReport,
    path: SolverPath,
    surface: &str,
    metric: fn(&PathErrors) -> f64,
) -> Vec<(usize, f64)> {
    let mut pts: Vec<(usize, f64)> = report
        .points
        .iter()
        .filter(|p| p.path == path && p.surface == surface)
        .map(|p| (p.size, metric(&p.spatial)))
        .collect();
    pts.sort_by_key(|p| p.0);
    pts
}

fn assert_decreasing(pts: &[(usize, f64)], what: &str) {
    assert_eq!(pts.len(), 3, "{what}: {pts:?}");
    for w in pts.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "{what}: error at {} ({:.3e}) is not below the one at {} ({:.3e})",
            w[1].0,
            w[1].1,
            w[0].0,
            w[0].1
        );
    }
}

#[test]
fn fe_and_lumped_errors_fall_with_refinement() {
    // The spatial error (against FE 400 elements at the same dt): against the dt/4
    // reference every path hits the dt = 1 ms floor from ~20 nodes on (that is the next
    // test). Over 10, 20, 50 nodes deflection, tyre force and moment fall on both paths
    // and roads; so does the acceleration of the lumped path. FE's acceleration at 50
    // elements is lifted (to 1e-4, 50x under the floor) by element passing: a wheel
    // crossing 0.6 m elements at 20 m/s loads the bridge at 33 Hz, next to f3 = 34 Hz.
    let (_, report) = report();
    let metrics: [Metric; 3] = [
        ("deflection", |e| e.deflection),
        ("force", |e| e.force),
        ("moment", |e| e.moment),
    ];
    for (surface, _) in &report.references {
        for path in [SolverPath::LumpedLowRank, SolverPath::FeBanded] {
            for (name, metric) in metrics {
                let pts = metric_series(report, path, surface, metric);
                assert_decreasing(&pts, &format!("{} {name} road {surface}", path.name()));
            }
        }
        let accel = metric_series(report, SolverPath::LumpedLowRank, surface, |e| {
            e.acceleration_rms
        });
        assert_decreasing(&accel, &format!("lumped acceleration road {surface}"));
    }
}

#[test]
fn refined_paths_reach_the_time_step_floor() {
    // At 50 nodes the spatial error is far below the time-step error, so the error against
    // the converged reference is the floor's (FE 400 at dt = 1 ms) within 10 %.
    let (_, report) = report();
    for (surface, reference) in &report.references {
        let floor = &reference.time_step_floor;
        for path in [SolverPath::LumpedLowRank, SolverPath::FeBanded] {
            let p = report.point(path, 50, surface).unwrap();
            for (e, f) in [
                (p.errors.deflection, floor.deflection),
                (p.errors.acceleration_rms, floor.acceleration_rms),
                (p.errors.force, floor.force),
            ] {
                assert!(
                    (e - f).abs() <= 0.1 * f,
                    "{} road {surface}: {e:.3e} vs floor {f:.3e}",
                    path.name()
                );
            }
        }
    }
}

#[test]
fn modal_errors_fall_with_modes_and_every_size_meets_the_moment_target() {
    let (_, report) = report();
    for (surface, _) in &report.references {
        let metrics: [Metric; 2] = [("deflection", |e| e.deflection), ("force", |e| e.force)];
        for (name, metric) in metrics {
            let pts = metric_series(report, SolverPath::Modal, surface, metric);
            assert_decreasing(&pts, &format!("modal {name} road {surface}"));
        }
    }
    // The midspan moment, recovered from element equilibrium, errs by 3e-4 to 1e-3 of
    // its peak at every path and size (the worst, 9.9e-4, the lumped model's 10 masses
    // on road A), where the interpolated curvature erred by 1.7 % at 20 elements: every
    // point holds 2e-3, and FE meets every target at its smallest quick size.
    for p in &report.points {
        assert!(
            p.errors.moment < 2e-3 && 2e-3 < MOMENT_TARGET,
            "{} {} road {}: moment {:.2e}",
            p.path.name(),
            p.size,
            p.surface,
            p.errors.moment
        );
    }
    let fe = report
        .candidates
        .iter()
        .find(|c| c.path == SolverPath::FeBanded)
        .expect("FE meets the targets at some quick size");
    assert_eq!(fe.size, 10);
    assert!(fe.scenario_physics_ms > 0.0 && fe.scenario_physics_ms.is_finite());
}
