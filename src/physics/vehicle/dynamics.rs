//! The vehicle as the coupled solver sees it: linear matrices of the suspended system
//! (tyres excluded) and a list of tyre contacts. Any linear pitch-plane vehicle (moving
//! force, sprung mass, quarter car, half car, multi-axle truck, tractor + trailer) is one
//! of these, so new vehicle types never touch the solver.

use nalgebra::{Complex, DMatrix, DVector};

use crate::error::{Error, Result};

pub use crate::base::units::GRAVITY_M_S2;

/// One tyre: a spring and dashpot between a vehicle DOF and the road surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Axle {
    /// Distance behind the front axle (m, >= 0).
    pub offset_m: f64,
    /// The vehicle DOF the tyre acts on; `None` for a moving force (no dynamics).
    pub dof: Option<usize>,
    /// Tyre stiffness (N/m).
    pub tyre_stiffness_n_m: f64,
    /// Tyre damping (N s/m).
    pub tyre_damping_n_s_m: f64,
    /// Static axle load on a level rigid road (N, downward force on the road, > 0).
    pub static_load_n: f64,
}

/// Linear vehicle model; displacements upward positive from static equilibrium on a
/// level rigid road.
#[derive(Debug, Clone)]
pub struct VehicleDynamics {
    /// Model name for output ("half_car/two_axle_truck").
    pub name: String,
    /// Mass matrix of the vehicle DOFs (kg, kg m^2).
    pub mass: DMatrix<f64>,
    /// Suspension damping (tyres excluded).
    pub damping: DMatrix<f64>,
    /// Suspension stiffness (tyres excluded).
    pub stiffness: DMatrix<f64>,
    pub axles: Vec<Axle>,
    /// Named parameters for the truth record.
    pub parameters: Vec<(String, f64)>,
    /// Names of the DOFs ("body_bounce", "body_pitch", "axle_1", ...).
    pub dof_names: Vec<String>,
}

impl VehicleDynamics {
    /// A set of constant forces (no DOFs): `loads_n` downward, `offsets_m` behind the front axle.
    pub fn moving_forces(loads_n: &[f64], offsets_m: &[f64]) -> Self {
        let axles = loads_n
            .iter()
            .zip(offsets_m)
            .map(|(&load, &offset)| Axle {
                offset_m: offset,
                dof: None,
                tyre_stiffness_n_m: 0.0,
                tyre_damping_n_s_m: 0.0,
                static_load_n: load,
            })
            .collect();
        VehicleDynamics {
            name: "moving_force".into(),
            mass: DMatrix::zeros(0, 0),
            damping: DMatrix::zeros(0, 0),
            stiffness: DMatrix::zeros(0, 0),
            axles,
            parameters: Vec::new(),
            dof_names: Vec::new(),
        }
    }

    /// This vehicle with every spring (suspension and tyres) times `stiffness_factor` and
    /// every damper times `damping_factor`: one vehicle of a class differing from the
    /// next. Scaling all springs alike keeps the static axle loads exactly (the static
    /// deflections scale by 1 / factor, the forces do not change), so the drawn weights
    /// and load shares stay the truth. The factors join the truth-record parameters.
    pub fn varied(mut self, stiffness_factor: f64, damping_factor: f64) -> Self {
        self.stiffness *= stiffness_factor;
        self.damping *= damping_factor;
        for axle in &mut self.axles {
            axle.tyre_stiffness_n_m *= stiffness_factor;
            axle.tyre_damping_n_s_m *= damping_factor;
        }
        self.parameters
            .push(("variation_stiffness_factor".into(), stiffness_factor));
        self.parameters
            .push(("variation_damping_factor".into(), damping_factor));
        self
    }

    /// Number of vehicle DOFs.
    pub fn n_dof(&self) -> usize {
        self.mass.nrows()
    }

    /// Gross weight (N).
    pub fn gross_weight_n(&self) -> f64 {
        self.axles.iter().map(|a| a.static_load_n).sum()
    }

    /// Distance from the front to the last axle (m).
    pub fn wheelbase_m(&self) -> f64 {
        self.axles.iter().map(|a| a.offset_m).fold(0.0, f64::max)
    }

    /// Stiffness with the tyres attached to a rigid road.
    pub fn stiffness_with_tyres(&self) -> DMatrix<f64> {
        let mut k = self.stiffness.clone();
        for axle in &self.axles {
            if let Some(d) = axle.dof {
                k[(d, d)] += axle.tyre_stiffness_n_m;
            }
        }
        k
    }

    /// Damping with the tyres attached to a rigid road.
    pub fn damping_with_tyres(&self) -> DMatrix<f64> {
        let mut c = self.damping.clone();
        for axle in &self.axles {
            if let Some(d) = axle.dof {
                c[(d, d)] += axle.tyre_damping_n_s_m;
            }
        }
        c
    }

    /// Eigenvalues (1/s) of the free vehicle on a rigid road, from its first-order system
    /// matrix `[[0, I], [-M^-1 K, -M^-1 C]]` with the tyres attached: a complex pair per
    /// underdamped mode, `-Re` its decay rate, `-Re / |lambda|` its damping ratio.
    pub fn rigid_road_eigenvalues(&self) -> Result<DVector<Complex<f64>>> {
        let n = self.n_dof();
        let inverse_mass = self
            .mass
            .clone()
            .try_inverse()
            .ok_or_else(|| Error::Factorization {
                what: format!("mass matrix of {}", self.name),
                reason: "singular".into(),
            })?;
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n))
            .copy_from(&(-&inverse_mass * self.stiffness_with_tyres()));
        a.view_mut((n, n), (n, n))
            .copy_from(&(-&inverse_mass * self.damping_with_tyres()));
        Ok(a.complex_eigenvalues())
    }

    /// Static axle loads from gravity: solves the vehicle on rigid tyre supports under
    /// `gravity_forces_n` (per DOF, upward positive) and sets each axle's static load.
    pub fn set_static_loads_from_gravity(&mut self, gravity_forces_n: &DVector<f64>) -> Result<()> {
        let k = self.stiffness_with_tyres();
        let y = k
            .lu()
            .solve(gravity_forces_n)
            .ok_or_else(|| Error::Factorization {
                what: format!("static stiffness of vehicle {}", self.name),
                reason: "singular (a DOF without spring support?)".into(),
            })?;
        for axle in &mut self.axles {
            if let Some(d) = axle.dof {
                // Tyre compression force on the road = -kt * y (y < 0 under gravity).
                axle.static_load_n = -axle.tyre_stiffness_n_m * y[d];
            }
        }
        Ok(())
    }

    /// Vehicle displacements in static equilibrium on a road whose elevation under each
    /// axle is `road_m[j]` (rigid road): `(K + sum kt e e^T) y = sum kt e r`.
    pub fn equilibrium_on_road(&self, road_m: &[f64]) -> DVector<f64> {
        let n = self.n_dof();
        let mut rhs = DVector::zeros(n);
        for (axle, &r) in self.axles.iter().zip(road_m) {
            if let Some(d) = axle.dof {
                rhs[d] += axle.tyre_stiffness_n_m * r;
            }
        }
        // A level road (every tyre at zero elevation): the equilibrium is the origin, with
        // no factorization (a 16-car train's stiffness is 160 x 160).
        if n == 0 || rhs.iter().all(|&f| f == 0.0) {
            return DVector::zeros(n);
        }
        self.stiffness_with_tyres()
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| DVector::zeros(n))
    }
}
