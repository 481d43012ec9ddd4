//! The plain-text table of `bridgetwin bench`.

use std::fmt::Write as _;

use super::{BenchPath, BenchReport, BenchRow};

/// The whole report as text: header, the per-step table, the end-to-end lines.
pub fn table(r: &BenchReport) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "bridgetwin bench{}: one coupled step, two_axle_truck at 20 m/s with both axles on \
         the paper's 30 m bridge, dt = 1 ms (median of repetitions after a warm-up)",
        if r.quick { " --quick" } else { "" }
    );
    t.push_str(
        "baseline: the paper's direct method (DirectSolver: the full coupled system \
         assembled and LU-factorized every step) on the lumped model with the same nodes\n",
    );
    let _ = writeln!(
        t,
        "accuracy: peak midspan deflection and peak tyre force vs {} ({})",
        r.reference.description,
        if r.reference.converged {
            "converged: passes its check"
        } else {
            "NOT converged: fails its check"
        }
    );
    t.push('\n');
    let _ = writeln!(
        t,
        "{:<16} {:>5} {:>5} {:>10} {:>21} {:>12} {:>9} {:>8} {:>10} {:>10}",
        "path",
        "nodes",
        "DOF",
        "us/step",
        "(min..max)",
        "direct us",
        "speedup",
        "build s",
        "peak defl",
        "peak force"
    );
    for row in &r.rows {
        t.push_str(&row_line(row));
    }
    t.push('\n');
    end_to_end_lines(&mut t, r);
    t
}

fn row_line(row: &BenchRow) -> String {
    let (defl, force) = match (&row.accuracy, row.path) {
        (Some(e), _) => (
            format!("{:.1e}", e.peak_deflection),
            format!("{:.1e}", e.peak_force),
        ),
        (None, BenchPath::Direct) => ("= lumped".to_string(), "= lumped".to_string()),
        (None, _) => ("-".to_string(), "-".to_string()),
    };
    format!(
        "{:<16} {:>5} {:>5} {:>10} {:>21} {:>12} {:>8.1}x {:>8.3} {:>10} {:>10}\n",
        row.path.name(),
        row.nodes,
        row.dof,
        us(row.us_per_step),
        format!("({}..{})", us(row.us_per_step_min), us(row.us_per_step_max)),
        us(row.direct_us_per_step),
        row.speedup_vs_direct,
        row.model_build_s,
        defl,
        force
    )
}

/// Microseconds with three significant digits.
fn us(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

fn end_to_end_lines(t: &mut String, r: &BenchReport) {
    let e = &r.end_to_end;
    let _ = writeln!(
        t,
        "end to end, default scenario ({} layout; {:.2} s simulated, {} steps, {} records, \
         {:.2} MiB; in-memory MCAP; median of {}):",
        e.layout,
        e.simulated_s,
        e.solver_steps,
        e.records,
        e.mcap_bytes as f64 / 1048576.0,
        e.repetitions
    );
    for (name, wall, rtf) in [
        ("end to end", e.end_to_end_s, e.real_time_factor),
        (
            "  one thread",
            e.end_to_end_one_thread_s,
            e.simulated_s / e.end_to_end_one_thread_s,
        ),
        (
            "physics only",
            e.physics_only_s,
            e.real_time_factor_physics_only,
        ),
        (
            "writing only",
            e.writing_only_s,
            e.real_time_factor_writing_only,
        ),
    ] {
        let _ = writeln!(
            t,
            "  {name:<13} {:>8.1} ms  {:>7.1}x real time",
            1e3 * wall,
            rtf
        );
    }
    let _ = writeln!(
        t,
        "  end_to_end / writing_only = {:.2} (writer on a second thread, as `simulate`; \
         {:.2} on one thread, as a sweep job)",
        e.end_to_end_over_writing_only, e.one_thread_over_writing_only
    );
    let c = &r.chains;
    let _ = writeln!(
        t,
        "measurement chains, {} accelerometers at 100 Hz, {:.0} s simulated (ambient + a \
         truck; median of {}):\n  ideal sensors {:>8.1} ms\n  mems_lownoise + node clocks \
         + faults {:>8.1} ms\n  ratio {:.2} (target <= 1.5)",
        c.channels,
        c.simulated_s,
        c.repetitions,
        1e3 * c.ideal_s,
        1e3 * c.realistic_s,
        c.ratio
    );
    let g = &r.girder;
    let _ = writeln!(
        t,
        "continuous girder, one coupled step, banded FE with {} elements (median of {} \
         alternate rounds):\n  single 30 m span {:>8.2} us\n  three spans 24 + 30 + 24 m \
         {:>8.2} us\n  ratio {:.2} (target <= 1.5)",
        g.elements, g.rounds, g.single_span_us, g.three_span_us, g.ratio
    );
    let _ = writeln!(t, "bench wall time {:.1} s", r.wall_s);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::bench::{EndToEnd, ReferenceSummary};
    use crate::studies::solver_paths::PathErrors;

    fn row(path: BenchPath, us: f64, direct: f64) -> BenchRow {
        BenchRow {
            path,
            nodes: 100,
            dof: 100,
            us_per_step: us,
            us_per_step_min: 0.9 * us,
            us_per_step_max: 1.1 * us,
            steps_per_repetition: 1000,
            repetitions: 5,
            direct_us_per_step: direct,
            speedup_vs_direct: direct / us,
            model_build_s: 0.01,
            accuracy: (path != BenchPath::Direct).then(|| PathErrors {
                peak_deflection: 4.0e-5,
                peak_force: 3.5e-5,
                ..PathErrors::default()
            }),
        }
    }

    #[test]
    fn table_has_a_line_per_row_with_ratio_and_accuracy_and_the_end_to_end_lines() {
        let report = BenchReport {
            quick: true,
            nodes: vec![100],
            rows: vec![
                row(BenchPath::LumpedLowRank, 18.2, 188.0),
                row(BenchPath::Direct, 188.0, 188.0),
            ],
            reference: ReferenceSummary {
                description: "FE 400".into(),
                converged: true,
                check: PathErrors::default(),
                time_step_floor: PathErrors::default(),
            },
            end_to_end: EndToEnd {
                layout: "sample".into(),
                simulated_s: 9.714,
                solver_steps: 9714,
                records: 19629,
                mcap_bytes: 1 << 20,
                end_to_end_s: 0.062,
                end_to_end_one_thread_s: 0.07,
                physics_only_s: 0.040,
                writing_only_s: 0.021,
                real_time_factor: 156.7,
                real_time_factor_physics_only: 242.9,
                real_time_factor_writing_only: 462.6,
                end_to_end_over_writing_only: 2.95,
                one_thread_over_writing_only: 3.33,
                repetitions: 3,
            },
            chains: crate::studies::bench::chains::ChainCost {
                channels: 16,
                simulated_s: 60.0,
                ideal_s: 0.5,
                realistic_s: 0.6,
                ratio: 1.2,
                repetitions: 1,
            },
            girder: crate::studies::bench::girder::GirderCost {
                elements: 150,
                single_span_us: 4.0,
                three_span_us: 4.4,
                ratio: 1.1,
                rounds: 3,
            },
            wall_s: 3.5,
        };
        let text = table(&report);
        let line = |start: &str| text.lines().find(|l| l.starts_with(start)).unwrap();
        let lumped = line("lumped_low_rank");
        assert!(
            lumped.contains("18.2") && lumped.contains("10.3x"),
            "{lumped}"
        );
        assert!(
            lumped.contains("4.0e-5") && lumped.contains("3.5e-5"),
            "{lumped}"
        );
        assert!(line("direct_paper").contains("= lumped"));
        assert!(text.contains("converged: passes its check"));
        assert!(text.contains("156.7x real time"));
        assert!(text.contains("end_to_end / writing_only = 2.95"));
        assert!(text.contains("ratio 1.20 (target <= 1.5)"));
        assert!(
            text.contains("three spans 24 + 30 + 24 m     4.40 us"),
            "{text}"
        );
        assert!(text.contains("ratio 1.10 (target <= 1.5)"));
    }
}
