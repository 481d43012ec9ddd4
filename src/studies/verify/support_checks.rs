//! The supports of continuous girders: reactions against the three-moment equation and
//! equilibrium (static and on a slow crossing), the static effect of a settlement against
//! its closed forms, and the frequency of a girder on a softened pier.

use nalgebra::DVector;

use super::girder_checks::girder;
use super::CheckRow;
use crate::error::{Error, Result};
use crate::physics::bridge::{
    BeamProperties, BridgeModel, LumpedStiffness, ModelSpec, PointQuantity, ReactionOperator,
    ReactionState, SettlementField, Support,
};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::analytic::{Condition, ContinuousBeam};
use crate::studies::continuous::example_beam;

const GROUP: &str = "girder_supports";
const EI_N_M2: f64 = 5.629e10;

/// Two equal spans `l` of the paper's section on `pier`.
fn two_spans(l: f64, pier: Support) -> BeamProperties {
    girder(&[l, l], &[Support::Pinned, pier, Support::Roller], [0.0; 2])
}

/// The two models the statics rows hold to round-off: 40 Hermite elements and 39 lumped
/// masses (loads and supports on their nodes) with K by `stiffness`.
fn fe_and_lumped(stiffness: LumpedStiffness) -> [ModelSpec; 2] {
    [
        ModelSpec::FiniteElement { elements: 40 },
        ModelSpec::LumpedMass {
            nodes: 39,
            stiffness,
        },
    ]
}

/// The static displacement of `model` under `loads` ((x, upward N)).
fn static_state(model: &BridgeModel, loads: &[(f64, f64)]) -> Result<DVector<f64>> {
    let mut f = DVector::zeros(model.n_dof());
    for &(x, p) in loads {
        f += model.point_load_vector(x, p);
    }
    let chol = model
        .stiffness
        .to_dense()
        .cholesky()
        .ok_or_else(|| Error::Factorization {
            what: "girder stiffness".into(),
            reason: "not positive definite".into(),
        })?;
    Ok(chol.solve(&f))
}

/// Every row of the group.
pub fn girder_supports() -> Result<Vec<CheckRow>> {
    let mut rows = pier_reactions()?;
    rows.extend(static_balance()?);
    rows.push(slow_crossing_balance()?);
    rows.extend(settlement()?);
    rows.extend(softened_pier()?);
    Ok(rows)
}

/// The pier reaction of two 30 m spans under a unit load at `a` in span one:
/// `R = a / L + a (L^2 - a^2) / (2 L^3)` (the three-moment equation). Exact at statics
/// with the load on a node (FE) or a mass (lumped): 1e-9.
fn pier_reactions() -> Result<Vec<CheckRow>> {
    let l = 30.0;
    let beam = two_spans(l, Support::Roller);
    let mut rows = Vec::new();
    for spec in fe_and_lumped(LumpedStiffness::Auto) {
        let model = BridgeModel::build(&beam, &spec, 0.0)?;
        for a in [7.5, 15.0, 22.5] {
            let u = static_state(&model, &[(a, -1.0)])?;
            let r = model.support_reactions(&ReactionState {
                u: &u,
                v: None,
                a: None,
                loads: &[(a, -1.0)],
            });
            rows.push(CheckRow::relative(
                GROUP,
                format!("pier reaction, unit load at {a} m, {}", spec.label()),
                "three-moment equation (N)",
                a / l + a * (l * l - a * a) / (2.0 * l.powi(3)),
                r[1],
                1e-9,
            ));
        }
    }
    Ok(rows)
}

/// The reactions of the three-span example (haunched) balance a static load anywhere,
/// also between nodes and on a support: 1e-9 of the load (round-off).
fn static_balance() -> Result<Vec<CheckRow>> {
    let model = BridgeModel::build(
        &example_beam()?,
        &ModelSpec::FiniteElement { elements: 104 },
        0.0,
    )?;
    let mut worst = 0.0f64;
    for i in 0..=39 {
        let x = 2.0 * i as f64;
        let u = static_state(&model, &[(x, -1e5)])?;
        let r = model.support_reactions(&ReactionState {
            u: &u,
            v: None,
            a: None,
            loads: &[(x, -1e5)],
        });
        worst = worst.max((r.iter().sum::<f64>() - 1e5).abs() / 1e5);
    }
    Ok(vec![CheckRow::with_error(
        GROUP,
        "sum of reactions, 100 kN at every 2 m of the three-span example, FE 104".into(),
        "the load (relative error, worst of 40)",
        1.0,
        1.0 + worst,
        worst,
        1e-9,
    )])
}

/// A 100 kN force crossing the three-span example at 1 m/s (dt = 10 ms, 5 % damping):
/// the reactions balance the force at every step to the inertia of a slow crossing, at
/// most 5e-3 of the load (the force stepping onto the girder excites it most).
fn slow_crossing_balance() -> Result<CheckRow> {
    let model = BridgeModel::build(
        &example_beam()?,
        &ModelSpec::FiniteElement { elements: 78 },
        0.05,
    )?;
    let road = LevelRoad;
    let coefficients = NewmarkCoefficients::new(0.01, NewmarkParams::default())?;
    let mut solver = CoupledSolver::new(
        &model,
        &road,
        coefficients,
        SolveMode::Prefactored(Storage::Sparse),
        ContactLaw::Full,
    )?;
    let force = VehicleDynamics::moving_forces(&[1e5], &[0.0]);
    solver.add_vehicle(CoupledVehicle::new(0, force, 1.0, -1.0, 0));
    let operator = ReactionOperator::new(&model);
    let mut r = vec![0.0; operator.len()];
    let mut loads = Vec::with_capacity(1);
    let mut worst = 0.0f64;
    let length = model.length_m();
    for _ in 0..8000 {
        solver.advance()?;
        let v = &solver.vehicles[0];
        let x = v.axle_x_m(0, solver.step, 0.01);
        let on = (0.0..=length).contains(&x);
        loads.clear();
        if on {
            loads.push((x, -v.contact_force_n[0]));
        }
        let s = &solver.bridge.state;
        operator.reactions(
            &ReactionState {
                u: &s.u,
                v: Some(&s.v),
                a: Some(&s.a),
                loads: &loads,
            },
            &mut r,
        );
        let load = if on { v.contact_force_n[0] } else { 0.0 };
        worst = worst.max((r.iter().sum::<f64>() - load).abs() / 1e5);
    }
    Ok(CheckRow::with_error(
        GROUP,
        "sum of reactions at each of 8000 steps, 100 kN crossing three spans at 1 m/s".into(),
        "the force on the girder (worst error over the load)",
        1.0,
        1.0 + worst,
        worst,
        5e-3,
    ))
}

/// Two equal 20 m spans whose pier settles 10 mm: the pier sheds `6 EI d / L^3` to the
/// abutments, its moment rises by `3 EI d / L^2`; FE and lumped (the field is their
/// mesh's, exact for the piecewise-cubic solution): 1e-9.
fn settlement() -> Result<Vec<CheckRow>> {
    let (l, d) = (20.0f64, 0.01);
    let beam = two_spans(l, Support::Roller);
    let mut rows = Vec::new();
    for spec in fe_and_lumped(LumpedStiffness::Condensation) {
        let model = BridgeModel::build(&beam, &spec, 0.0)?;
        let field = SettlementField::new(&model)?;
        let settled = [0.0, d, 0.0];
        let mut r = [0.0; 3];
        field.reactions(&settled, &mut r);
        let values = field.node_values(&settled);
        let shed = 6.0 * EI_N_M2 * d / l.powi(3);
        rows.push(CheckRow::relative(
            GROUP,
            format!("pier reaction, pier settled 10 mm, {}", spec.label()),
            "-6 EI d / L^3 (N)",
            -shed,
            r[1],
            1e-9,
        ));
        rows.push(CheckRow::relative(
            GROUP,
            format!("abutment reaction, pier settled 10 mm, {}", spec.label()),
            "3 EI d / L^3 (N)",
            0.5 * shed,
            r[0],
            1e-9,
        ));
        rows.push(CheckRow::relative(
            GROUP,
            format!("pier moment, pier settled 10 mm, {}", spec.label()),
            "3 EI d / L^2 (N m)",
            3.0 * EI_N_M2 * d / (l * l),
            field.read(&values, l, PointQuantity::Moment),
            1e-9,
        ));
    }
    Ok(rows)
}

/// f1 of two 20 m spans on a pier spring that has lost half of 2e8 N/m (a degraded bearing
/// or scour) against the exact frequency determinant with springs: within the FE bound
/// of 40 elements, 1e-4.
fn softened_pier() -> Result<Vec<CheckRow>> {
    let mut rows = Vec::new();
    for (what, kv) in [
        ("intact pier, 2e8 N/m", 2e8),
        ("softened pier, 1e8 N/m", 1e8),
    ] {
        let pier = Support::Elastic {
            vertical_n_m: kv,
            rotational_n_m_rad: 0.0,
        };
        let beam = two_spans(20.0, pier);
        let model = BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 40 }, 0.0)?;
        let exact = ContinuousBeam {
            pieces_m: vec![20.0, 20.0],
            conditions: vec![
                Condition::Pinned,
                Condition::Springs {
                    vertical_n_m: kv,
                    rotational_n_m_rad: 0.0,
                },
                Condition::Pinned,
            ],
            flexural_rigidity_n_m2: beam.flexural_rigidity_n_m2,
            mass_per_length_kg_m: beam.mass_per_length_kg_m,
        }
        .frequencies_hz(1)?[0];
        rows.push(CheckRow::relative(
            GROUP,
            format!("f1 of two 20 m spans, {what}, FE 40"),
            "exact frequency determinant (Hz)",
            exact,
            model.frequency_hz(1),
            1e-4,
        ));
    }
    Ok(rows)
}
