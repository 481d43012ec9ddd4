//! The study's SVG figures: DLC and sigma/static vs speed per road, convergence with the
//! model size, the smooth-road responses.

use crate::error::Result;
use crate::studies::plot::{Chart, Figure, Scale, Series};

use super::stats::rel;
use super::{Crossing, DlcCase, DlcReport, SmoothPoint, Surface, AXLES, CONVERGENCE_SPEED_M_S};

pub(super) fn cases_of(r: &DlcReport, surface: Surface) -> impl Iterator<Item = &DlcCase> {
    r.cases.iter().filter(move |c| c.surface == surface)
}

pub(super) fn dlc_figure(r: &DlcReport) -> Result<String> {
    // One y range for all four charts, so that the classes compare at a glance.
    let top = r
        .cases
        .iter()
        .map(|c| c.dlc[0].p95.max(c.dlc[1].p95))
        .fold(2.0, f64::max);
    let charts: Vec<Chart> = Surface::STUDIED
        .iter()
        .map(|&surface| {
            let mut chart = Chart::new(
                format!("DLC = max F / F_static, road {}", surface.label()),
                "speed (m/s)",
                "DLC",
            )
            .with_y_range(0.9, 1.05 * top);
            for (j, axle) in AXLES.iter().enumerate() {
                let cases: Vec<&DlcCase> = cases_of(r, surface).collect();
                let mean = cases.iter().map(|c| (c.speed_m_s, c.dlc[j].mean)).collect();
                let band = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.dlc[j].p5, c.dlc[j].p95))
                    .collect();
                chart.series.push(
                    Series::line_markers(format!("{axle} axle: mean, p5-p95"), mean)
                        .with_band(band),
                );
            }
            for (code, factor) in &r.codes {
                chart.hlines.push((*factor, format!("{code} {factor:.2}")));
            }
            chart
        })
        .collect();
    Figure::grid(2, 2, &charts)
}

pub(super) fn sigma_figure(r: &DlcReport) -> Result<String> {
    let charts: Vec<Chart> = AXLES
        .iter()
        .enumerate()
        .map(|(j, axle)| {
            let mut chart = Chart::new(
                format!("sigma_F / F_static, {axle} axle (on the bridge)"),
                "speed (m/s)",
                "sigma / static",
            );
            for surface in Surface::STUDIED {
                let cases: Vec<&DlcCase> = cases_of(r, surface).collect();
                let mean = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.sigma_ratio[j].mean))
                    .collect();
                let band = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.sigma_ratio[j].p5, c.sigma_ratio[j].p95))
                    .collect();
                chart.series.push(
                    Series::line_markers(format!("road {}", surface.label()), mean).with_band(band),
                );
            }
            chart
        })
        .collect();
    Figure::grid(1, 2, &charts)
}

type Metric = (&'static str, &'static str, fn(&Crossing) -> f64);

const CONVERGENCE_METRICS: [Metric; 4] = [
    ("Peak midspan deflection", "mm", |c| {
        1e3 * c.peak_deflection_m
    }),
    ("Peak midspan acceleration", "m/s^2", |c| {
        c.peak_acceleration_m_s2
    }),
    ("DLC front axle", "max F / F_static", |c| c.dlc[0]),
    ("DLC rear axle", "max F / F_static", |c| c.dlc[1]),
];

/// Relative differences to the finest FE model, on log axes (the absolute values agree
/// to 5-6 digits and would plot as flat lines).
pub(super) fn convergence_figure(r: &DlcReport) -> Result<String> {
    let reference = r
        .convergence
        .iter()
        .filter(|p| p.model == "finite_element")
        .max_by_key(|p| p.n);
    let charts: Vec<Chart> = CONVERGENCE_METRICS
        .iter()
        .map(|(title, _unit, metric)| {
            let mut chart = Chart::new(
                format!("{title} (class B, {CONVERGENCE_SPEED_M_S} m/s)"),
                "n (masses or elements)",
                format!(
                    "|q - q_ref| / q_ref, ref FE n={}",
                    reference.map_or(0, |p| p.n)
                ),
            )
            .with_scales(Scale::Log10, Scale::Log10);
            let q_ref = reference.map_or(f64::NAN, |p| metric(&p.crossing));
            for model in ["lumped_mass", "finite_element"] {
                let pts = r
                    .convergence
                    .iter()
                    .filter(|p| p.model == model)
                    .map(|p| (p.n as f64, rel(metric(&p.crossing), q_ref)))
                    .collect();
                chart
                    .series
                    .push(Series::line_markers(model, pts).with_dashed(model == "finite_element"));
            }
            chart
        })
        .collect();
    Figure::grid(2, 2, &charts)
}

pub(super) fn smooth_figure(r: &DlcReport) -> Result<String> {
    let line = |f: &dyn Fn(&SmoothPoint) -> f64| -> Vec<(f64, f64)> {
        r.smooth.iter().map(|p| (p.speed_m_s, f(p))).collect()
    };
    let deflection = Chart::new("Smooth road: peak midspan deflection", "speed (m/s)", "mm")
        .with_series(Series::line_markers(
            "vehicle-bridge interaction",
            line(&|p| 1e3 * p.vbi.peak_deflection_m),
        ))
        .with_series(
            Series::line_markers(
                "moving forces",
                line(&|p| 1e3 * p.moving_force.peak_deflection_m),
            )
            .with_dashed(true),
        );
    let mut daf = Chart::new(
        "Smooth road: DAF = peak / static peak deflection",
        "speed (m/s)",
        "DAF",
    )
    .with_series(Series::line_markers(
        "vehicle-bridge interaction",
        line(&|p| p.vbi.peak_deflection_m / p.static_peak_m),
    ))
    .with_series(
        Series::line_markers(
            "moving forces",
            line(&|p| p.moving_force.peak_deflection_m / p.static_peak_m),
        )
        .with_dashed(true),
    );
    for (code, factor) in &r.codes {
        daf.hlines.push((*factor, format!("{code} {factor:.2}")));
    }
    let acceleration = Chart::new(
        "Smooth road: peak midspan acceleration",
        "speed (m/s)",
        "m/s^2",
    )
    .with_series(Series::line_markers(
        "vehicle-bridge interaction",
        line(&|p| p.vbi.peak_acceleration_m_s2),
    ))
    .with_series(
        Series::line_markers(
            "moving forces",
            line(&|p| p.moving_force.peak_acceleration_m_s2),
        )
        .with_dashed(true),
    );
    let dlc = Chart::new("Smooth road: DLC", "speed (m/s)", "max F / F_static")
        .with_series(Series::line_markers("front axle", line(&|p| p.vbi.dlc[0])))
        .with_series(Series::line_markers("rear axle", line(&|p| p.vbi.dlc[1])));
    Figure::grid(2, 2, &[deflection, daf, acceleration, dlc])
}
