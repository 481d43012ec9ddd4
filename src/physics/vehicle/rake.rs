//! A rake of railway vehicles in the pitch plane: car bodies resting through the secondary
//! suspension on bogies, each bogie on two wheelsets through the primary suspension, each
//! wheelset on the rail through a linearised Hertz contact spring (the solver's "tyre").
//!
//! One layout serves every railway vehicle: a conventional car (a body on its own two
//! bogies), a train of such cars (no spring between cars: the couplers carry no vertical
//! load in this model, so each car is an independent block the solver handles apart) and an
//! articulated rake (bodies sharing Jacobs bogies, one coupled block).
//!
//! Positions are distances behind the train's first wheelset (m). A spring between a point
//! of a rigid body at lever `d` (positive ahead of the body's centre, as in
//! `rigid_body_on_axles`) and a DOF below stretches by `z + d theta - z_below`, so each
//! spring adds `k B B^T` with that `B`.

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

/// A car body: bounce and pitch about its centre of gravity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CarBody {
    /// Centre of gravity behind the first wheelset (m).
    pub centre_m: f64,
    pub mass_kg: f64,
    pub pitch_inertia_kg_m2: f64,
}

/// A two-axle bogie with its wheelsets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bogie {
    /// Bogie centre (the pivot) behind the first wheelset (m).
    pub centre_m: f64,
    /// Distance between its two wheelsets (m).
    pub wheelbase_m: f64,
    pub frame_mass_kg: f64,
    pub frame_pitch_inertia_kg_m2: f64,
    pub wheelset_mass_kg: f64,
    /// Per wheelset (both axleboxes).
    pub primary: Suspension,
    /// Linearised wheel-rail contact per wheelset, both wheels (N/m).
    pub contact_stiffness_n_m: f64,
}

/// Body `body` rests on bogie `bogie`'s centre through `secondary` (both sides).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pivot {
    pub body: usize,
    pub bogie: usize,
    pub secondary: Suspension,
}

/// Bodies, bogies and which body rests on which bogie.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RakeLayout {
    pub bodies: Vec<CarBody>,
    pub bogies: Vec<Bogie>,
    pub pivots: Vec<Pivot>,
}

impl RakeLayout {
    /// Appends `other` shifted `offset_m` back (its bodies and bogies renumbered).
    pub fn append(&mut self, other: &RakeLayout, offset_m: f64) {
        let (b0, g0) = (self.bodies.len(), self.bogies.len());
        self.bodies.extend(other.bodies.iter().map(|b| CarBody {
            centre_m: b.centre_m + offset_m,
            ..*b
        }));
        self.bogies.extend(other.bogies.iter().map(|g| Bogie {
            centre_m: g.centre_m + offset_m,
            ..*g
        }));
        self.pivots.extend(other.pivots.iter().map(|p| Pivot {
            body: p.body + b0,
            bogie: p.bogie + g0,
            ..*p
        }));
    }

    /// Wheelset positions behind the first one (m), front to rear.
    pub fn wheelset_offsets_m(&self) -> Vec<f64> {
        self.bogies
            .iter()
            .flat_map(|g| {
                [
                    g.centre_m - 0.5 * g.wheelbase_m,
                    g.centre_m + 0.5 * g.wheelbase_m,
                ]
            })
            .collect()
    }

    /// DOFs: each body (bounce, pitch), each bogie (bounce, pitch), then each wheelset.
    fn dof_names(&self) -> Vec<String> {
        let single = self.bodies.len() == 1;
        let body = |i: usize, what: &str| match single {
            true => format!("body_{what}"),
            false => format!("body_{}_{what}", i + 1),
        };
        let mut names = Vec::new();
        for i in 0..self.bodies.len() {
            names.push(body(i, "bounce"));
            names.push(body(i, "pitch"));
        }
        for i in 0..self.bogies.len() {
            names.push(format!("bogie_{}_bounce", i + 1));
            names.push(format!("bogie_{}_pitch", i + 1));
        }
        names.extend((0..2 * self.bogies.len()).map(|w| format!("wheelset_{}", w + 1)));
        names
    }

    /// The rake's matrices and contacts, static wheel loads from gravity.
    pub fn build(&self, name: &str, parameters: Vec<(String, f64)>) -> Result<VehicleDynamics> {
        let nb = 2 * self.bodies.len();
        let first_wheelset = nb + 2 * self.bogies.len();
        let n = first_wheelset + 2 * self.bogies.len();
        let mut mass = DVector::zeros(n);
        for (i, b) in self.bodies.iter().enumerate() {
            mass[2 * i] = b.mass_kg;
            mass[2 * i + 1] = b.pitch_inertia_kg_m2;
        }
        for (i, g) in self.bogies.iter().enumerate() {
            mass[nb + 2 * i] = g.frame_mass_kg;
            mass[nb + 2 * i + 1] = g.frame_pitch_inertia_kg_m2;
            mass[first_wheelset + 2 * i] = g.wheelset_mass_kg;
            mass[first_wheelset + 2 * i + 1] = g.wheelset_mass_kg;
        }
        let mut stiffness = DMatrix::zeros(n, n);
        let mut damping = DMatrix::zeros(n, n);
        let mut spring = |upper: (usize, f64), lower: usize, s: Suspension| {
            // (bounce DOF of the upper body, the lever of the point on it), the lower DOF:
            // k B B^T over the three entries of B = e_bounce + lever e_pitch - e_lower.
            let b = [(upper.0, 1.0), (upper.0 + 1, upper.1), (lower, -1.0)];
            for &(i, bi) in &b {
                for &(j, bj) in &b {
                    stiffness[(i, j)] += s.stiffness_n_m * bi * bj;
                    damping[(i, j)] += s.damping_n_s_m * bi * bj;
                }
            }
        };
        for p in &self.pivots {
            let (body, bogie) = (&self.bodies[p.body], &self.bogies[p.bogie]);
            let lever = body.centre_m - bogie.centre_m;
            spring((2 * p.body, lever), nb + 2 * p.bogie, p.secondary);
        }
        for (i, g) in self.bogies.iter().enumerate() {
            for (w, lever) in [(0, 0.5 * g.wheelbase_m), (1, -0.5 * g.wheelbase_m)] {
                spring((nb + 2 * i, lever), first_wheelset + 2 * i + w, g.primary);
            }
        }
        let axles = self
            .wheelset_offsets_m()
            .into_iter()
            .enumerate()
            .map(|(w, offset_m)| Axle {
                offset_m,
                dof: Some(first_wheelset + w),
                tyre_stiffness_n_m: self.bogies[w / 2].contact_stiffness_n_m,
                tyre_damping_n_s_m: 0.0,
                static_load_n: 0.0,
            })
            .collect();
        // Gravity on the bounce DOFs only (a pitch DOF carries no weight).
        let gravity = DVector::from_fn(n, |d, _| match d < first_wheelset && d % 2 == 1 {
            true => 0.0,
            false => -mass[d] * GRAVITY_M_S2,
        });
        let mut rake = VehicleDynamics {
            name: name.to_string(),
            mass: DMatrix::from_diagonal(&mass),
            damping,
            stiffness,
            axles,
            parameters,
            dof_names: self.dof_names(),
        };
        rake.set_static_loads_from_gravity(&gravity)?;
        Ok(rake)
    }
}
