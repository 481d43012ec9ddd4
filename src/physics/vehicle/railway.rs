//! A railway car in the pitch plane: the car body (bounce, pitch) on two bogies (bounce,
//! pitch) through the secondary suspension, each bogie on two wheelsets through the
//! primary suspension, each wheelset on the rail through a linearised Hertz contact
//! spring. Ten DOFs; the solver sees it as any other linear vehicle (the contact spring is
//! the "tyre"), so trains need no solver change.
//!
//! Levers are signed as in `rigid_body_on_axles`: positive ahead of the body's centre. A
//! spring between a point of one body at lever `d` and another DOF stretches by
//! `z + d theta - z_other`, so each spring adds `k B B^T` with that `B`.

use nalgebra::{DMatrix, DVector};

use super::dynamics::{Axle, VehicleDynamics, GRAVITY_M_S2};
use crate::error::Result;

/// One suspension stage: stiffness and damping of the springs at one point, summed over
/// the track's two sides (N/m, N s/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Suspension {
    pub stiffness_n_m: f64,
    pub damping_n_s_m: f64,
}

/// A symmetric railway car (conventional: its own two bogies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailwayCarParams {
    /// Car body mass (kg) and pitch inertia about its centre (kg m^2).
    pub body_mass_kg: f64,
    pub body_pitch_inertia_kg_m2: f64,
    /// Half the distance between the bogie pivots (m).
    pub bogie_half_spacing_m: f64,
    /// Bogie frame mass (kg) and pitch inertia (kg m^2).
    pub bogie_mass_kg: f64,
    pub bogie_pitch_inertia_kg_m2: f64,
    /// Half the bogie wheelbase (m).
    pub wheelbase_half_m: f64,
    /// Wheelset mass (kg).
    pub wheelset_mass_kg: f64,
    /// Per bogie (both sides).
    pub secondary: Suspension,
    /// Per wheelset (both sides).
    pub primary: Suspension,
    /// Linearised Hertz contact stiffness per wheelset, both wheels (N/m).
    pub contact_stiffness_n_m: f64,
}

/// DOF order: body bounce, body pitch, front bogie bounce and pitch, rear bogie bounce and
/// pitch, wheelsets 1-4 from the front.
const DOF_NAMES: [&str; 10] = [
    "body_bounce",
    "body_pitch",
    "bogie_1_bounce",
    "bogie_1_pitch",
    "bogie_2_bounce",
    "bogie_2_pitch",
    "wheelset_1",
    "wheelset_2",
    "wheelset_3",
    "wheelset_4",
];

impl RailwayCarParams {
    /// Wheelset positions behind the front wheelset (m): 0, 2 lt, 2 lc, 2 lc + 2 lt.
    pub fn wheelset_offsets_m(&self) -> [f64; 4] {
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        [0.0, 2.0 * lt, 2.0 * lc, 2.0 * lc + 2.0 * lt]
    }

    /// The car's matrices and contacts, static wheel loads from gravity.
    pub fn build(&self, name: &str) -> Result<VehicleDynamics> {
        let n = DOF_NAMES.len();
        let mut mass = DMatrix::zeros(n, n);
        for (d, m) in [
            self.body_mass_kg,
            self.body_pitch_inertia_kg_m2,
            self.bogie_mass_kg,
            self.bogie_pitch_inertia_kg_m2,
            self.bogie_mass_kg,
            self.bogie_pitch_inertia_kg_m2,
        ]
        .into_iter()
        .chain([self.wheelset_mass_kg; 4])
        .enumerate()
        {
            mass[(d, d)] = m;
        }
        let mut stiffness = DMatrix::zeros(n, n);
        let mut damping = DMatrix::zeros(n, n);
        let mut spring = |from: (usize, usize, f64), to: usize, s: Suspension| {
            // (bounce DOF, pitch DOF, lever) of the upper body, the lower DOF.
            let mut b = DVector::zeros(n);
            b[from.0] = 1.0;
            b[from.1] = from.2;
            b[to] = -1.0;
            let bbt = &b * b.transpose();
            stiffness += &bbt * s.stiffness_n_m;
            damping += &bbt * s.damping_n_s_m;
        };
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        for (bogie, lever) in [(0usize, lc), (1, -lc)] {
            let bounce = 2 + 2 * bogie;
            spring((0, 1, lever), bounce, self.secondary);
            for (w, l) in [(0usize, lt), (1, -lt)] {
                spring((bounce, bounce + 1, l), 6 + 2 * bogie + w, self.primary);
            }
        }
        let axles = self
            .wheelset_offsets_m()
            .iter()
            .enumerate()
            .map(|(w, &offset)| Axle {
                offset_m: offset,
                dof: Some(6 + w),
                tyre_stiffness_n_m: self.contact_stiffness_n_m,
                tyre_damping_n_s_m: 0.0,
                static_load_n: 0.0,
            })
            .collect();
        let mut car = VehicleDynamics {
            name: name.to_string(),
            mass: mass.clone(),
            damping,
            stiffness,
            axles,
            parameters: self.parameters(),
            dof_names: DOF_NAMES.iter().map(|s| s.to_string()).collect(),
        };
        // Gravity on the bounce DOFs only (a pitch DOF carries no weight).
        let gravity = DVector::from_fn(n, |d, _| match d {
            1 | 3 | 5 => 0.0,
            _ => -mass[(d, d)] * GRAVITY_M_S2,
        });
        car.set_static_loads_from_gravity(&gravity)?;
        Ok(car)
    }

    fn parameters(&self) -> Vec<(String, f64)> {
        [
            ("body_mass_kg", self.body_mass_kg),
            ("body_pitch_inertia_kg_m2", self.body_pitch_inertia_kg_m2),
            ("bogie_half_spacing_m", self.bogie_half_spacing_m),
            ("bogie_mass_kg", self.bogie_mass_kg),
            ("bogie_pitch_inertia_kg_m2", self.bogie_pitch_inertia_kg_m2),
            ("wheelbase_half_m", self.wheelbase_half_m),
            ("wheelset_mass_kg", self.wheelset_mass_kg),
            ("secondary_stiffness_n_m", self.secondary.stiffness_n_m),
            ("secondary_damping_n_s_m", self.secondary.damping_n_s_m),
            ("primary_stiffness_n_m", self.primary.stiffness_n_m),
            ("primary_damping_n_s_m", self.primary.damping_n_s_m),
            ("contact_stiffness_n_m", self.contact_stiffness_n_m),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
    }
}
