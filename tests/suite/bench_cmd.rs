//! `bridgetwin bench --quick --json`: it runs, its JSON has every path at 50 and 100
//! nodes, every ratio is finite and every path is accurate. How fast a path is, is what
//! the bench reports (and docs/performance.md quotes from it), not something a test asserts: on a
//! shared machine a timing threshold fails or passes for reasons of its own.

use std::process::Command;

use serde_json::Value;

fn run_bench_quick_json() -> Value {
    let out = Command::new(crate::common::BIN)
        .args(["bench", "--quick", "--json"])
        .output()
        .expect("bridgetwin runs");
    assert!(
        out.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn f(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

#[test]
fn quick_bench_json_has_every_path_with_finite_ratios_and_accurate_results() {
    let report = run_bench_quick_json();
    let rows = report["rows"].as_array().expect("rows");
    // 4 paths x 2 node counts.
    assert_eq!(rows.len(), 8, "{rows:?}");
    for row in rows {
        let (path, nodes) = (
            row["path"].as_str().unwrap(),
            row["nodes"].as_u64().unwrap(),
        );
        let ratio = f(row, "speedup_vs_direct");
        assert!(ratio.is_finite() && ratio > 0.0, "{path} {nodes}: {ratio}");
        assert!(f(row, "us_per_step") > 0.0);
        if path == "direct_paper" {
            assert!((ratio - 1.0).abs() < 1e-12, "the baseline against itself");
            assert!(row["accuracy"].is_null());
            continue;
        }
        // Accuracy against the converged reference: at 50 and 100 nodes every path is at
        // the dt = 1 ms floor (peak errors ~4e-5); 1e-3 leaves room and still catches a
        // broken path.
        let acc = &row["accuracy"];
        for key in ["peak_deflection", "peak_force", "deflection", "force"] {
            let e = f(acc, key);
            assert!(e.is_finite() && e < 1e-3, "{path} {nodes}: {key} {e}");
        }
    }
    assert_eq!(report["reference"]["converged"], Value::Bool(true));
    let e2e = &report["end_to_end"];
    for key in [
        "real_time_factor",
        "real_time_factor_physics_only",
        "real_time_factor_writing_only",
    ] {
        let v = f(e2e, key);
        assert!(v.is_finite() && v > 0.0, "{key}: {v}");
    }
    let ratio = f(e2e, "end_to_end_over_writing_only");
    assert!(ratio.is_finite() && ratio > 0.0, "{ratio}");
}
