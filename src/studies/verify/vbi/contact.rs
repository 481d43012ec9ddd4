//! Unilateral against full (tension-capable) tyre contact over a dip.

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::RoadProfileSpec;
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{coupled, deterministic_road, fe, half_car, max_abs, vbi_beam};

/// What one run over the bump recorded.
#[derive(Debug, Default)]
struct ContactRun {
    /// (step, axle) pairs with the tyre lifted off.
    airborne: u64,
    /// Largest |tyre force| while lifted off (N).
    max_force_airborne_n: f64,
    /// Landings: a tyre in contact again after a lift-off.
    recontacts: u64,
    /// Smallest total tyre force / static load.
    min_force_ratio: f64,
    /// Largest |recorded force - tyre law at the solved state| / static, tyres in contact.
    max_law_residual: f64,
    /// Largest tyre-law force (static included) / static while lifted off: <= 0 means
    /// the tyre would indeed be in tension, i.e. the gap is open.
    max_law_airborne: f64,
    /// Steps the solver counted as contact loss.
    contact_loss_steps: u64,
    /// Midspan deflection per step (m, upward).
    midspan_m: Vec<f64>,
    /// First step with a tyre lifted off or in tension.
    first_loss_step: Option<u64>,
    all_in_contact_at_end: bool,
}

/// The contact case: two_axle_truck at 20 m/s over a raised-cosine dip 40 mm deep and
/// 1 m long at x = 6 m on the VBI-2D beam (FE 20, 2 % damping). A raised 40 mm bump of
/// 0.5-2 m only unloads this heavily damped truck's tyres to 2-35 % of their static load
/// at 15-25 m/s (it lifts off for a few steps at most); over the dip the wheels cannot
/// follow the falling road and fly for ~15 ms each.
fn bump_run(law: ContactLaw) -> Result<ContactRun> {
    let (height_m, length_m, speed) = (-0.040, 1.0, 20.0);
    let beam = vbi_beam();
    let model = BridgeModel::build(&beam, &fe(20), 0.02)?;
    let bump = RoadProfileSpec::Bump {
        position_m: 6.0,
        length_m,
        height_m,
    };
    let road = deterministic_road(&bump, -50.0, 150.0)?;
    let dt_s = 5e-4;
    let mut solver = coupled(&model, &road, dt_s, law)?;
    let truck = half_car("two_axle_truck", None)?;
    solver.add_vehicle(CoupledVehicle::new(0, truck, speed, -10.0, 0));
    let steps = ((10.0 + beam.length_m() + 15.0) / (speed * dt_s)).round() as u64;
    let mut run = ContactRun {
        min_force_ratio: f64::INFINITY,
        max_law_airborne: f64::NEG_INFINITY,
        ..Default::default()
    };
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut was_airborne = [false; 2];
    let stepper = Stepper::new(&model, DIVERGENCE_HINT);
    for step in 1..=steps {
        stepper.advance(&mut solver)?;
        run.midspan_m.push(solver.bridge_response(
            0.5 * beam.length_m(),
            PointQuantity::Deflection,
            0,
            &mut op,
        ));
        let v = &solver.vehicles[0];
        for (j, axle) in v.dynamics.axles.iter().enumerate() {
            let Some(dof) = axle.dof else { continue };
            let x = v.axle_x_m(j, step, dt_s);
            let w = solver.bridge_response(x, PointQuantity::Deflection, 0, &mut op);
            let w_rate = solver.bridge_response(x, PointQuantity::Deflection, 1, &mut op);
            let w_slope = solver.bridge_response(x, PointQuantity::Slope, 0, &mut op);
            let z = w + road.elevation_m(x);
            let z_rate = w_rate + speed * (w_slope + road.slope(x));
            let law = axle.static_load_n
                + axle.tyre_stiffness_n_m * (z - v.state.u[dof])
                + axle.tyre_damping_n_s_m * (z_rate - v.state.v[dof]);
            let force = v.contact_force_n[j];
            run.min_force_ratio = run.min_force_ratio.min(force / axle.static_load_n);
            if v.in_contact[j] {
                run.max_law_residual = run
                    .max_law_residual
                    .max((force - law).abs() / axle.static_load_n);
                if was_airborne[j] {
                    run.recontacts += 1;
                }
            } else {
                run.airborne += 1;
                run.max_force_airborne_n = run.max_force_airborne_n.max(force.abs());
                run.max_law_airborne = run.max_law_airborne.max(law / axle.static_load_n);
            }
            if (!v.in_contact[j] || force < 0.0) && run.first_loss_step.is_none() {
                run.first_loss_step = Some(step);
            }
            was_airborne[j] = !v.in_contact[j];
        }
        run.all_in_contact_at_end = v.in_contact.iter().all(|&c| c);
        run.contact_loss_steps = v.contact_loss_steps;
    }
    Ok(run)
}

/// A flag as a row: error 0 when `ok`, 1 otherwise.
fn flag_row(group: &str, check: String, reference: &str, value: f64, ok: bool) -> CheckRow {
    let error = if ok { 0.0 } else { 1.0 };
    CheckRow::with_error(group, check, reference, 0.0, value, error, 0.0)
}

/// Unilateral and full (tension-capable) tyres over the dip of [`bump_run`].
pub fn unilateral_contact() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_contact";
    let unilateral = bump_run(ContactLaw::Unilateral)?;
    let full = bump_run(ContactLaw::Full)?;
    let what = "two_axle_truck 20 m/s, 40 mm dip";
    let mut rows = vec![
        flag_row(
            GROUP,
            format!("unilateral: tyre-steps lifted off, {what}"),
            "> 0",
            unilateral.airborne as f64,
            unilateral.airborne > 0,
        ),
        // An airborne tyre's row of the contact system pins f = -F_static; the total
        // is then F_static + (-F_static), exactly 0.
        CheckRow::with_error(
            GROUP,
            format!("unilateral: max |F| while lifted off, {what}"),
            "0 (N)",
            0.0,
            unilateral.max_force_airborne_n,
            unilateral.max_force_airborne_n,
            0.0,
        ),
        flag_row(
            GROUP,
            format!("unilateral: landings after lift-off, {what}"),
            "> 0, all tyres in contact at the end",
            unilateral.recontacts as f64,
            unilateral.recontacts > 0 && unilateral.all_in_contact_at_end,
        ),
        flag_row(
            GROUP,
            format!("unilateral: contact_loss_steps, {what}"),
            "> 0",
            unilateral.contact_loss_steps as f64,
            unilateral.contact_loss_steps > 0,
        ),
        flag_row(
            GROUP,
            format!("unilateral: min F / F_static, {what}"),
            ">= 0 (no tension)",
            unilateral.min_force_ratio,
            unilateral.min_force_ratio >= 0.0,
        ),
        // While lifted off, the tyre law at the solved state gives tension (<= 0): the
        // wheel is really above the road, not held off it. The active set decides on the
        // same linear law, so the sign is exact up to round-off.
        flag_row(
            GROUP,
            format!("unilateral: max tyre-law force / F_static while lifted off, {what}"),
            "<= 0 (gap open)",
            unilateral.max_law_airborne,
            unilateral.max_law_airborne <= 1e-9,
        ),
    ];
    for (name, run) in [("unilateral", &unilateral), ("full", &full)] {
        // The recorded force is the tyre law kt (z - y) + ct (dz/dt - dy/dt), with the
        // convective term v (dw/dx + dr/dx), evaluated at the committed state: the
        // solver eliminates it exactly, so only round-off of the small solve remains
        // (forces ~1e5 N, states ~1e-2 m with kt ~ 4e6 N/m: ~1e-12 relative).
        rows.push(CheckRow::with_error(
            GROUP,
            format!("{name}: max |F - tyre law| / F_static in contact, {what}"),
            "0",
            0.0,
            run.max_law_residual,
            run.max_law_residual,
            1e-9,
        ));
    }
    rows.push(flag_row(
        GROUP,
        format!("full: min F / F_static, {what}"),
        "< 0 (tension)",
        full.min_force_ratio,
        full.min_force_ratio < 0.0 && full.airborne == 0 && full.contact_loss_steps > 0,
    ));
    // Both laws solve the same system until the first tyre would pull.
    let first = unilateral
        .first_loss_step
        .unwrap_or(unilateral.midspan_m.len() as u64) as usize;
    let before = max_abs(
        unilateral.midspan_m[..first.saturating_sub(1)]
            .iter()
            .zip(&full.midspan_m)
            .map(|(a, b)| a - b),
    );
    rows.push(CheckRow::with_error(
        GROUP,
        format!("unilateral vs full midspan before the first lift-off, {what}"),
        "identical (m)",
        0.0,
        before,
        before,
        0.0,
    ));
    Ok(rows)
}
