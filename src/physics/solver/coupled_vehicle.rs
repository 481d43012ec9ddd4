//! A vehicle in the coupled step, with its own Newmark state.
//!
//! A train is one vehicle whose matrices fall apart into independent blocks (the cars of a
//! conventional train share no spring; an articulated rake is one block). The vehicle is
//! split into those blocks once, when it appears: each block keeps its own matrices,
//! factor and tyre influence columns, so a step costs the sum of the blocks' small dense
//! products instead of one product of the whole train's size, and tyres of different
//! blocks are not coupled through the vehicle (the contact solve can treat them apart).

use nalgebra::{DMatrix, DVector};

use super::newmark::{NewmarkCoefficients, State};
use crate::error::{Error, Result};
use crate::physics::road::RoadSurface;
use crate::physics::vehicle::VehicleDynamics;

/// One independent part of a vehicle: DOFs coupled by its mass, damping or stiffness.
struct Block {
    /// The vehicle DOFs of the block, ascending.
    dofs: Vec<usize>,
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    factor: nalgebra::linalg::Cholesky<f64, nalgebra::Dyn>,
    /// Per tyre of the block (`tyres[i]` is the axle): `K_eff,b^-1 e_dof` over the block.
    tyres: Vec<usize>,
    w: Vec<DVector<f64>>,
    /// Block-local work vectors.
    gathered: DVector<f64>,
    history: DVector<f64>,
}

/// A vehicle on the road, with its own Newmark state.
pub struct CoupledVehicle {
    pub id: u32,
    pub dynamics: VehicleDynamics,
    pub speed_m_s: f64,
    /// +1 travelling towards +x (from the left support), -1 towards -x (the opposite
    /// lane, entering at the right support); axles trail the front axle accordingly.
    pub direction: f64,
    /// Front-axle position when the vehicle appears (m).
    pub start_front_x_m: f64,
    /// Step index at which it appears.
    pub entry_step: u64,
    pub state: State,
    /// Total tyre force of each axle at the last step (N, compression positive).
    pub contact_force_n: Vec<f64>,
    /// Whether each tyre touched the road at the last step.
    pub in_contact: Vec<bool>,
    /// Steps with at least one tyre in tension or lifted off.
    pub contact_loss_steps: u64,
    pub(super) active: bool,
    pub(super) retired: bool,
    blocks: Vec<Block>,
    /// Per DOF: its block and its place in the block.
    block_of_dof: Vec<(usize, usize)>,
    /// Per axle: the block of its tyre DOF and the tyre's index among the block's tyres.
    block_of_axle: Vec<Option<(usize, usize)>>,
    /// The displacement predicted from the history alone, then corrected by the tyre forces.
    pub(super) y0: DVector<f64>,
}

impl CoupledVehicle {
    /// A vehicle that appears at `entry_step` with its front axle at `start_front_x_m`.
    pub fn new(
        id: u32,
        dynamics: VehicleDynamics,
        speed_m_s: f64,
        start_front_x_m: f64,
        entry_step: u64,
    ) -> Self {
        let n = dynamics.n_dof();
        let axles = dynamics.axles.len();
        CoupledVehicle {
            id,
            speed_m_s,
            direction: 1.0,
            start_front_x_m,
            entry_step,
            state: State::zeros(n),
            contact_force_n: dynamics.axles.iter().map(|a| a.static_load_n).collect(),
            in_contact: vec![true; axles],
            contact_loss_steps: 0,
            active: false,
            retired: false,
            blocks: Vec::new(),
            block_of_dof: Vec::new(),
            block_of_axle: vec![None; axles],
            y0: DVector::zeros(n),
            dynamics,
        }
    }

    /// Position of axle `j` at step `step` (m).
    pub fn axle_x_m(&self, j: usize, step: u64, dt_s: f64) -> f64 {
        let travelled = self.speed_m_s * (step.saturating_sub(self.entry_step)) as f64 * dt_s;
        self.start_front_x_m + self.direction * (travelled - self.dynamics.axles[j].offset_m)
    }

    /// The same vehicle travelling towards -x (`direction < 0`) or +x.
    pub fn with_direction(mut self, direction: i8) -> Self {
        self.direction = if direction < 0 { -1.0 } else { 1.0 };
        self
    }

    /// Signed velocity along x (m/s): what the road slope under a tyre is multiplied by.
    pub fn velocity_m_s(&self) -> f64 {
        self.direction * self.speed_m_s
    }

    /// Whether every axle is more than `margin_m` beyond the end of a `span_m` bridge it
    /// crosses in its direction at `step`.
    pub fn has_left(&self, span_m: f64, margin_m: f64, step: u64, dt_s: f64) -> bool {
        let last = self.dynamics.axles.len() - 1;
        let x = self.axle_x_m(last, step, dt_s);
        match self.direction > 0.0 {
            true => x > span_m + margin_m,
            false => x < -margin_m,
        }
    }

    /// True once the vehicle has appeared and until it is retired.
    pub fn is_active(&self) -> bool {
        self.active
    }

    /// True once the vehicle has left the modelled road.
    pub fn is_retired(&self) -> bool {
        self.retired
    }

    /// Number of independent blocks the vehicle was split into (0 before it appears).
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// The block of axle `j`'s tyre DOF (`None` for a moving force).
    pub(super) fn block_of_axle(&self, j: usize) -> Option<usize> {
        self.block_of_axle[j].map(|(b, _)| b)
    }

    /// Static equilibrium on the road under the axles, and the blocks' factors.
    pub(super) fn activate(
        &mut self,
        road: &dyn RoadSurface,
        step: u64,
        coefficients: &NewmarkCoefficients,
    ) -> Result<()> {
        let dt = coefficients.dt_s;
        let under: Vec<f64> = (0..self.dynamics.axles.len())
            .map(|j| road.elevation_m(self.axle_x_m(j, step, dt)))
            .collect();
        self.state.u = self.dynamics.equilibrium_on_road(&under);
        self.split_into_blocks(coefficients)?;
        self.active = true;
        Ok(())
    }

    fn split_into_blocks(&mut self, coefficients: &NewmarkCoefficients) -> Result<()> {
        let d = &self.dynamics;
        let k_eff = &d.stiffness + &d.mass * coefficients.a0 + &d.damping * coefficients.a1;
        self.blocks.clear();
        self.block_of_dof = vec![(0, 0); d.n_dof()];
        for dofs in connected_dofs(&k_eff, &d.mass, &d.damping) {
            let sub = |a: &DMatrix<f64>| a.select_rows(&dofs).select_columns(&dofs);
            let factor = sub(&k_eff).cholesky().ok_or_else(|| Error::Factorization {
                what: format!("effective matrix of vehicle {}", self.id),
                reason: "not positive definite (check masses)".into(),
            })?;
            let b = self.blocks.len();
            for (place, &dof) in dofs.iter().enumerate() {
                self.block_of_dof[dof] = (b, place);
            }
            let m = dofs.len();
            self.blocks.push(Block {
                mass: sub(&d.mass),
                damping: sub(&d.damping),
                factor,
                tyres: Vec::new(),
                w: Vec::new(),
                gathered: DVector::zeros(m),
                history: DVector::zeros(m),
                dofs,
            });
        }
        for (j, axle) in d.axles.iter().enumerate() {
            self.block_of_axle[j] = axle.dof.map(|dof| {
                let (b, place) = self.block_of_dof[dof];
                let block = &mut self.blocks[b];
                let mut col = DVector::zeros(block.dofs.len());
                col[place] = 1.0;
                block.factor.solve_mut(&mut col);
                block.tyres.push(j);
                block.w.push(col);
                (b, block.tyres.len() - 1)
            });
        }
        Ok(())
    }

    /// `(K_eff,v^-1)` between the tyre DOFs of axles `j` and `k`: how much a unit force on
    /// tyre `k` moves tyre `j`'s DOF (0 across blocks).
    pub(super) fn tyre_coupling(&self, j: usize, k: usize) -> f64 {
        match (self.block_of_axle[j], self.block_of_axle[k]) {
            (Some((bj, _)), Some((bk, tk))) if bj == bk => {
                let dof = self.dynamics.axles[j].dof.unwrap_or_default();
                self.blocks[bk].w[tk][self.block_of_dof[dof].1]
            }
            _ => 0.0,
        }
    }

    /// y0 = K_eff,v^-1 (history): the displacement with no dynamic tyre force.
    pub(super) fn predict(&mut self, c: &NewmarkCoefficients) {
        let s = &self.state;
        for block in &mut self.blocks {
            // history = M (a0 u + a2 v + a3 a) + C (a1 u + a4 v + a5 a), block by block.
            for (place, &dof) in block.dofs.iter().enumerate() {
                block.gathered[place] = c.a0 * s.u[dof] + c.a2 * s.v[dof] + c.a3 * s.a[dof];
            }
            block.history.gemv(1.0, &block.mass, &block.gathered, 0.0);
            for (place, &dof) in block.dofs.iter().enumerate() {
                block.gathered[place] = c.a1 * s.u[dof] + c.a4 * s.v[dof] + c.a5 * s.a[dof];
            }
            block
                .history
                .gemv(1.0, &block.damping, &block.gathered, 1.0);
            block.factor.solve_mut(&mut block.history);
            for (place, &dof) in block.dofs.iter().enumerate() {
                self.y0[dof] = block.history[place];
            }
        }
    }

    /// y0 += f K_eff,v^-1 e_dof(j): the response to the dynamic force `f` on tyre `j`.
    pub(super) fn add_tyre_force(&mut self, j: usize, force_n: f64) {
        if let Some((b, t)) = self.block_of_axle[j] {
            let block = &self.blocks[b];
            for (place, &dof) in block.dofs.iter().enumerate() {
                self.y0[dof] += force_n * block.w[t][place];
            }
        }
    }

    /// Newmark update of the vehicle state to the solved displacement `y0`.
    pub(super) fn finish_step(&mut self, c: &NewmarkCoefficients) {
        let s = &mut self.state;
        for i in 0..self.dynamics.n_dof() {
            let y_next = self.y0[i];
            let a_next = c.acceleration(y_next, s.u[i], s.v[i], s.a[i]);
            s.v[i] += c.dt_s * ((1.0 - c.gamma) * s.a[i] + c.gamma * a_next);
            s.a[i] = a_next;
            s.u[i] = y_next;
        }
    }
}

/// The DOFs grouped into the connected parts of the matrices' sparsity graph (an exact
/// zero off the diagonal means no coupling), each part ascending, parts by first DOF.
fn connected_dofs(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DMatrix<f64>) -> Vec<Vec<usize>> {
    let n = a.nrows();
    let mut part: Vec<Option<usize>> = vec![None; n];
    let mut parts = Vec::new();
    for seed in 0..n {
        if part[seed].is_some() {
            continue;
        }
        let id = parts.len();
        let mut members = vec![seed];
        part[seed] = Some(id);
        let mut next = 0;
        while next < members.len() {
            let i = members[next];
            next += 1;
            for j in 0..n {
                let coupled = a[(i, j)] != 0.0 || b[(i, j)] != 0.0 || c[(i, j)] != 0.0;
                if coupled && part[j].is_none() {
                    part[j] = Some(id);
                    members.push(j);
                }
            }
        }
        members.sort_unstable();
        parts.push(members);
    }
    parts
}
