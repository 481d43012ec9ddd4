//! The coupled vehicle-bridge step (docs/physics.md section 9).
//!
//! The bridge's effective matrix is factorized once. Each step, every tyre contact on the
//! span adds a rank-one coupling, which is eliminated through the contact forces: with
//! `Z = K_eff^-1 H` (one solve per contact on the span) the unknown dynamic tyre forces
//! solve a small dense system of the size of the number of axles, and bridge and vehicle
//! displacements follow by superposition. Nothing of the size of the bridge is factorized
//! in the time loop.
//!
//! Sign conventions: every displacement and force is upward positive; the vehicle DOFs are
//! measured from static equilibrium on a level rigid road; the dynamic tyre force of axle
//! j is `f_j = kt (z_j - y_j) + ct (dz_j/dt - dy_j/dt)` with the surface under the wheel
//! `z_j = w(x_j) + r(x_j)` and `dz/dt = dw/dt + v (dw/dx + dr/dx)` (the convective term);
//! the total tyre force is `F_static + f_j` (compression positive), and the bridge carries
//! `-(F_static + f_j)` at x_j.

use std::borrow::Cow;

use nalgebra::DVector;

pub use super::coupled_vehicle::CoupledVehicle;
use super::linear::SmallLu;
use super::newmark::{Newmark, NewmarkCoefficients, SolveMode};
use crate::error::{Error, Result};
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::RoadSurface;

/// Tyre-road contact law.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Default,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum ContactLaw {
    /// The tyre spring may pull (the paper's assumption); tension is counted as contact loss.
    #[default]
    Full,
    /// A tyre in tension lifts off (zero force) until it touches the road again.
    Unilateral,
}

/// The point operator of a wheel at `x_m`, or with `sleeper_spacing_m` the 1/4, 1/2, 1/4
/// sum over the sleepers at x - a, x, x + a (entries may repeat: they add up).
fn load_operator(
    model: &BridgeModel,
    x_m: f64,
    sleeper_spacing_m: Option<f64>,
    quantity: PointQuantity,
    out: &mut SparseVec,
    scratch: &mut SparseVec,
) {
    model.point_operator(x_m, quantity, out);
    let Some(a) = sleeper_spacing_m else {
        return;
    };
    for v in &mut out.val {
        *v *= 0.5;
    }
    for x in [x_m - a, x_m + a] {
        model.point_operator(x, quantity, scratch);
        for (&i, &v) in scratch.idx.iter().zip(&scratch.val) {
            out.push(i, 0.25 * v);
        }
    }
}

/// Per-contact data of one step.
struct Contact {
    vehicle: usize,
    axle: usize,
    x_m: f64,
    on_span: bool,
    h: SparseVec,
    h_slope: SparseVec,
    /// K_eff^-1 h (only for contacts on the span).
    z: DVector<f64>,
    /// alpha = (kt + a1 ct) h + ct v h'  (bridge side of the linearized tyre force).
    kappa: f64,
    c: f64,
    rhs: f64,
    active: bool,
}

/// The coupled system: one bridge and the vehicles on its road.
pub struct CoupledSolver<'a> {
    /// The bridge model: borrowed, or owned once [`CoupledSolver::replace_model`] has
    /// swapped in a rebuilt one (temperature, damage).
    pub model: Cow<'a, BridgeModel>,
    pub bridge: Newmark,
    pub vehicles: Vec<CoupledVehicle>,
    pub contact_law: ContactLaw,
    /// Extra load on the bridge at the next step (ambient excitation), reset by the caller.
    pub external_load: DVector<f64>,
    /// Index of the last completed step (time = step * dt).
    pub step: u64,
    /// A vehicle is retired once its last axle is this far past the bridge end (m).
    pub retire_after_m: f64,
    /// Sleeper spacing `a` (m) when each wheel load reaches the deck over three sleepers
    /// (1/4, 1/2, 1/4 at x - a, x, x + a; EN 1991-2 6.3.6.1): the contact's point
    /// operators become that weighted sum, so the wheel also rides on the weighted
    /// deflection (the coupling stays symmetric). `None`: at the contact point.
    pub sleeper_spacing_m: Option<f64>,
    spread_scratch: SparseVec,
    road: &'a dyn RoadSurface,
    contacts: Vec<Contact>,
    rhs: DVector<f64>,
    beta_u: DVector<f64>,
    lu: SmallLu,
    forces: Vec<f64>,
    entries: Vec<f64>,
    /// Contacts sorted by independent group (see `group_contacts`), and work buffers.
    order: Vec<((usize, usize, usize), usize)>,
    bridge_blocks: Vec<(usize, usize)>,
    group_rhs: Vec<f64>,
    /// Columns of `K_eff^-1` (see [`Newmark::inverse_columns`]): an influence vector
    /// `Z = K_eff^-1 h` is then a few axpys over the entries of h instead of a solve.
    inverse_columns: Option<Vec<DVector<f64>>>,
}

impl<'a> CoupledSolver<'a> {
    /// Prepares the bridge integrator (one factorization) for the given step and mode.
    pub fn new(
        model: &'a BridgeModel,
        road: &'a dyn RoadSurface,
        coefficients: NewmarkCoefficients,
        mode: SolveMode,
        contact_law: ContactLaw,
    ) -> Result<Self> {
        let bridge = Newmark::new(
            &model.mass,
            &model.damping,
            &model.stiffness,
            coefficients,
            mode,
        )?;
        let n = model.n_dof();
        let inverse_columns = bridge.inverse_columns();
        Ok(CoupledSolver {
            inverse_columns,
            model: Cow::Borrowed(model),
            bridge,
            vehicles: Vec::new(),
            contact_law,
            external_load: DVector::zeros(n),
            step: 0,
            retire_after_m: 50.0,
            sleeper_spacing_m: None,
            spread_scratch: SparseVec::with_capacity(8),
            road,
            contacts: Vec::new(),
            rhs: DVector::zeros(n),
            beta_u: DVector::zeros(n),
            lu: SmallLu::with_capacity(8),
            forces: Vec::new(),
            entries: Vec::new(),
            order: Vec::new(),
            bridge_blocks: Vec::new(),
            group_rhs: Vec::new(),
        })
    }

    /// Replaces the bridge model by `model` (same DOF layout: a rebuild of the same mesh
    /// with other stiffnesses) and refactorizes once, keeping the bridge's displacement,
    /// velocity and acceleration. The acceleration is not re-equilibrated: the stiffness
    /// changes by a fraction of a percent between rebuilds, and the next step's Newmark
    /// update absorbs the mismatch.
    pub fn replace_model(&mut self, model: BridgeModel, mode: SolveMode) -> Result<()> {
        if model.n_dof() != self.model.n_dof() || model.diagonal_mass != self.model.diagonal_mass {
            return Err(Error::invalid(
                "bridge.model",
                model.spec.label(),
                "a rebuilt model must keep the DOF layout of the running one",
            ));
        }
        let mut bridge = Newmark::new(
            &model.mass,
            &model.damping,
            &model.stiffness,
            self.bridge.coefficients,
            mode,
        )?;
        bridge.state = self.bridge.state.clone();
        self.inverse_columns = bridge.inverse_columns();
        self.bridge = bridge;
        self.model = Cow::Owned(model);
        Ok(())
    }

    /// Adds a vehicle (it takes part from its entry step on).
    pub fn add_vehicle(&mut self, vehicle: CoupledVehicle) {
        self.vehicles.push(vehicle);
    }

    /// Time of the last completed step (s).
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.bridge.coefficients.dt_s
    }

    /// Advances one step.
    pub fn advance(&mut self) -> Result<()> {
        let next = self.step + 1;
        let coefficients = self.bridge.coefficients;
        let dt = coefficients.dt_s;
        let span = self.model.length_m();
        for v in &mut self.vehicles {
            if !v.active && !v.retired && v.entry_step <= next {
                // The equilibrium is that of the state being advanced: positions at `step`.
                v.activate(self.road, self.step, &coefficients)?;
            }
            if v.active && v.has_left(span, self.retire_after_m, next, dt) {
                v.active = false;
                v.retired = true;
            }
        }
        self.gather_contacts(next);
        self.prepare_bridge();
        self.prepare_vehicles();
        self.solve_contact_forces();
        self.commit();
        self.step = next;
        Ok(())
    }

    /// Builds the contact list at step `next` with point operators at the new positions.
    fn gather_contacts(&mut self, next: u64) {
        let dt = self.bridge.coefficients.dt_s;
        let n = self.model.n_dof();
        let mut count = 0;
        for (vi, v) in self.vehicles.iter().enumerate() {
            if !v.active {
                continue;
            }
            for j in 0..v.dynamics.axles.len() {
                if self.contacts.len() <= count {
                    self.contacts.push(Contact {
                        vehicle: 0,
                        axle: 0,
                        x_m: 0.0,
                        on_span: false,
                        h: SparseVec::with_capacity(n),
                        h_slope: SparseVec::with_capacity(n),
                        z: DVector::zeros(n),
                        kappa: 0.0,
                        c: 0.0,
                        rhs: 0.0,
                        active: true,
                    });
                }
                let c = &mut self.contacts[count];
                c.vehicle = vi;
                c.axle = j;
                c.x_m = v.axle_x_m(j, next, dt);
                let spread = self.sleeper_spacing_m;
                let reach = spread.unwrap_or(0.0);
                c.on_span = [c.x_m - reach, c.x_m, c.x_m + reach]
                    .into_iter()
                    .any(|x| self.model.on_girder(x));
                let scratch = &mut self.spread_scratch;
                load_operator(
                    &self.model,
                    c.x_m,
                    spread,
                    PointQuantity::Deflection,
                    &mut c.h,
                    scratch,
                );
                load_operator(
                    &self.model,
                    c.x_m,
                    spread,
                    PointQuantity::Slope,
                    &mut c.h_slope,
                    scratch,
                );
                c.active = true;
                count += 1;
            }
        }
        self.contacts.truncate(count);
    }

    /// u0 = K_eff^-1 (history + external - H F_static); Z_j = K_eff^-1 h_j.
    fn prepare_bridge(&mut self) {
        let c = self.bridge.coefficients;
        self.rhs.copy_from(&self.external_load);
        self.bridge.add_history(&mut self.rhs);
        for contact in &self.contacts {
            if contact.on_span {
                let load =
                    self.vehicles[contact.vehicle].dynamics.axles[contact.axle].static_load_n;
                contact.h.add_scaled_to(-load, &mut self.rhs);
            }
        }
        self.bridge.solve_in_place(&mut self.rhs);
        // beta_u = -a1 u - a4 v - a5 a: the part of the new velocity known before the step.
        let s = &self.bridge.state;
        self.beta_u.copy_from(&s.u);
        self.beta_u.scale_mut(-c.a1);
        self.beta_u.axpy(-c.a4, &s.v, 1.0);
        self.beta_u.axpy(-c.a5, &s.a, 1.0);
        for contact in &mut self.contacts {
            if contact.on_span {
                contact.z.fill(0.0);
                match &self.inverse_columns {
                    Some(columns) => {
                        for (&k, &w) in contact.h.idx.iter().zip(&contact.h.val) {
                            contact.z.axpy(w, &columns[k], 1.0);
                        }
                    }
                    None => {
                        contact.h.add_scaled_to(1.0, &mut contact.z);
                        self.bridge.solve_in_place(&mut contact.z);
                    }
                }
            }
        }
    }

    /// y0 = K_eff,v^-1 (vehicle history), and the known parts of each tyre force.
    fn prepare_vehicles(&mut self) {
        let c = self.bridge.coefficients;
        for v in &mut self.vehicles {
            if v.active && v.dynamics.n_dof() > 0 {
                v.predict(&c);
            }
        }
        let u0 = &self.rhs;
        for contact in &mut self.contacts {
            let v = &self.vehicles[contact.vehicle];
            let axle = &v.dynamics.axles[contact.axle];
            let Some(dof) = axle.dof else {
                contact.kappa = 0.0;
                contact.c = 0.0;
                contact.rhs = 0.0;
                continue;
            };
            let (kt, ct, speed) = (
                axle.tyre_stiffness_n_m,
                axle.tyre_damping_n_s_m,
                v.velocity_m_s(),
            );
            contact.kappa = kt + c.a1 * ct;
            let beta_y = -c.a1 * v.state.u[dof] - c.a4 * v.state.v[dof] - c.a5 * v.state.a[dof];
            let (r, r_slope) = self.road.elevation_and_slope(contact.x_m);
            let mut known = kt * r + ct * speed * r_slope - ct * beta_y;
            let mut alpha_u0 = 0.0;
            if contact.on_span {
                known += ct * contact.h.dot(&self.beta_u);
                alpha_u0 = contact.kappa * contact.h.dot(u0) + ct * speed * contact.h_slope.dot(u0);
            }
            contact.c = known;
            contact.rhs = alpha_u0 - contact.kappa * v.y0[dof] + known;
        }
    }

    /// alpha_j . x for a bridge vector x.
    fn alpha_dot(&self, j: usize, x: &DVector<f64>) -> f64 {
        let contact = &self.contacts[j];
        if !contact.on_span || contact.kappa == 0.0 {
            return 0.0;
        }
        let v = &self.vehicles[contact.vehicle];
        let ct = v.dynamics.axles[contact.axle].tyre_damping_n_s_m;
        contact.kappa * contact.h.dot(x) + ct * v.velocity_m_s() * contact.h_slope.dot(x)
    }

    /// Solves the small system for the dynamic tyre forces, with an active set for
    /// unilateral contact. The system falls apart into independent groups (every tyre
    /// coupled through the bridge, then each vehicle block off the span on its own), each
    /// solved alone: a long train off the span costs many 4 x 4 solves, not one large one.
    fn solve_contact_forces(&mut self) {
        let p = self.contacts.len();
        self.forces.resize(p, 0.0);
        self.group_contacts();
        let order = std::mem::take(&mut self.order);
        for _iteration in 0..20 {
            // Inactive rows pin f_j = -F_static (zero total force).
            for (j, contact) in self.contacts.iter().enumerate() {
                self.forces[j] = if contact.active {
                    contact.rhs
                } else {
                    -self.vehicles[contact.vehicle].dynamics.axles[contact.axle].static_load_n
                };
            }
            for members in order.chunk_by(|a, b| a.0 == b.0) {
                self.solve_group(members);
            }
            if self.contact_law == ContactLaw::Full || !self.update_active_set() {
                break;
            }
        }
        self.order = order;
    }

    /// Sorts the contacts by group: 0 every tyre coupled through the bridge (a vehicle
    /// block with any tyre on the span), then one group per other block, then moving
    /// forces alone.
    fn group_contacts(&mut self) {
        self.bridge_blocks.clear();
        for c in &self.contacts {
            if let (true, Some(b)) = (c.on_span, self.vehicles[c.vehicle].block_of_axle(c.axle)) {
                self.bridge_blocks.push((c.vehicle, b));
            }
        }
        self.bridge_blocks.sort_unstable();
        self.bridge_blocks.dedup();
        self.order.clear();
        for (j, c) in self.contacts.iter().enumerate() {
            let key = match self.vehicles[c.vehicle].block_of_axle(c.axle) {
                Some(b) if self.bridge_blocks.binary_search(&(c.vehicle, b)).is_ok() => (0, 0, 0),
                Some(b) => (1, c.vehicle, b),
                None => (2, j, 0),
            };
            self.order.push((key, j));
        }
        self.order.sort_unstable();
    }

    /// Matrix B_jk = delta_jk + alpha_j . Z_k + kappa_j G_jk (same vehicle block) over the
    /// group's contacts; `forces` holds the right-hand side and receives the solution.
    fn solve_group(&mut self, members: &[((usize, usize, usize), usize)]) {
        let m = members.len();
        if m == 1 && self.contacts[members[0].1].kappa == 0.0 {
            return; // a moving force: identity row
        }
        let mut entries = std::mem::take(&mut self.entries);
        entries.clear();
        entries.extend(
            (0..m * m).map(|idx| self.system_entry(members[idx % m].1, members[idx / m].1)),
        );
        self.group_rhs.clear();
        self.group_rhs
            .extend(members.iter().map(|&(_, j)| self.forces[j]));
        self.lu
            .solve(m, |i, j| entries[i + j * m], &mut self.group_rhs);
        for (&(_, j), &f) in members.iter().zip(&self.group_rhs) {
            self.forces[j] = f;
        }
        self.entries = entries;
    }

    fn system_entry(&self, j: usize, k: usize) -> f64 {
        let cj = &self.contacts[j];
        let identity = if j == k { 1.0 } else { 0.0 };
        if !cj.active || cj.kappa == 0.0 {
            return identity;
        }
        let ck = &self.contacts[k];
        let mut entry = identity;
        if cj.on_span && ck.on_span {
            entry += self.alpha_dot(j, &ck.z);
        }
        if cj.vehicle == ck.vehicle {
            entry += cj.kappa * self.vehicles[cj.vehicle].tyre_coupling(cj.axle, ck.axle);
        }
        entry
    }

    /// Flips contacts whose state is inconsistent with the solution; true if any changed.
    fn update_active_set(&mut self) -> bool {
        let mut changed = false;
        for j in 0..self.contacts.len() {
            let f_trial = self.trial_force(j);
            let contact = &self.contacts[j];
            let axle = &self.vehicles[contact.vehicle].dynamics.axles[contact.axle];
            if axle.dof.is_none() {
                continue;
            }
            let total = axle.static_load_n + f_trial;
            let should_touch = total > 0.0;
            if should_touch != contact.active {
                self.contacts[j].active = should_touch;
                changed = true;
            }
        }
        changed
    }

    /// The tyre force law evaluated at the current solution (what the tyre would carry in contact).
    fn trial_force(&self, j: usize) -> f64 {
        let contact = &self.contacts[j];
        if !contact.active {
            let v = &self.vehicles[contact.vehicle];
            if v.dynamics.axles[contact.axle].dof.is_none() {
                return 0.0;
            }
            // u = u0 - Z f, y = y0 + W f: the law's linear form at that state.
            let mut value = contact.rhs;
            for (k, ck) in self.contacts.iter().enumerate() {
                if contact.on_span && ck.on_span {
                    value -= self.alpha_dot(j, &ck.z) * self.forces[k];
                }
                if ck.vehicle == contact.vehicle {
                    value -=
                        contact.kappa * v.tyre_coupling(contact.axle, ck.axle) * self.forces[k];
                }
            }
            return value;
        }
        self.forces[j]
    }

    /// u = u0 - Z f, y = y0 + W f; Newmark updates; records contact forces.
    fn commit(&mut self) {
        for (k, contact) in self.contacts.iter().enumerate() {
            if contact.on_span {
                self.rhs.axpy(-self.forces[k], &contact.z, 1.0);
            }
        }
        let u_next = std::mem::replace(&mut self.rhs, DVector::zeros(0));
        self.bridge.commit(&u_next);
        self.rhs = u_next;
        let c = self.bridge.coefficients;
        for (k, contact) in self.contacts.iter().enumerate() {
            let v = &mut self.vehicles[contact.vehicle];
            v.add_tyre_force(contact.axle, self.forces[k]);
            let total = v.dynamics.axles[contact.axle].static_load_n + self.forces[k];
            v.contact_force_n[contact.axle] = total;
            v.in_contact[contact.axle] = contact.active;
        }
        for v in &mut self.vehicles {
            if !v.active {
                continue;
            }
            if v.in_contact.iter().any(|&t| !t) || v.contact_force_n.iter().any(|&f| f < 0.0) {
                v.contact_loss_steps += 1;
            }
            v.finish_step(&c);
        }
    }

    /// Bridge quantity at x from the current state (`which` 0: u, 1: v, 2: a).
    pub fn bridge_response(
        &self,
        x_m: f64,
        quantity: PointQuantity,
        which: usize,
        op: &mut SparseVec,
    ) -> f64 {
        self.model.point_operator(x_m, quantity, op);
        let s = &self.bridge.state;
        op.dot(match which {
            0 => &s.u,
            1 => &s.v,
            _ => &s.a,
        })
    }
}
