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
use crate::base::dot::dot;
use crate::error::{Error, Result};
use crate::physics::road::RoadSurface;
use crate::physics::vehicle::VehicleDynamics;

/// Blocks with more tyres than this are solved as a general group (an articulated rake is
/// one block with all its wheelsets; a car or a road vehicle has a few).
pub(super) const MAX_TYRES_PER_BLOCK: usize = 16;

/// One independent part of a vehicle: DOFs coupled by its mass, damping or stiffness.
struct Block {
    /// The vehicle DOFs of the block, ascending.
    dofs: Vec<usize>,
    /// `K_eff,b^-1 [a0 M + a1 C | a2 M + a4 C | a3 M + a5 C]` (m x 3m, row-major): the
    /// step's prediction from the history is one product with the stacked (u, v, a),
    /// instead of two products and two triangular solves every step.
    propagator: Vec<f64>,
    /// Per tyre of the block (`tyres[i]` is the axle): `K_eff,b^-1 e_dof` over the block.
    tyres: Vec<usize>,
    w: Vec<DVector<f64>>,
    /// `coupling[i + t k]`: tyre i's DOF under a unit force on tyre k (t tyres), the
    /// block's part of the contact system, read from `w` once.
    coupling: Vec<f64>,
    /// `(I + kappa G)^-1` (t x t, column-major): the contact system of the block alone,
    /// every tyre touching a rigid road. It does not change while the block is off the
    /// span, so most of a long train's tyres cost one small product a step, not a solve.
    contact_inverse: Vec<f64>,
    /// Block-local work vectors: the stacked (u, v, a), and the displacement (predicted,
    /// then with the tyre forces' response).
    gathered: Vec<f64>,
    history: Vec<f64>,
    /// Whether the block has not moved yet: every DOF's displacement, velocity and
    /// acceleration exactly +0.0 since it appeared (a car on a level approach).
    at_rest: bool,
    /// This step's decision: at rest, and every tyre off the span on a level road, so the
    /// step leaves it at rest (see [`CoupledVehicle::stays_at_rest`]).
    resting: bool,
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
    #[inline]
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
    #[inline]
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
        let c = coefficients;
        let mut factors = Vec::new();
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
            let (mass, damping) = (sub(&d.mass), sub(&d.damping));
            let mut propagator = DMatrix::zeros(m, 3 * m);
            for (part, (cm, cc)) in [(c.a0, c.a1), (c.a2, c.a4), (c.a3, c.a5)]
                .into_iter()
                .enumerate()
            {
                let mut history = &mass * cm + &damping * cc;
                factor.solve_mut(&mut history);
                propagator.columns_mut(part * m, m).copy_from(&history);
            }
            let propagator = propagator.transpose().as_slice().to_vec();
            self.blocks.push(Block {
                propagator,
                tyres: Vec::new(),
                w: Vec::new(),
                coupling: Vec::new(),
                contact_inverse: Vec::new(),
                gathered: vec![0.0; 3 * m],
                history: vec![0.0; m],
                // +0.0 only: the full step would turn a -0.0 into +0.0, the skip would not.
                at_rest: dofs.iter().all(|&i| {
                    let s = &self.state;
                    [s.u[i], s.v[i], s.a[i]].iter().all(|x| x.to_bits() == 0)
                }),
                resting: false,
                dofs,
            });
            factors.push(factor);
        }
        for (j, axle) in d.axles.iter().enumerate() {
            self.block_of_axle[j] = axle.dof.map(|dof| {
                let (b, place) = self.block_of_dof[dof];
                let block = &mut self.blocks[b];
                let mut col = DVector::zeros(block.dofs.len());
                col[place] = 1.0;
                factors[b].solve_mut(&mut col);
                block.tyres.push(j);
                block.w.push(col);
                (b, block.tyres.len() - 1)
            });
        }
        for block in &mut self.blocks {
            let t = block.tyres.len();
            block.coupling = (0..t * t)
                .map(|ik| {
                    let dof = d.axles[block.tyres[ik % t]].dof.unwrap_or_default();
                    block.w[ik / t][self.block_of_dof[dof].1]
                })
                .collect();
            if t > MAX_TYRES_PER_BLOCK {
                continue;
            }
            let kappa: Vec<f64> = (block.tyres.iter())
                .map(|&j| d.axles[j].tyre_stiffness_n_m + c.a1 * d.axles[j].tyre_damping_n_s_m)
                .collect();
            let system = DMatrix::from_fn(t, t, |i, k| {
                f64::from(i == k) + kappa[i] * block.coupling[i + t * k]
            });
            let inverse = system.try_inverse().ok_or_else(|| Error::Factorization {
                what: format!("tyre contact system of vehicle {}", self.id),
                reason: "singular (check tyre and suspension parameters)".into(),
            })?;
            block.contact_inverse = inverse.as_slice().to_vec();
        }
        Ok(())
    }

    /// `(K_eff,v^-1)` between two tyre DOFs of block `block` (by their places, see
    /// [`Self::tyre_place`]): how much a unit force on tyre `tk` moves tyre `tj`'s DOF.
    #[inline]
    pub(super) fn block_coupling(&self, block: usize, tj: usize, tk: usize) -> f64 {
        let b = &self.blocks[block];
        b.coupling[tj + b.tyres.len() * tk]
    }

    /// The dynamic tyre forces of block `block` off the span, every tyre in contact:
    /// `forces[i]` holds the right-hand side of tyre place i and receives its force.
    #[inline]
    pub(super) fn solve_off_span(&self, block: usize, forces: &mut [f64]) {
        let b = &self.blocks[block];
        let t = b.tyres.len();
        let mut rhs = [0.0; MAX_TYRES_PER_BLOCK];
        for (r, &f) in rhs.iter_mut().zip(forces.iter()) {
            *r = f;
        }
        for (i, f) in forces.iter_mut().enumerate() {
            *f = (0..t).map(|k| b.contact_inverse[i + t * k] * rhs[k]).sum();
        }
    }

    /// `(I + kappa G)^-1` of block `block` between its tyre places `tj` and `tk` (blocks
    /// of at most [`MAX_TYRES_PER_BLOCK`] tyres).
    #[inline]
    pub(super) fn contact_inverse(&self, block: usize, tj: usize, tk: usize) -> f64 {
        let b = &self.blocks[block];
        b.contact_inverse[tj + b.tyres.len() * tk]
    }

    /// Tyres of block `block`.
    #[inline]
    pub(super) fn block_tyres(&self, block: usize) -> usize {
        self.blocks[block].tyres.len()
    }

    /// Axle `j`'s block and its tyre's place among the block's tyres (`None`: a moving
    /// force).
    #[inline]
    pub(super) fn tyre_place(&self, j: usize) -> Option<(usize, usize)> {
        self.block_of_axle[j]
    }

    /// Marks, for this step, the blocks that stay at rest: at rest so far and with no tyre
    /// in `excited` (a tyre on the span, or on a road with elevation or slope under it).
    /// Such a block's history is zero and so are its tyres' right-hand sides and dynamic
    /// forces: [`Self::predict`] and [`Self::finish_step`] skip it, and its state stays
    /// the exact zeros the full step would compute (`+0.0`: every product with a zero
    /// state or a zero road is summed onto a `+0.0` start). Returns how many blocks rest.
    pub(super) fn mark_resting(&mut self, excited: impl Iterator<Item = usize>) -> usize {
        for block in &mut self.blocks {
            block.resting = block.at_rest;
        }
        for axle in excited {
            if let Some((b, _)) = self.block_of_axle[axle] {
                self.blocks[b].resting = false;
            }
        }
        self.blocks.iter().filter(|b| b.resting).count()
    }

    /// Whether block `block` was marked resting this step ([`Self::mark_resting`]).
    #[inline]
    pub(super) fn is_resting(&self, block: usize) -> bool {
        self.blocks[block].resting
    }

    /// Whether axle `j`'s block was marked resting this step ([`Self::mark_resting`]).
    #[inline]
    pub(super) fn stays_at_rest(&self, j: usize) -> bool {
        self.block_of_axle[j].is_some_and(|(b, _)| self.blocks[b].resting)
    }

    /// y0 = K_eff,v^-1 (history): the displacement with no dynamic tyre force.
    pub(super) fn predict(&mut self) {
        let (u, v, a) = (
            self.state.u.as_slice(),
            self.state.v.as_slice(),
            self.state.a.as_slice(),
        );
        for block in self.blocks.iter_mut().filter(|b| !b.resting) {
            // K_eff^-1 (M (a0 u + a2 v + a3 a) + C (a1 u + a4 v + a5 a)), block by block.
            let m = block.dofs.len();
            let (gu, rest) = block.gathered.split_at_mut(m);
            let (gv, ga) = rest.split_at_mut(m);
            for (((&dof, gu), gv), ga) in block.dofs.iter().zip(gu).zip(gv).zip(ga) {
                (*gu, *gv, *ga) = (u[dof], v[dof], a[dof]);
            }
            let rows = block.propagator.chunks_exact(3 * m);
            for ((y, row), &dof) in block.history.iter_mut().zip(rows).zip(&block.dofs) {
                *y = dot(row, &block.gathered);
                self.y0[dof] = *y;
            }
        }
    }

    /// Adds each tyre's response to its dynamic force (`dynamic_force_n`, per axle) to
    /// the prediction, block by block (y = y0 + sum f_t K_eff,b^-1 e_t), and makes the
    /// Newmark update of the vehicle state to that displacement.
    pub(super) fn finish_step(&mut self, c: &NewmarkCoefficients, dynamic_force_n: &[f64]) {
        let (u, v, a) = (
            self.state.u.as_mut_slice(),
            self.state.v.as_mut_slice(),
            self.state.a.as_mut_slice(),
        );
        for block in self.blocks.iter_mut().filter(|b| !b.resting) {
            block.at_rest = false;
            for (&axle, w) in block.tyres.iter().zip(&block.w) {
                let f = dynamic_force_n[axle];
                for (y, &wi) in block.history.iter_mut().zip(w.as_slice()) {
                    *y += f * wi;
                }
            }
            for (&y_next, &i) in block.history.iter().zip(&block.dofs) {
                let a_next = c.acceleration(y_next, u[i], v[i], a[i]);
                v[i] += c.dt_s * ((1.0 - c.gamma) * a[i] + c.gamma * a_next);
                a[i] = a_next;
                u[i] = y_next;
            }
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
