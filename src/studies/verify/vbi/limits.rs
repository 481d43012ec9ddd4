//! The sprung mass's soft and stiff suspension limits: the moving force and the moving mass.

use crate::error::Result;
use crate::physics::bridge::BridgeModel;
use crate::physics::road::LevelRoad;
use crate::physics::vehicle::{sprung_mass, GRAVITY_M_S2};
use crate::studies::analytic::moving_mass::{MovingMassOptions, MovingMassProblem};
use crate::studies::analytic::{
    ModalDamping, MovingForceSolution, SprungMassOptions, SprungMassProblem, SprungMassVehicle,
};
use crate::studies::verify::harness::{moving_force_history, MovingForceCase};
use crate::studies::verify::CheckRow;

use super::sprung_mass::{
    sprung_mass_history, REFERENCE_MODES, SPRUNG_MASS_KG, SPRUNG_SPEED_M_S, SPRUNG_STIFFNESS_N_M,
};
use super::{analytic_beam, fe, peak, vbi_beam};

/// The sprung mass of the VBI-2D case with its stiffness scaled down tends to the moving
/// force m g, scaled up to the moving mass (`analytic::moving_mass`).
pub fn suspension_limits() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_limits";
    let beam = vbi_beam();
    let ab = analytic_beam(&beam)?;
    let dt_s = 5e-4;
    let model = BridgeModel::build(&beam, &fe(20), 0.0)?;
    let weight_n = SPRUNG_MASS_KG * GRAVITY_M_S2;
    let mut rows = Vec::new();

    // Soft limit, numerical model against the numerical moving force on the same model
    // and step, so that only the suspension differs.
    let (_, force_history) = moving_force_history(&MovingForceCase {
        beam: beam.clone(),
        spec: fe(20),
        damping_ratio: 0.0,
        force_n: weight_n,
        speed_m_s: SPRUNG_SPEED_M_S,
        dt_s,
        free_time_s: 0.0,
    })?;
    let force_peak = peak(&force_history);
    let fryba = MovingForceSolution::new(ab, weight_n, SPRUNG_SPEED_M_S, ModalDamping::None, 100)?;
    let exit_s = beam.length_m() / SPRUNG_SPEED_M_S;
    let (_, fryba_peak) = fryba.peak_deflection_m(0.5 * beam.length_m(), exit_s);
    let discretization = ((force_peak - fryba_peak) / fryba_peak).abs();
    // The limit itself: the same bound as the moving_force group (1e-3 on the peak).
    rows.push(CheckRow::relative(
        GROUP,
        format!(
            "moving force m g, peak midspan {} dt={dt_s}",
            model.spec.label()
        ),
        "Fryba 100 modes (m)",
        fryba_peak,
        force_peak,
        1e-3,
    ));
    for scale in [1e-1, 1e-2, 1e-3] {
        let k = SPRUNG_STIFFNESS_N_M * scale;
        let vehicle = sprung_mass(SPRUNG_MASS_KG, k, 0.0);
        let history = sprung_mass_history(&model, &LevelRoad, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
        let error = ((peak(&history) - force_peak) / force_peak).abs();
        // The spring's dynamic force is k s with |s| <= |y| + |w| <= 3 w_max (the mass,
        // driven through the spring from rest, moves at most twice the base), so the
        // contact force departs from m g by <= 3 k w_max, and the peak by that fraction
        // of m g: tolerance 3 k w_max / (m g), proportional to k.
        let tolerance = 3.0 * k * force_peak / weight_n;
        rows.push(CheckRow::with_error(
            GROUP,
            format!("soft k = {k:.4e} N/m: peak midspan {}", model.spec.label()),
            "moving force m g, same model and dt",
            force_peak,
            peak(&history),
            error,
            tolerance,
        ));
    }

    // Stiff limit. A spring of frequency w_v passes the contact point's motion to the
    // mass amplified by 1 / (1 - (w / w_v)^2): once w_v is above the beam modes that
    // carry the contact point's acceleration, the sprung mass's extra inertial force, and
    // its difference from the moving mass, fall as 1/k (10x per decade of k; below that,
    // w_v crosses beam modes and the difference is not monotone: 1.9e-4 at k = 1.6e8,
    // 5.8e-5 at 1.6e9 N/m, measured). Rows: the analytic sprung mass at 1e3, 1e4, 1e5
    // times the nominal k must be within a tenth of the gap between the two limits
    // (moving force to moving mass) and then shrink >= 3x per decade; the numerical
    // model at the same k within that analytic difference plus twice its own
    // discretization error (measured on the moving force above).
    let moving_mass = MovingMassProblem {
        beam: ab,
        mass_kg: SPRUNG_MASS_KG,
        speed_m_s: SPRUNG_SPEED_M_S,
        options: MovingMassOptions {
            n_modes: REFERENCE_MODES,
            gravity_m_s2: GRAVITY_M_S2,
            ..Default::default()
        },
    }
    .solve(&[exit_s])?;
    let mm_peak = moving_mass.peak_midspan_deflection_on_beam_m;
    let fryba_25 = MovingForceSolution::new(
        ab,
        weight_n,
        SPRUNG_SPEED_M_S,
        ModalDamping::None,
        REFERENCE_MODES,
    )?;
    let gap =
        ((mm_peak - fryba_25.peak_deflection_m(0.5 * beam.length_m(), exit_s).1) / mm_peak).abs();
    let mut previous = 10.0 * gap;
    for scale in [1e3, 1e4, 1e5] {
        let k = SPRUNG_STIFFNESS_N_M * scale;
        let sprung = SprungMassProblem {
            beam: ab,
            vehicle: SprungMassVehicle {
                mass_kg: SPRUNG_MASS_KG,
                stiffness_n_m: k,
                damping_n_s_m: 0.0,
            },
            speed_m_s: SPRUNG_SPEED_M_S,
            road: None,
            options: SprungMassOptions {
                n_modes: REFERENCE_MODES,
                gravity_m_s2: GRAVITY_M_S2,
                ..Default::default()
            },
        }
        .solve(&[exit_s])?;
        let value = sprung.peak_midspan_deflection_on_beam_m;
        let analytic_error = ((value - mm_peak) / mm_peak).abs();
        rows.push(CheckRow::with_error(
            GROUP,
            format!("stiff k = {k:.4e} N/m: peak midspan, sprung_mass 25 modes"),
            "moving_mass 25 modes (m)",
            mm_peak,
            value,
            analytic_error,
            if scale == 1e3 {
                0.1 * gap
            } else {
                previous / 3.0
            },
        ));
        previous = analytic_error;
        let vehicle = sprung_mass(SPRUNG_MASS_KG, k, 0.0);
        let history = sprung_mass_history(&model, &LevelRoad, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
        let value = peak(&history);
        rows.push(CheckRow::with_error(
            GROUP,
            format!(
                "stiff k = {k:.4e} N/m: peak midspan {} dt={dt_s}",
                model.spec.label()
            ),
            "moving_mass 25 modes (m)",
            mm_peak,
            value,
            ((value - mm_peak) / mm_peak).abs(),
            analytic_error + 2.0 * discretization + 1e-6,
        ));
    }
    Ok(rows)
}
