//! CSV and SVG outputs of the solver-paths study.

use std::fmt::Write as _;
use std::path::Path;

use super::metrics::{low_pass, PathErrors};
use super::{summary, SolverPath, SolverPathsReport};
use crate::error::Result;
use crate::studies::output::{write_file, write_svg_file};
use crate::studies::plot::{Chart, Figure, Scale, Series};

/// Writes `solver_paths.csv`, `reference.csv`, the figures and `summary.md` into `out`.
pub fn write_outputs(out: &Path, report: &SolverPathsReport) -> Result<()> {
    write_file(&out.join("solver_paths.csv"), &points_csv(report))?;
    write_file(&out.join("reference.csv"), &reference_csv(report))?;
    write_svg_file(
        &out.join("errors_vs_dof.svg"),
        &error_figure(report, false)?,
    )?;
    write_svg_file(
        &out.join("spatial_errors_vs_dof.svg"),
        &error_figure(report, true)?,
    )?;
    write_svg_file(&out.join("histories.svg"), &history_figure(report)?)?;
    write_file(&out.join("summary.md"), &summary::markdown(report))?;
    Ok(())
}

const METRICS_HEADER: &str =
    "deflection,acceleration_max,acceleration_rms,force,moment,peak_deflection,peak_force";

fn metrics_csv(e: &PathErrors) -> String {
    format!(
        "{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e}",
        e.deflection,
        e.acceleration_max,
        e.acceleration_rms,
        e.force,
        e.moment,
        e.peak_deflection,
        e.peak_force
    )
}

fn points_csv(report: &SolverPathsReport) -> String {
    let spatial_header = METRICS_HEADER
        .split(',')
        .map(|m| format!("spatial_{m}"))
        .collect::<Vec<_>>()
        .join(",");
    let mut csv =
        format!("road,path,size,size_is,dof,us_per_step,{METRICS_HEADER},{spatial_header}\n");
    for p in &report.points {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{:.3},{},{}",
            p.surface,
            p.path.name(),
            p.size,
            p.path.size_name(),
            p.dof,
            p.us_per_step,
            metrics_csv(&p.errors),
            metrics_csv(&p.spatial)
        );
    }
    csv
}

fn reference_csv(report: &SolverPathsReport) -> String {
    let mut csv = format!("road,comparison,converged,{METRICS_HEADER}\n");
    for (surface, r) in &report.references {
        for (what, e) in [
            ("check_fe200_dt_half", &r.check),
            ("time_step_floor_fe400_dt", &r.time_step_floor),
        ] {
            let _ = writeln!(csv, "{surface},{what},{},{}", r.converged(), metrics_csv(e));
        }
    }
    csv
}

/// The metrics drawn, with how each is read off the errors.
type Metric = (&'static str, fn(&PathErrors) -> f64);

const PLOTTED: [Metric; 4] = [
    ("midspan deflection", |e| e.deflection),
    ("acceleration < 50 Hz (RMS)", |e| e.acceleration_rms),
    ("tyre force / static", |e| e.force),
    ("midspan moment", |e| e.moment),
];

/// Error vs DOF per road (rows) and metric (columns), one series per path; the
/// time-step floor as a reference line. `spatial`: against FE 400 at the same dt.
fn error_figure(report: &SolverPathsReport, spatial: bool) -> Result<String> {
    let mut charts = Vec::new();
    for (surface, reference) in &report.references {
        for (name, metric) in PLOTTED {
            let mut chart = Chart::new(
                format!("road {surface}: {name}"),
                "DOF",
                if spatial {
                    "error vs FE 400 at dt = 1 ms"
                } else {
                    "error vs converged reference"
                },
            )
            .with_scales(Scale::Log10, Scale::Log10)
            .with_hline(metric(&reference.time_step_floor), "dt = 1 ms floor");
            for path in SolverPath::ALL {
                let pts = report
                    .points
                    .iter()
                    .filter(|p| p.path == path && &p.surface == surface)
                    .map(|p| {
                        let e = if spatial { &p.spatial } else { &p.errors };
                        (p.dof as f64, metric(e))
                    })
                    .collect();
                chart.series.push(Series::line_markers(path.name(), pts));
            }
            charts.push(chart.with_size(480, 360));
        }
    }
    let title = if spatial {
        "Spatial (and modal truncation) error alone: against FE 400 elements at the same dt"
    } else {
        "Error against the converged reference (FE 400 elements, dt = 0.25 ms)"
    };
    Figure::grid_titled(title, report.references.len(), PLOTTED.len(), &charts)
}

/// Plot sample spacing of the histories (s): every 5 ms keeps the figure small.
const PLOT_STEP_S: f64 = 5e-3;

/// Midspan deflection, acceleration (< 50 Hz) and rear tyre force over the crossing, per
/// road: the reference and each path at its smallest size.
fn history_figure(report: &SolverPathsReport) -> Result<String> {
    let mut charts = Vec::new();
    let t0 = report.case.approach_m / report.case.speed_m_s;
    for (surface, _) in &report.references {
        let quantities: [(&str, &str); 3] = [
            ("midspan deflection", "mm, down positive"),
            ("midspan acceleration < 50 Hz", "m/s^2"),
            ("rear tyre force", "kN"),
        ];
        for (q, (title, unit)) in quantities.iter().enumerate() {
            let mut chart = Chart::new(
                format!("road {surface}: {title}"),
                "time since the front axle entered (s)",
                *unit,
            );
            for ex in report.examples.iter().filter(|e| &e.surface == surface) {
                let h = &ex.history;
                let values: Vec<f64> = match q {
                    0 => h.deflection_m.iter().map(|u| -1e3 * u).collect(),
                    1 => low_pass(&h.acceleration_m_s2, h.dt_s),
                    _ => h.force_n[1].iter().map(|f| 1e-3 * f).collect(),
                };
                let stride = (PLOT_STEP_S / h.dt_s).round().max(1.0) as usize;
                let pts = values
                    .iter()
                    .enumerate()
                    .step_by(stride)
                    .map(|(i, &v)| (i as f64 * h.dt_s - t0, v))
                    .filter(|&(t, _)| t >= -0.1)
                    .collect();
                let dashed = !ex.label.starts_with("reference");
                chart
                    .series
                    .push(Series::line(ex.label.clone(), pts).with_dashed(dashed));
            }
            charts.push(chart.with_size(560, 360));
        }
    }
    Figure::grid_titled(
        "Crossing histories: reference and the coarsest size of each path",
        report.references.len(),
        3,
        &charts,
    )
}
