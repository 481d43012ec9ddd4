//! Vehicle models built as `VehicleDynamics`: sprung mass, quarter car, and the rigid
//! pitch-plane body on n axles (the 4-DOF half car is n = 2; PHYSICS.md section 6).

use nalgebra::{DMatrix, DVector};

use super::dynamics::{Axle, VehicleDynamics, GRAVITY_M_S2};
use crate::error::Result;

/// A single mass on a spring and dashpot in contact with the road.
pub fn sprung_mass(mass_kg: f64, stiffness_n_m: f64, damping_n_s_m: f64) -> VehicleDynamics {
    VehicleDynamics {
        name: "sprung_mass".into(),
        mass: DMatrix::from_element(1, 1, mass_kg),
        damping: DMatrix::zeros(1, 1),
        stiffness: DMatrix::zeros(1, 1),
        axles: vec![Axle {
            offset_m: 0.0,
            dof: Some(0),
            tyre_stiffness_n_m: stiffness_n_m,
            tyre_damping_n_s_m: damping_n_s_m,
            static_load_n: mass_kg * GRAVITY_M_S2,
        }],
        parameters: vec![
            ("mass_kg".into(), mass_kg),
            ("stiffness_n_m".into(), stiffness_n_m),
            ("damping_n_s_m".into(), damping_n_s_m),
        ],
        dof_names: vec!["mass".into()],
    }
}

/// Parameters of one axle of a suspended vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxleParams {
    pub mass_kg: f64,
    pub suspension_stiffness_n_m: f64,
    pub suspension_damping_n_s_m: f64,
    pub tyre_stiffness_n_m: f64,
    pub tyre_damping_n_s_m: f64,
}

/// Quarter car: body on a suspension on one axle on a tyre. DOFs (body, axle).
pub fn quarter_car(body_mass_kg: f64, axle: AxleParams) -> VehicleDynamics {
    let (k, c) = (axle.suspension_stiffness_n_m, axle.suspension_damping_n_s_m);
    let spring = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);
    VehicleDynamics {
        name: "quarter_car".into(),
        mass: DMatrix::from_diagonal(&DVector::from_vec(vec![body_mass_kg, axle.mass_kg])),
        damping: &spring * c,
        stiffness: &spring * k,
        axles: vec![Axle {
            offset_m: 0.0,
            dof: Some(1),
            tyre_stiffness_n_m: axle.tyre_stiffness_n_m,
            tyre_damping_n_s_m: axle.tyre_damping_n_s_m,
            static_load_n: (body_mass_kg + axle.mass_kg) * GRAVITY_M_S2,
        }],
        parameters: vec![
            ("body_mass_kg".into(), body_mass_kg),
            ("axle_mass_kg".into(), axle.mass_kg),
            ("suspension_stiffness_n_m".into(), k),
            ("suspension_damping_n_s_m".into(), c),
            ("tyre_stiffness_n_m".into(), axle.tyre_stiffness_n_m),
            ("tyre_damping_n_s_m".into(), axle.tyre_damping_n_s_m),
        ],
        dof_names: vec!["body".into(), "axle".into()],
    }
}

/// A rigid body (bounce, pitch) on n suspended axles.
///
/// `axle_offsets_m` are distances behind the front axle, `cg_behind_front_m` the centre of
/// gravity's. The signed lever of axle j is `d_j = cg - offset_j` (positive ahead of the
/// CG), the body point above it moves `y_B + d_j theta`, and the stiffness is PHYSICS.md's
/// `[[sum k, sum k d, -k_j], [., sum k d^2, -k_j d_j], [-k_j, -k_j d_j, k_j]]` (tyres excluded).
pub fn rigid_body_on_axles(
    name: &str,
    body_mass_kg: f64,
    pitch_inertia_kg_m2: f64,
    cg_behind_front_m: f64,
    axle_offsets_m: &[f64],
    axles: &[AxleParams],
) -> Result<VehicleDynamics> {
    let n = axles.len();
    let dofs = 2 + n;
    let mut mass = DMatrix::zeros(dofs, dofs);
    mass[(0, 0)] = body_mass_kg;
    mass[(1, 1)] = pitch_inertia_kg_m2;
    let mut stiffness = DMatrix::zeros(dofs, dofs);
    let mut damping = DMatrix::zeros(dofs, dofs);
    for (j, (axle, &offset)) in axles.iter().zip(axle_offsets_m).enumerate() {
        mass[(2 + j, 2 + j)] = axle.mass_kg;
        // Spring between body point (y_B + d theta) and axle j: B^T k B, B = [1, d, -1 at axle].
        let d = cg_behind_front_m - offset;
        let mut b = DVector::zeros(dofs);
        b[0] = 1.0;
        b[1] = d;
        b[2 + j] = -1.0;
        let bbt = &b * b.transpose();
        stiffness += &bbt * axle.suspension_stiffness_n_m;
        damping += &bbt * axle.suspension_damping_n_s_m;
    }
    let mut parameters = vec![
        ("body_mass_kg".to_string(), body_mass_kg),
        ("pitch_inertia_kg_m2".to_string(), pitch_inertia_kg_m2),
        ("cg_behind_front_m".to_string(), cg_behind_front_m),
    ];
    let mut dof_names = vec!["body_bounce".to_string(), "body_pitch".to_string()];
    for (j, a) in axles.iter().enumerate() {
        let i = j + 1;
        parameters.extend([
            (format!("axle_{i}_offset_m"), axle_offsets_m[j]),
            (format!("axle_{i}_mass_kg"), a.mass_kg),
            (
                format!("axle_{i}_suspension_stiffness_n_m"),
                a.suspension_stiffness_n_m,
            ),
            (
                format!("axle_{i}_suspension_damping_n_s_m"),
                a.suspension_damping_n_s_m,
            ),
            (format!("axle_{i}_tyre_stiffness_n_m"), a.tyre_stiffness_n_m),
            (format!("axle_{i}_tyre_damping_n_s_m"), a.tyre_damping_n_s_m),
        ]);
        dof_names.push(format!("axle_{i}"));
    }
    let axle_list = axles
        .iter()
        .zip(axle_offsets_m)
        .enumerate()
        .map(|(j, (a, &offset))| Axle {
            offset_m: offset,
            dof: Some(2 + j),
            tyre_stiffness_n_m: a.tyre_stiffness_n_m,
            tyre_damping_n_s_m: a.tyre_damping_n_s_m,
            static_load_n: 0.0,
        })
        .collect();
    let mut vehicle = VehicleDynamics {
        name: name.to_string(),
        mass,
        damping,
        stiffness,
        axles: axle_list,
        parameters,
        dof_names,
    };
    let mut gravity = DVector::zeros(dofs);
    gravity[0] = -body_mass_kg * GRAVITY_M_S2;
    for (j, a) in axles.iter().enumerate() {
        gravity[2 + j] = -a.mass_kg * GRAVITY_M_S2;
    }
    vehicle.set_static_loads_from_gravity(&gravity)?;
    Ok(vehicle)
}
