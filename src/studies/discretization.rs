//! The paper's section 6 study and past it: lumped mass (flexibility) vs Hermite finite
//! elements on a manufactured solution, error and cost vs node count and time step, each
//! method solved (a) the paper's way (dense effective system factorized every step) and
//! (b) with its structure exploited (factorized once; banded for FE).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, LumpedStiffness, ModelSpec};
use crate::physics::solver::{SolveMode, Storage};
use crate::studies::plot::{Chart, Figure, Scale, Series};
use crate::studies::verify::{manufactured_history, ManufacturedCase};

use super::output::{write_file, write_svg_file};

/// One (model, n, dt) point of the study.
#[derive(Debug, Clone)]
pub struct DiscretizationPoint {
    pub model: &'static str,
    pub n: usize,
    pub dof: usize,
    pub dt_s: f64,
    pub error_0_3l: f64,
    pub error_0_5l: f64,
    /// Per-step wall time, structure exploited (us).
    pub step_structured_us: f64,
    /// Per-step wall time, dense system factorized every step (us).
    pub step_paper_us: f64,
    pub steps: u64,
}

const DURATION_S: f64 = 2.0;

fn spec(model: &str, n: usize) -> ModelSpec {
    if model == "lumped_mass" {
        ModelSpec::LumpedMass {
            nodes: n,
            stiffness: LumpedStiffness::Auto,
        }
    } else {
        ModelSpec::FiniteElement { elements: n }
    }
}

fn structured_mode(model: &str) -> SolveMode {
    if model == "lumped_mass" {
        // The lumped K (= F^-1) is dense: prefactored dense Cholesky.
        SolveMode::Prefactored(Storage::Dense)
    } else {
        // Hermite FE matrices are banded: sparse Cholesky keeps the band, O(n) per step.
        SolveMode::Prefactored(Storage::Sparse)
    }
}

/// Runs one point. The paper's way is timed on a capped number of steps (its per-step
/// cost does not depend on dt); its results equal the structured ones to round-off
/// (tested in `solver::newmark`).
pub fn run_point(model: &'static str, n: usize, dt_s: f64) -> Result<DiscretizationPoint> {
    let beam = BeamProperties::paper_default();
    let points = [0.3 * beam.length_m(), 0.5 * beam.length_m()];
    let mut case = ManufacturedCase {
        beam: beam.clone(),
        spec: spec(model, n),
        damping_ratio: 0.02,
        dt_s,
        duration_s: DURATION_S,
        mode: structured_mode(model),
    };
    let structured = manufactured_history(&case, &points)?;
    case.mode = SolveMode::FactorEachStep;
    case.duration_s = (200.0 * dt_s).min(DURATION_S);
    let paper = manufactured_history(&case, &points)?;
    let dof = if model == "lumped_mass" { n } else { 2 * n };
    Ok(DiscretizationPoint {
        model,
        n,
        dof,
        dt_s,
        error_0_3l: structured.relative_error[0],
        error_0_5l: structured.relative_error[1],
        step_structured_us: 1e6 * structured.loop_wall_s / structured.steps as f64,
        step_paper_us: 1e6 * paper.loop_wall_s / paper.steps as f64,
        steps: structured.steps,
    })
}

/// Runs the grid and writes CSV, figures and summary.md into `out`.
pub fn run(
    out: &Path,
    quick: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<DiscretizationPoint>> {
    let nodes: &[usize] = if quick {
        &[10, 20, 50]
    } else {
        &[10, 20, 50, 100, 200]
    };
    let dts: &[f64] = if quick {
        &[0.01, 0.005]
    } else {
        &[0.01, 0.005, 0.001]
    };
    let mut points = Vec::new();
    for model in ["lumped_mass", "finite_element"] {
        for &n in nodes {
            for &dt in dts {
                progress(&format!("{model} n={n} dt={dt}"));
                points.push(run_point(model, n, dt)?);
            }
        }
    }
    write_outputs(out, &points)?;
    Ok(points)
}

fn write_outputs(out: &Path, points: &[DiscretizationPoint]) -> Result<()> {
    let mut csv = String::from(
        "model,n,dof,dt_s,rel_error_0_3L,rel_error_0_5L,step_structured_us,step_paper_us,run_structured_s,run_paper_s\n",
    );
    for p in points {
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.6e},{:.6e},{:.3},{:.3},{:.6},{:.6}",
            p.model,
            p.n,
            p.dof,
            p.dt_s,
            p.error_0_3l,
            p.error_0_5l,
            p.step_structured_us,
            p.step_paper_us,
            p.step_structured_us * p.steps as f64 * 1e-6,
            p.step_paper_us * p.steps as f64 * 1e-6
        );
    }
    write_file(&out.join("discretization.csv"), &csv)?;
    write_svg_file(&out.join("error_vs_n.svg"), &error_figure(points)?)?;
    write_svg_file(&out.join("time_vs_n.svg"), &time_chart(points).to_svg()?)?;
    write_svg_file(
        &out.join("time_ratio_vs_n.svg"),
        &ratio_chart(points).to_svg()?,
    )?;
    write_file(&out.join("summary.md"), &summary(points))?;
    Ok(())
}

fn series_for(
    points: &[DiscretizationPoint],
    model: &str,
    dt: f64,
    y: impl Fn(&DiscretizationPoint) -> f64,
) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p.model == model && p.dt_s == dt)
        .map(|p| (p.n as f64, y(p)))
        .collect()
}

fn dts_of(points: &[DiscretizationPoint]) -> Vec<f64> {
    let mut dts: Vec<f64> = points.iter().map(|p| p.dt_s).collect();
    dts.sort_by(|a, b| b.total_cmp(a));
    dts.dedup();
    dts
}

fn error_figure(points: &[DiscretizationPoint]) -> Result<String> {
    let charts: Vec<Chart> = [("0.3 L", 0usize), ("0.5 L", 1usize)]
        .iter()
        .map(|&(label, which)| {
            let mut series = Vec::new();
            for model in ["lumped_mass", "finite_element"] {
                for dt in dts_of(points) {
                    let pts = series_for(points, model, dt, |p| {
                        if which == 0 {
                            p.error_0_3l
                        } else {
                            p.error_0_5l
                        }
                    });
                    series.push(
                        Series::line_markers(format!("{model} dt={dt} s"), pts)
                            .with_dashed(model == "finite_element"),
                    );
                }
            }
            let mut chart = Chart::new(
                format!("Manufactured solution: max error at {label}"),
                "n (masses or elements)",
                "max |error| / max |w|",
            );
            chart.x_scale = Scale::Log10;
            chart.y_scale = Scale::Log10;
            chart.series = series;
            chart
        })
        .collect();
    Figure::grid(1, 2, &charts)
}

fn time_chart(points: &[DiscretizationPoint]) -> Chart {
    let dt = dts_of(points).last().copied().unwrap_or(0.001);
    let mut chart = Chart::new(
        "Wall time per Newmark step",
        "n (masses or elements)",
        "time per step (us)",
    );
    chart.x_scale = Scale::Log10;
    chart.y_scale = Scale::Log10;
    for model in ["lumped_mass", "finite_element"] {
        for (way, paper) in [
            ("dense each step (paper)", true),
            ("structured, prefactored", false),
        ] {
            let pts = series_for(points, model, dt, |p| {
                if paper {
                    p.step_paper_us
                } else {
                    p.step_structured_us
                }
            });
            chart
                .series
                .push(Series::line_markers(format!("{model}: {way}"), pts).with_dashed(!paper));
        }
    }
    chart
}

fn ratio_chart(points: &[DiscretizationPoint]) -> Chart {
    let dt = dts_of(points).last().copied().unwrap_or(0.001);
    let mut chart = Chart::new(
        "Time ratio finite element / lumped mass (same n)",
        "n (masses or elements)",
        "FE time / lumped time",
    );
    chart.x_scale = Scale::Log10;
    chart.y_scale = Scale::Log10;
    chart.hlines = vec![
        (1.0, "equal cost".into()),
        (2.0, "paper: 2x".into()),
        (8.0, "paper: 8x".into()),
    ];
    for (way, paper) in [
        ("dense each step (paper)", true),
        ("structured, prefactored", false),
    ] {
        let lumped = series_for(points, "lumped_mass", dt, |p| {
            if paper {
                p.step_paper_us
            } else {
                p.step_structured_us
            }
        });
        let fe = series_for(points, "finite_element", dt, |p| {
            if paper {
                p.step_paper_us
            } else {
                p.step_structured_us
            }
        });
        let pts = lumped
            .iter()
            .zip(&fe)
            .map(|(l, f)| (l.0, f.1 / l.1))
            .collect();
        chart
            .series
            .push(Series::line_markers(way.to_string(), pts));
    }
    chart
}

fn summary(points: &[DiscretizationPoint]) -> String {
    let dt = dts_of(points).last().copied().unwrap_or(0.001);
    let mut md = String::from("# Discretization study: lumped mass vs Hermite finite elements\n\n");
    md.push_str("Manufactured solution with modes 1-3 (forcing at 2, 3 and 7 Hz, 2 s, Rayleigh 2 %) on the paper's 30 m beam. Error = max over time of |w_num - w_exact| / max |w_exact|.\n\n");
    let _ = writeln!(md, "## Error and cost at dt = {dt} s\n");
    md.push_str("| model | n | DOF | error 0.3 L | error 0.5 L | us/step paper way | us/step structured |\n|---|---|---|---|---|---|---|\n");
    for p in points.iter().filter(|p| p.dt_s == dt) {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2e} | {:.2e} | {:.1} | {:.1} |",
            p.model, p.n, p.dof, p.error_0_3l, p.error_0_5l, p.step_paper_us, p.step_structured_us
        );
    }
    md.push_str("\n## Time ratio finite element / lumped mass at the same n\n\n| n | paper way (dense each step) | structured (prefactored; banded FE) |\n|---|---|---|\n");
    let by = |model: &str, n: usize| {
        points
            .iter()
            .find(|p| p.model == model && p.n == n && p.dt_s == dt)
    };
    let mut ns: Vec<usize> = points.iter().map(|p| p.n).collect();
    ns.sort();
    ns.dedup();
    for n in ns {
        if let (Some(l), Some(f)) = (by("lumped_mass", n), by("finite_element", n)) {
            let _ = writeln!(
                md,
                "| {} | {:.2} | {:.2} |",
                n,
                f.step_paper_us / l.step_paper_us,
                f.step_structured_us / l.step_structured_us
            );
        }
    }
    md.push_str("\nFigures: `error_vs_n.svg`, `time_vs_n.svg`, `time_ratio_vs_n.svg`; data: `discretization.csv`.\n");
    md
}
