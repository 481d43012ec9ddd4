//! Vehicle models built as `VehicleDynamics`: sprung mass, quarter car, and the rigid
//! pitch-plane body on n axles (the 4-DOF half car is n = 2; docs/physics.md section 6).

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
/// CG), the body point above it moves `y_B + d_j theta`, and the stiffness is docs/physics.md's
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
    for (j, (a, &offset)) in axles.iter().zip(axle_offsets_m).enumerate() {
        parameters.extend(axle_parameters(j + 1, offset, a));
        dof_names.push(format!("axle_{}", j + 1));
    }
    let axle_list = tyre_contacts(axle_offsets_m, axles, 2);
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

/// Mass properties of one rigid body of a pitch-plane model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyParams {
    /// Sprung mass of the body (kg), axles excluded.
    pub mass_kg: f64,
    /// Pitch moment of inertia about the body's centre of gravity (kg m^2).
    pub pitch_inertia_kg_m2: f64,
    /// Centre of gravity behind the vehicle's front axle (m).
    pub cg_behind_front_m: f64,
}

/// A rigid truck (or car): one body on n >= 2 suspended axles.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidTruckParams {
    pub body: BodyParams,
    /// Distances behind the front axle (m), ascending, the first 0.
    pub axle_offsets_m: Vec<f64>,
    /// One entry per axle, front first.
    pub axles: Vec<AxleParams>,
}

impl RigidTruckParams {
    /// The model, with static axle loads from gravity (`rigid_body_on_axles`).
    pub fn build(&self, name: &str) -> Result<VehicleDynamics> {
        rigid_body_on_axles(
            name,
            self.body.mass_kg,
            self.body.pitch_inertia_kg_m2,
            self.body.cg_behind_front_m,
            &self.axle_offsets_m,
            &self.axles,
        )
    }
}

/// The truth-record parameters of axle `i` (1-based).
pub(crate) fn axle_parameters(i: usize, offset_m: f64, a: &AxleParams) -> [(String, f64); 6] {
    [
        (format!("axle_{i}_offset_m"), offset_m),
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
    ]
}

/// Tyre contacts of axles whose hop DOFs are `first_dof`, `first_dof + 1`, ...; static
/// loads are left at 0 for `set_static_loads_from_gravity`.
pub(crate) fn tyre_contacts(
    offsets_m: &[f64],
    axles: &[AxleParams],
    first_dof: usize,
) -> Vec<Axle> {
    axles
        .iter()
        .zip(offsets_m)
        .enumerate()
        .map(|(j, (a, &offset))| Axle {
            offset_m: offset,
            dof: Some(first_dof + j),
            tyre_stiffness_n_m: a.tyre_stiffness_n_m,
            tyre_damping_n_s_m: a.tyre_damping_n_s_m,
            static_load_n: 0.0,
        })
        .collect()
}
