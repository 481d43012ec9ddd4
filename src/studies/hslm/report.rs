//! The HSLM study's outputs: CSV, SVG figures and summary.md.

use std::fmt::Write;
use std::path::Path;

use crate::error::Result;
use crate::studies::analytic::resonance::resonance_speeds_m_s;
use crate::studies::output::{write_file, write_svg_file};
use crate::studies::plot::{Chart, Figure, Series};

use super::{
    frequency_band_hz, hslm_parameters, phi2, phi3, HslmReport, Row, LIMIT_BALLASTED_M_S2,
    LIMIT_DIRECT_FASTENING_M_S2, LINE_SPEED_KM_H,
};

pub(super) fn write_outputs(out: &Path, r: &HslmReport) -> Result<()> {
    write_file(&out.join("hslm.csv"), &rows_csv(r))?;
    write_file(&out.join("envelope.csv"), &envelope_csv(r))?;
    for (b, bridge) in r.bridges.iter().enumerate() {
        write_svg_file(
            &out.join(format!("acceleration_{}.svg", bridge.name)),
            &acceleration_figure(r, b)?,
        )?;
    }
    write_svg_file(&out.join("interaction.svg"), &interaction_figure(r)?)?;
    write_svg_file(&out.join("closed_forms.svg"), &closed_form_figure(r)?)?;
    write_svg_file(&out.join("dynamic_factor.svg"), &factor_figure(r)?)?;
    write_file(&out.join("summary.md"), &summary(r))
}

fn rows_csv(r: &HslmReport) -> String {
    let mut csv = String::from(
        "bridge,train,model,speed_km_h,acceleration_m_s2,deflection_mm,moment_kn_m,\
         static_moment_kn_m,moment_factor,min_wheel_ratio,der_m_s2,lir_m_s2\n",
    );
    for row in &r.rows {
        let _ = writeln!(
            csv,
            "{},A{},{},{},{:.5},{:.5},{:.3},{:.3},{:.5},{:.5},{:.5},{:.5}",
            r.bridges[row.bridge].name,
            row.train,
            model_name(row.vehicles),
            row.speed_km_h,
            row.peaks.acceleration_m_s2,
            1e3 * row.peaks.deflection_m,
            1e-3 * row.peaks.moment_n_m,
            1e-3 * row.static_moment_n_m,
            row.moment_factor(),
            row.peaks.min_wheel_ratio,
            row.der_m_s2,
            row.lir_m_s2
        );
    }
    csv
}

fn model_name(vehicles: bool) -> &'static str {
    if vehicles {
        "vehicles"
    } else {
        "moving_forces"
    }
}

/// The rows of one bridge and model.
fn rows_of(r: &HslmReport, b: usize, vehicles: bool) -> impl Iterator<Item = &Row> {
    r.rows
        .iter()
        .filter(move |row| row.bridge == b && row.vehicles == vehicles)
}

/// Per speed, the row with the largest acceleration over the trains.
fn envelope(r: &HslmReport, b: usize, vehicles: bool) -> Vec<&Row> {
    r.speeds_km_h
        .iter()
        .filter_map(|&v| {
            rows_of(r, b, vehicles)
                .filter(|row| row.speed_km_h == v)
                .max_by(|x, y| {
                    x.peaks
                        .acceleration_m_s2
                        .total_cmp(&y.peaks.acceleration_m_s2)
                })
        })
        .collect()
}

fn envelope_csv(r: &HslmReport) -> String {
    let mut csv = String::from(
        "bridge,model,speed_km_h,worst_train,acceleration_m_s2,max_deflection_mm,max_moment_factor\n",
    );
    for b in 0..r.bridges.len() {
        for vehicles in [false, true] {
            for row in envelope(r, b, vehicles) {
                let same_speed =
                    || rows_of(r, b, vehicles).filter(|x| x.speed_km_h == row.speed_km_h);
                let deflection = same_speed()
                    .map(|x| x.peaks.deflection_m)
                    .fold(0.0, f64::max);
                let factor = same_speed().map(Row::moment_factor).fold(0.0, f64::max);
                let _ = writeln!(
                    csv,
                    "{},{},{},A{},{:.5},{:.5},{:.5}",
                    r.bridges[b].name,
                    model_name(vehicles),
                    row.speed_km_h,
                    row.train,
                    row.peaks.acceleration_m_s2,
                    1e3 * deflection,
                    factor
                );
            }
        }
    }
    csv
}

/// Vertical marker at `x` from 0 to `top`, as a dashed series.
fn marker(name: String, x: f64, top: f64) -> Series {
    Series::line(name, vec![(x, 0.0), (x, top)]).with_dashed(true)
}

fn acceleration_figure(r: &HslmReport, b: usize) -> Result<String> {
    let bridge = &r.bridges[b];
    let mut chart = Chart::new(
        format!(
            "{}: deck acceleration, HSLM-A as moving forces (n0 = {:.2} Hz, zeta = {:.2} %)",
            bridge.name,
            r.frequencies_hz[b][0],
            100.0 * bridge.damping_ratio()
        ),
        "speed (km/h)",
        "max |deck acceleration| (m/s^2)",
    )
    .with_size(900, 560)
    .with_hline(LIMIT_BALLASTED_M_S2, "ballasted 3.5 m/s^2")
    .with_hline(LIMIT_DIRECT_FASTENING_M_S2, "direct fastening 5 m/s^2");
    for &t in &r.trains {
        let points = rows_of(r, b, false)
            .filter(|row| row.train == t)
            .map(|row| (row.speed_km_h, row.peaks.acceleration_m_s2))
            .collect();
        chart = chart.with_series(Series::line(format!("A{t}"), points));
    }
    // The worst train's resonances v = n0 D / i.
    let worst = worst_row(r, b, false);
    let top = worst.map_or(1.0, |w| w.peaks.acceleration_m_s2);
    if let Some(w) = worst {
        let coach_m = hslm_parameters(w.train).1;
        let (lo, hi) = (r.speeds_km_h[0] / 3.6, 1.2 * LINE_SPEED_KM_H / 3.6);
        for (i, v) in resonance_speeds_m_s(r.frequencies_hz[b][0], coach_m, lo, hi) {
            chart = chart.with_series(marker(format!("A{} n0 D / {i}", w.train), 3.6 * v, top));
        }
    }
    chart.to_svg()
}

fn worst_row(r: &HslmReport, b: usize, vehicles: bool) -> Option<&Row> {
    rows_of(r, b, vehicles).max_by(|x, y| {
        x.peaks
            .acceleration_m_s2
            .total_cmp(&y.peaks.acceleration_m_s2)
    })
}

fn interaction_figure(r: &HslmReport) -> Result<String> {
    let charts: Vec<Chart> = (0..r.bridges.len())
        .map(|b| {
            let line = |vehicles| {
                envelope(r, b, vehicles)
                    .iter()
                    .map(|row| (row.speed_km_h, row.peaks.acceleration_m_s2))
                    .collect()
            };
            Chart::new(
                format!("{}: envelope over A1-A10", r.bridges[b].name),
                "speed (km/h)",
                "max |deck acceleration| (m/s^2)",
            )
            .with_series(Series::line("moving forces", line(false)))
            .with_series(Series::line("vehicle models", line(true)).with_dashed(true))
            .with_hline(LIMIT_BALLASTED_M_S2, "3.5 m/s^2")
        })
        .collect();
    Figure::grid_titled(
        "Moving forces against vehicle models: what the interaction takes off",
        1,
        charts.len(),
        &charts,
    )
}

fn closed_form_figure(r: &HslmReport) -> Result<String> {
    let charts: Vec<Chart> = (0..r.bridges.len())
        .map(|b| {
            let env = envelope(r, b, false);
            let max_over = |f: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> {
                r.speeds_km_h
                    .iter()
                    .map(|&v| {
                        let m = rows_of(r, b, false)
                            .filter(|row| row.speed_km_h == v)
                            .map(f)
                            .fold(0.0, f64::max);
                        (v, m)
                    })
                    .collect()
            };
            Chart::new(
                format!("{}: envelope over A1-A10", r.bridges[b].name),
                "speed (km/h)",
                "max |deck acceleration| (m/s^2)",
            )
            .with_series(Series::line(
                "simulated (moving forces, modes to cut-off)",
                env.iter()
                    .map(|row| (row.speed_km_h, row.peaks.acceleration_m_s2))
                    .collect(),
            ))
            .with_series(
                Series::line("LIR (mode 1)", max_over(&|row| row.lir_m_s2)).with_dashed(true),
            )
            .with_series(
                Series::line("DER (mode 1)", max_over(&|row| row.der_m_s2)).with_dashed(true),
            )
        })
        .collect();
    Figure::grid_titled(
        "Simulation against the closed-form envelopes (ERRI D214)",
        1,
        charts.len(),
        &charts,
    )
}

fn factor_figure(r: &HslmReport) -> Result<String> {
    let charts: Vec<Chart> = r
        .bridges
        .iter()
        .enumerate()
        .map(|(b, bridge)| {
            let points = r
                .speeds_km_h
                .iter()
                .map(|&v| {
                    let m = rows_of(r, b, false)
                        .filter(|row| row.speed_km_h == v)
                        .map(Row::moment_factor)
                        .fold(0.0, f64::max);
                    (v, m)
                })
                .collect();
            let l = bridge.length_m();
            Chart::new(
                format!("{}: midspan moment, dynamic / static", bridge.name),
                "speed (km/h)",
                "1 + phi'_dyn (max over A1-A10)",
            )
            .with_series(Series::line("moving forces", points))
            .with_hline(phi2(l), format!("Phi2 = {:.3}", phi2(l)))
            .with_hline(phi3(l), format!("Phi3 = {:.3}", phi3(l)))
        })
        .collect();
    Figure::grid_titled(
        "Dynamic increment of the moment against the static factors",
        1,
        charts.len(),
        &charts,
    )
}

fn summary(r: &HslmReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# HSLM-A dynamic check (EN 1991-2 6.4.6)\n\n\
         {} trains x {} speeds ({}-{} km/h, 1.2 x a {LINE_SPEED_KM_H} km/h line) x {} bridges, \
         as moving forces ({:.0} s) and as vehicle models ({:.0} s) on this machine{}.\n\n\
         Rules as commonly quoted from EN 1991-2 (its text was not at hand): deck acceleration \
         limits 3.5 m/s^2 (ballasted) and 5 m/s^2 (direct fastening) with the modes up to \
         max(30 Hz, 1.5 n0, n3); Table 6.6 lower-bound damping; Phi2 = 1.44/(sqrt(L) - 0.2) + \
         0.82, Phi3 = 2.16/(sqrt(L) - 0.2) + 0.73. Vehicle models: articulated rakes on the \
         Eurostar bogies of Domenech (2014), every axle at P.\n",
        r.trains.len(),
        r.speeds_km_h.len(),
        r.speeds_km_h[0],
        r.speeds_km_h[r.speeds_km_h.len() - 1],
        r.bridges.len(),
        r.moving_force_s,
        r.vehicles_s,
        if r.quick { " (quick grid)" } else { "" }
    );
    let _ = writeln!(
        s,
        "| bridge | n0 (Hz) | Fig. 6.10 band (Hz) | damping | modes kept (cut-off) | worst train, speed | max accel. moving forces | vehicle models | limit (ballasted) | max 1 + phi'_dyn | Phi2 / Phi3 |\n\
         |---|---|---|---|---|---|---|---|---|---|---|"
    );
    for (b, bridge) in r.bridges.iter().enumerate() {
        let (lo, hi) = frequency_band_hz(bridge.length_m());
        let mf = worst_row(r, b, false);
        let veh = worst_row(r, b, true);
        let factor = rows_of(r, b, false)
            .map(Row::moment_factor)
            .fold(0.0, f64::max);
        let l = bridge.length_m();
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:.2}-{:.2} | {:.2} % ({}) | {} ({:.0} Hz) | {} | {:.2} m/s^2 | {} | {} | {:.3} | {:.3} / {:.3} |",
            bridge.name,
            r.frequencies_hz[b][0],
            lo,
            hi,
            100.0 * bridge.damping_ratio(),
            bridge.deck.label(),
            r.kept_modes[b],
            r.cutoff_hz[b],
            mf.map_or("-".into(), |w| format!("A{} at {} km/h", w.train, w.speed_km_h)),
            mf.map_or(0.0, |w| w.peaks.acceleration_m_s2),
            veh.map_or("-".into(), |w| format!(
                "{:.2} m/s^2 (A{} at {} km/h)",
                w.peaks.acceleration_m_s2, w.train, w.speed_km_h
            )),
            if mf.is_some_and(|w| w.peaks.acceleration_m_s2 > LIMIT_BALLASTED_M_S2) {
                "exceeded"
            } else {
                "met"
            },
            factor,
            phi2(l),
            phi3(l)
        );
    }
    let _ = writeln!(
        s,
        "\nFigures: `acceleration_<bridge>.svg` (every train, limits, the worst train's \
         resonances v = n0 D / i), `interaction.svg` (moving forces against vehicle models), \
         `closed_forms.svg` (against DER and LIR), `dynamic_factor.svg`. Data: `hslm.csv`, \
         `envelope.csv`."
    );
    s
}
