//! A railway car in the pitch plane: the car body (bounce, pitch) on two bogies (bounce,
//! pitch) through the secondary suspension, each bogie on two wheelsets through the
//! primary suspension, each wheelset on the rail through a linearised Hertz contact
//! spring. Ten DOFs; the solver sees it as any other linear vehicle (the contact spring is
//! the "tyre"), so trains need no solver change. Built as a rake of one body
//! (`rake.rs`).

use super::dynamics::VehicleDynamics;
use super::rake::{Bogie, CarBody, Pivot, RakeLayout, Suspension};
use crate::error::Result;

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

impl RailwayCarParams {
    /// Wheelset positions behind the front wheelset (m): 0, 2 lt, 2 lc, 2 lc + 2 lt.
    pub fn wheelset_offsets_m(&self) -> [f64; 4] {
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        [0.0, 2.0 * lt, 2.0 * lc, 2.0 * lc + 2.0 * lt]
    }

    /// The car as a rake of one body on two bogies.
    pub fn layout(&self) -> RakeLayout {
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        let bogie = |centre_m| Bogie {
            centre_m,
            wheelbase_m: 2.0 * lt,
            frame_mass_kg: self.bogie_mass_kg,
            frame_pitch_inertia_kg_m2: self.bogie_pitch_inertia_kg_m2,
            wheelset_mass_kg: self.wheelset_mass_kg,
            primary: self.primary,
            contact_stiffness_n_m: self.contact_stiffness_n_m,
        };
        let pivot = |bogie| Pivot {
            body: 0,
            bogie,
            secondary: self.secondary,
        };
        RakeLayout {
            bodies: vec![CarBody {
                centre_m: lt + lc,
                mass_kg: self.body_mass_kg,
                pitch_inertia_kg_m2: self.body_pitch_inertia_kg_m2,
            }],
            bogies: vec![bogie(lt), bogie(lt + 2.0 * lc)],
            pivots: vec![pivot(0), pivot(1)],
        }
    }

    /// The car's matrices and contacts, static wheel loads from gravity. DOFs: body bounce
    /// and pitch, front bogie bounce and pitch, rear bogie bounce and pitch, wheelsets 1-4.
    pub fn build(&self, name: &str) -> Result<VehicleDynamics> {
        self.layout().build(name, self.parameters())
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
