//! Static axle loads against the weight and the lever rule, and vehicles crawling over the
//! bridge against the weights and the static influence lines.

use std::f64::consts::PI;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::physics::vehicle::{sprung_mass, GRAVITY_M_S2};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{analytic_beam, coupled, fe, half_car};

/// Static axle loads of both presets against the weight and the lever rule, and three
/// vehicles crawling over the bridge together: the sum of their tyre forces against the
/// sum of their weights, and the midspan deflection against the static influence lines.
pub fn static_loads() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_static_loads";
    let mut rows = Vec::new();
    for (preset, body_kg, axles_kg) in [
        ("two_axle_truck", 17_735.0, [1_500.0, 1_000.0]),
        ("vbi2d_e01", 10_500.0, [900.0, 900.0]),
    ] {
        let vehicle = half_car(preset, None)?;
        let weight_n = (body_kg + axles_kg[0] + axles_kg[1]) * GRAVITY_M_S2;
        // The presets put the CG at mid-wheelbase: the body's weight splits in half.
        let front_n = (0.5 * body_kg + axles_kg[0]) * GRAVITY_M_S2;
        // Static loads come from one LU solve of the 4x4 stiffness: round-off, ~1e-15.
        rows.push(CheckRow::relative(
            GROUP,
            format!("sum of static axle loads {preset}"),
            "gross weight (N)",
            weight_n,
            vehicle.gross_weight_n(),
            1e-12,
        ));
        rows.push(CheckRow::relative(
            GROUP,
            format!("front static axle load {preset}"),
            "lever rule, CG mid-wheelbase (N)",
            front_n,
            vehicle.axles[0].static_load_n,
            1e-12,
        ));
    }
    rows.extend(crawl_rows(GROUP)?);
    Ok(rows)
}

/// Three vehicles (two_axle_truck, vbi2d_e01, a 20 t sprung mass) 3 m apart crawl at
/// 0.5 m/s over the 30 m paper bridge (FE 20, 2 % Rayleigh damping) on a smooth road;
/// averages over the steps with every axle on the span, from 2 s after the last one came
/// on.
fn crawl_rows(group: &str) -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let model = BridgeModel::build(&beam, &fe(20), 0.02)?;
    let ab = analytic_beam(&beam)?;
    let road = LevelRoad;
    let (dt_s, speed, gap_m, first_front_m) = (5e-3, 0.5, 3.0, -1.0);
    let mut solver = coupled(&model, &road, dt_s, ContactLaw::Full)?;
    let vehicles = [
        half_car("two_axle_truck", None)?,
        half_car("vbi2d_e01", None)?,
        sprung_mass(20_000.0, 4.0e6, 2.0e4),
    ];
    let mut front_m = first_front_m;
    let mut weight_n = 0.0;
    for (id, v) in vehicles.into_iter().enumerate() {
        weight_n += v.gross_weight_n();
        let length = v.wheelbase_m();
        solver.add_vehicle(CoupledVehicle::new(id as u32, v, speed, front_m, 0));
        front_m -= length + gap_m;
    }
    // Distance from the first front axle to the last axle.
    let train_m = first_front_m - (front_m + gap_m);
    let first_front = |step: u64| first_front_m + speed * step as f64 * dt_s;
    let on_from = train_m + 2.0 * speed;
    let on_to = beam.length_m() - 0.5;
    let steps = ((on_to - first_front_m) / (speed * dt_s)).round() as u64;
    let mid = 0.5 * beam.length_m();
    let mut op = SparseVec::with_capacity(model.n_dof());
    let (mut sum_force, mut sum_w, mut sum_w_static, mut count) = (0.0, 0.0, 0.0, 0usize);
    let mut max_dev = 0.0f64;
    let stepper = Stepper::new(&model, DIVERGENCE_HINT);
    for step in 1..=steps {
        stepper.advance(&mut solver)?;
        if !(on_from..=on_to).contains(&first_front(step)) {
            continue;
        }
        let mut total = 0.0;
        let mut w_static = 0.0;
        for v in &solver.vehicles {
            for (j, axle) in v.dynamics.axles.iter().enumerate() {
                total += v.contact_force_n[j];
                let x = v.axle_x_m(j, step, dt_s);
                w_static += ab.static_deflection_m(mid, x, axle.static_load_n);
            }
        }
        sum_force += total;
        max_dev = max_dev.max((total - weight_n).abs() / weight_n);
        sum_w -= solver.bridge_response(mid, PointQuantity::Deflection, 0, &mut op);
        sum_w_static += w_static;
        count += 1;
    }
    let n = count.max(1) as f64;
    let window_s = n * dt_s;
    // The dynamic remainder. An axle rolling onto the span excites mode 1 by about
    // Omega / w1 of its static deflection (Omega = pi v / L = 0.052 rad/s, w1 = 23.7
    // rad/s: 2.2e-3); all axles in phase, the bridge vibrates by `vibration` x delta with
    // delta the static midspan deflection of the whole weight, and the vehicles riding on
    // it feel an acceleration `vibration` w1^2 delta, i.e. an inertial force of that over g
    // relative to their weight (following the quasi-static deflection adds v^2 w'' ~
    // 1e-6 m/s^2, negligible). The time average over the window T cancels a vibration to
    // ~2 / (w1 T) of its amplitude (the change of velocity over T). Tolerances: the max
    // deviation of the force sum within that acceleration bound; the means within 4x the
    // averaged bound (the amplitude is an order-of-magnitude estimate). The static part is
    // exact: Hermite elements with consistent point loads are nodally exact (midspan is a
    // node), and the tyre forces sum to the weight in equilibrium.
    let omega1 = model.omega_rad_s[0];
    let vibration = PI * speed / beam.length_m() / omega1;
    let delta_m = ab.static_midspan_deflection_m(weight_n);
    let acceleration_g = vibration * omega1 * omega1 * delta_m / GRAVITY_M_S2;
    let averaging = 2.0 / (omega1 * window_s);
    let what = format!("3 vehicles crawling at {speed} m/s, all on the span for {window_s:.1} s");
    Ok(vec![
        CheckRow::relative(
            group,
            format!("mean sum of tyre forces, {what}"),
            "sum of weights (N)",
            weight_n,
            sum_force / n,
            4.0 * acceleration_g * averaging,
        ),
        CheckRow::with_error(
            group,
            format!("max |sum F - sum W| / sum W, {what}"),
            "0 (inertial remainder)",
            0.0,
            max_dev,
            max_dev,
            acceleration_g,
        ),
        CheckRow::relative(
            group,
            format!("mean midspan deflection, {what}"),
            "static influence lines (m)",
            sum_w_static / n,
            sum_w / n,
            4.0 * vibration * averaging,
        ),
    ])
}
