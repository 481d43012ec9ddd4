//! The continuous-girder study's outputs: CSV, SVG figures and summary.md.

use std::fmt::Write;
use std::path::Path;

use crate::error::Result;
use crate::studies::dlc::{Spread, Surface};
use crate::studies::output::{write_file, write_svg_file};
use crate::studies::plot::{Chart, Figure, Scale, Series};

use super::{Case, ContinuousReport, PIER_X_M, SAGGING_X_M};

pub(super) fn write_outputs(out: &Path, r: &ContinuousReport) -> Result<()> {
    write_file(&out.join("models.csv"), &models_csv(r))?;
    write_file(&out.join("amplification.csv"), &cases_csv(r))?;
    write_svg_file(&out.join("daf_vs_speed.svg"), &daf_figure(r)?)?;
    write_svg_file(&out.join("dlc_vs_speed.svg"), &dlc_figure(r)?)?;
    write_svg_file(&out.join("models.svg"), &models_figure(r)?)?;
    write_file(&out.join("summary.md"), &summary(r))
}

fn models_csv(r: &ContinuousReport) -> String {
    let mut csv = String::from(
        "model,n,dof,f1_hz,f2_hz,f3_hz,f1_error,f2_error,f3_error,peak_deflection_error,build_s,step_us\n",
    );
    for m in &r.models {
        let _ = writeln!(
            csv,
            "{},{},{},{:.6},{:.6},{:.6},{:.3e},{:.3e},{:.3e},{:.3e},{:.4},{:.3}",
            m.model,
            m.n,
            m.dof,
            m.frequencies_hz[0],
            m.frequencies_hz[1],
            m.frequencies_hz[2],
            m.frequency_error[0],
            m.frequency_error[1],
            m.frequency_error[2],
            m.deflection_error,
            m.build_s,
            m.step_us
        );
    }
    csv
}

fn cases_csv(r: &ContinuousReport) -> String {
    let mut csv = String::from(
        "road,speed_m_s,daf_sagging_mean,daf_sagging_p5,daf_sagging_p95,daf_hogging_mean,\
         daf_hogging_p5,daf_hogging_p95,dlc_front_mean,dlc_front_p95,dlc_rear_mean,dlc_rear_p95\n",
    );
    for c in &r.cases {
        let _ = writeln!(
            csv,
            "{},{},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5}",
            c.surface.label(),
            c.speed_m_s,
            c.daf_sagging.mean,
            c.daf_sagging.p5,
            c.daf_sagging.p95,
            c.daf_hogging.mean,
            c.daf_hogging.p5,
            c.daf_hogging.p95,
            c.dlc[0].mean,
            c.dlc[0].p95,
            c.dlc[1].mean,
            c.dlc[1].p95
        );
    }
    csv
}

/// One statistic of a case, by name in the figures.
type Statistic = fn(&Case) -> Spread;

/// A chart per road of `what` (mean with its p5-p95 band) vs speed, the codes as lines.
fn per_road(
    r: &ContinuousReport,
    title: &str,
    y_label: &str,
    series: &[(&str, Statistic)],
) -> Vec<Chart> {
    let top = r
        .cases
        .iter()
        .flat_map(|c| series.iter().map(move |(_, f)| f(c).p95))
        .fold(1.9, f64::max);
    Surface::STUDIED
        .iter()
        .map(|&surface| {
            let cases: Vec<&Case> = r.cases.iter().filter(|c| c.surface == surface).collect();
            let mut chart = Chart::new(
                format!("{title}, road {}", surface.label()),
                "speed (m/s)",
                y_label,
            )
            .with_y_range(0.8, 1.05 * top);
            for (name, f) in series {
                let mean = cases.iter().map(|c| (c.speed_m_s, f(c).mean)).collect();
                let band = cases
                    .iter()
                    .map(|c| (c.speed_m_s, f(c).p5, f(c).p95))
                    .collect();
                chart.series.push(
                    Series::line_markers(format!("{name}: mean, p5-p95"), mean).with_band(band),
                );
            }
            for (code, factor) in &r.codes {
                chart.hlines.push((*factor, format!("{code} {factor:.2}")));
            }
            chart
        })
        .collect()
}

fn daf_figure(r: &ContinuousReport) -> Result<String> {
    let charts = per_road(
        r,
        "DAF of the moments",
        "dynamic / static peak",
        &[
            ("sagging, central midspan", |c| c.daf_sagging),
            ("hogging, first pier", |c| c.daf_hogging),
        ],
    );
    Figure::grid(2, 2, &charts)
}

fn dlc_figure(r: &ContinuousReport) -> Result<String> {
    let charts = per_road(
        r,
        "DLC = max F / F_static",
        "DLC",
        &[("front axle", |c| c.dlc[0]), ("rear axle", |c| c.dlc[1])],
    );
    Figure::grid(2, 2, &charts)
}

fn models_figure(r: &ContinuousReport) -> Result<String> {
    let mut freq = Chart::new(
        "f1..f3 error against 400 Hermite elements",
        "DOFs",
        "|f / f_ref - 1|",
    )
    .with_scales(Scale::Log10, Scale::Log10);
    let mut cost = Chart::new("time per coupled step", "DOFs", "us / step")
        .with_scales(Scale::Log10, Scale::Log10);
    for name in ["lumped_mass", "finite_element"] {
        let rows: Vec<_> = r.models.iter().filter(|m| m.model == name).collect();
        for k in 0..3 {
            freq.series.push(Series::line_markers(
                format!("{name} f{}", k + 1),
                rows.iter()
                    .map(|m| (m.dof as f64, m.frequency_error[k].max(1e-12)))
                    .collect(),
            ));
        }
        cost.series.push(Series::line_markers(
            name,
            rows.iter().map(|m| (m.dof as f64, m.step_us)).collect(),
        ));
    }
    Figure::grid(1, 2, &[freq, cost])
}

fn summary(r: &ContinuousReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Continuous girder: dynamic amplification and axle loads\n\n\
         The two-axle truck over `examples/three_span_continuous.toml` (24 + 30 + 24 m, haunched \
         over the piers, f1 = {:.3} Hz), {} realisations per rough road. Static peaks from the \
         influence lines of the same mesh: sagging {:.1} kN m at x = {SAGGING_X_M} m, hogging \
         {:.1} kN m over the pier at x = {PIER_X_M} m. Wall time {:.0} s.\n",
        r.f1_hz,
        r.realisations,
        1e-3 * r.static_sagging_n_m,
        1e-3 * r.static_hogging_n_m,
        r.wall_s
    );
    let _ = writeln!(s, "## Lumped mass (condensation) vs Hermite elements\n");
    let _ = writeln!(
        s,
        "Reference: 400 elements, f1..f3 = {:.4}, {:.4}, {:.4} Hz.\n\n\
         | model | n | DOFs | f1 error | f2 error | f3 error | peak midspan deflection error | build (s) | step (us) |\n\
         |---|---|---|---|---|---|---|---|---|",
        r.reference_frequencies_hz[0], r.reference_frequencies_hz[1], r.reference_frequencies_hz[2]
    );
    for m in &r.models {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.4} | {:.2} |",
            m.model,
            m.n,
            m.dof,
            m.frequency_error[0],
            m.frequency_error[1],
            m.frequency_error[2],
            m.deflection_error,
            m.build_s,
            m.step_us
        );
    }
    let _ = writeln!(
        s,
        "\n## Amplification against the codes\n\nCodes at f1: {}.\n\n\
         | road | worst mean DAF sagging (speed) | p95 | worst mean DAF hogging (speed) | p95 | worst mean DLC (axle, speed) | p95 |\n\
         |---|---|---|---|---|---|---|",
        r.codes
            .iter()
            .map(|(c, f)| format!("{c} {f:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for surface in Surface::STUDIED {
        let cases: Vec<&Case> = r.cases.iter().filter(|c| c.surface == surface).collect();
        let worst = |f: &dyn Fn(&Case) -> Spread| {
            cases
                .iter()
                .map(|c| (f(c), c.speed_m_s))
                .max_by(|a, b| a.0.mean.total_cmp(&b.0.mean))
        };
        let (Some((sag, vs)), Some((hog, vh))) =
            (worst(&|c| c.daf_sagging), worst(&|c| c.daf_hogging))
        else {
            continue;
        };
        let (Some((front, vf)), Some((rear, vr))) = (worst(&|c| c.dlc[0]), worst(&|c| c.dlc[1]))
        else {
            continue;
        };
        let (dlc, axle, vd) = if front.mean >= rear.mean {
            (front, "front", vf)
        } else {
            (rear, "rear", vr)
        };
        let _ = writeln!(
            s,
            "| {} | {:.3} ({vs} m/s) | {:.3} | {:.3} ({vh} m/s) | {:.3} | {:.3} ({axle}, {vd} m/s) | {:.3} |",
            surface.label(),
            sag.mean,
            sag.p95,
            hog.mean,
            hog.p95,
            dlc.mean,
            dlc.p95
        );
    }
    let lowest = r.codes.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    let above: Vec<String> = Surface::STUDIED
        .iter()
        .filter_map(|&surface| {
            let speeds: Vec<String> = r
                .cases
                .iter()
                .filter(|c| c.surface == surface)
                .filter(|c| c.daf_sagging.p95 > lowest || c.daf_hogging.p95 > lowest)
                .map(|c| format!("{}", c.speed_m_s))
                .collect();
            (!speeds.is_empty())
                .then(|| format!("road {} at {} m/s", surface.label(), speeds.join(", ")))
        })
        .collect();
    let _ = writeln!(
        s,
        "\nCases whose p95 DAF exceeds the lowest code factor ({lowest:.2}): {}.",
        if above.is_empty() {
            "none".to_string()
        } else {
            above.join(", ")
        }
    );
    s
}
