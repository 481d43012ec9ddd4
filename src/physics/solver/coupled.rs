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

mod groups;

use std::borrow::Cow;

use nalgebra::DVector;

pub use super::coupled_vehicle::CoupledVehicle;
use super::coupled_vehicle::MAX_TYRES_PER_BLOCK;
use super::linear::SmallLu;
use super::newmark::{Newmark, NewmarkCoefficients, SolveMode};
use crate::error::{Error, Result};
use crate::physics::bridge::{BridgeModel, GaugeState, MomentGauge, PointQuantity, SparseVec};
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

/// The deflection and slope operators of a wheel at `x_m` (`ops`), or with
/// `sleeper_spacing_m` their 1/4, 1/2, 1/4 sums over the sleepers at x - a, x, x + a
/// (entries may repeat: they add up).
fn wheel_operators(
    model: &BridgeModel,
    x_m: f64,
    sleeper_spacing_m: Option<f64>,
    ops: [&mut SparseVec; 2],
    scratch: &mut [SparseVec; 2],
) {
    let [h, h_slope] = ops;
    model.wheel_operators(x_m, [&mut *h, &mut *h_slope]);
    let Some(a) = sleeper_spacing_m else {
        return;
    };
    for op in [&mut *h, &mut *h_slope] {
        op.val.iter_mut().for_each(|v| *v *= 0.5);
    }
    for x in [x_m - a, x_m + a] {
        let [sh, ss] = scratch;
        model.wheel_operators(x, [sh, ss]);
        for (out, side) in [(&mut *h, &*sh), (&mut *h_slope, &*ss)] {
            for (&i, &v) in side.idx.iter().zip(&side.val) {
                out.push(i, 0.25 * v);
            }
        }
    }
}

/// `out = a.0 a.1 + b.0 b.1` for two operators, merged entry by entry when they share
/// their indices (a point's deflection and slope do), else laid end to end.
fn combine(a: (f64, &SparseVec), b: (f64, &SparseVec), out: &mut SparseVec) {
    out.clear();
    if a.1.idx == b.1.idx {
        for ((&i, &va), &vb) in a.1.idx.iter().zip(&a.1.val).zip(&b.1.val) {
            out.push(i, a.0 * va + b.0 * vb);
        }
        return;
    }
    for (scale, op) in [a, b] {
        for (&i, &v) in op.idx.iter().zip(&op.val) {
            out.push(i, scale * v);
        }
    }
}

/// Entries reserved per contact for `alpha` (it grows once, on the first step, for a
/// modal model with more modes).
const ALPHA_CAPACITY: usize = 32;

/// Per-contact data of one step.
struct Contact {
    vehicle: usize,
    axle: usize,
    /// The axle's vehicle block and its tyre's place in it (`None`: a moving force).
    block: Option<(usize, usize)>,
    static_load_n: f64,
    x_m: f64,
    on_span: bool,
    h: SparseVec,
    h_slope: SparseVec,
    /// K_eff^-1 h (only for contacts on the span).
    z: DVector<f64>,
    /// alpha = (kt + a1 ct) h + ct v h': the bridge side of the linearized tyre force,
    /// empty off the span.
    alpha: SparseVec,
    kappa: f64,
    rhs: f64,
    active: bool,
    /// Road elevation (m) and slope under the tyre.
    road_m: f64,
    road_slope: f64,
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
    /// Whether vehicle blocks at rest on a level road off the span skip their step (the
    /// same bits: see [`CoupledVehicle::mark_resting`]); `false` only to check that.
    pub rest_skip: bool,
    /// Block-steps skipped that way since the start.
    pub resting_block_steps: u64,
    spread_scratch: [SparseVec; 2],
    road: &'a dyn RoadSurface,
    contacts: Vec<Contact>,
    rhs: DVector<f64>,
    lu: SmallLu,
    forces: Vec<f64>,
    entries: Vec<f64>,
    /// Contacts sorted by independent group (see `group_contacts`), and work buffers.
    order: Vec<((usize, usize, usize), usize)>,
    bridge_blocks: Vec<(usize, usize)>,
    /// The vehicles on the road (index and id, as the contacts were gathered) and the
    /// blocks on the span, now and when `order` was built: the caller may remove retired
    /// vehicles from `vehicles`, which shifts the indices.
    on_road: Vec<(usize, u32)>,
    grouped_on_road: Vec<(usize, u32)>,
    grouped_blocks: Vec<(usize, usize)>,
    group_rhs: Vec<f64>,
    /// Work buffers of the bridge group's push-through solve (see `groups`).
    on_span_places: Vec<usize>,
    runs: Vec<groups::BlockRun>,
    run_of: Vec<usize>,
    bridge_terms: Vec<f64>,
    push_through: Vec<f64>,
    load_on_span: Vec<f64>,
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
            rest_skip: true,
            resting_block_steps: 0,
            spread_scratch: [SparseVec::with_capacity(8), SparseVec::with_capacity(8)],
            road,
            contacts: Vec::new(),
            rhs: DVector::zeros(n),
            lu: SmallLu::with_capacity(8),
            forces: Vec::new(),
            entries: Vec::new(),
            order: Vec::new(),
            bridge_blocks: Vec::new(),
            on_road: Vec::new(),
            grouped_on_road: Vec::new(),
            grouped_blocks: Vec::new(),
            group_rhs: Vec::new(),
            on_span_places: Vec::new(),
            runs: Vec::new(),
            run_of: Vec::new(),
            bridge_terms: Vec::new(),
            push_through: Vec::new(),
            load_on_span: Vec::new(),
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
        self.on_road.clear();
        for (vi, v) in self.vehicles.iter().enumerate() {
            if !v.active {
                continue;
            }
            self.on_road.push((vi, v.id));
            for j in 0..v.dynamics.axles.len() {
                if self.contacts.len() <= count {
                    self.contacts.push(Contact {
                        vehicle: 0,
                        axle: 0,
                        block: None,
                        static_load_n: 0.0,
                        x_m: 0.0,
                        on_span: false,
                        h: SparseVec::with_capacity(n),
                        h_slope: SparseVec::with_capacity(n),
                        z: DVector::zeros(n),
                        // A wheel's operator touches one element's 4 DOFs (12 over three
                        // sleepers), a modal model's every mode: room for the usual
                        // case without reserving twice the model per contact.
                        alpha: SparseVec::with_capacity(2 * n.min(ALPHA_CAPACITY)),
                        kappa: 0.0,
                        rhs: 0.0,
                        active: true,
                        road_m: 0.0,
                        road_slope: 0.0,
                    });
                }
                let c = &mut self.contacts[count];
                c.vehicle = vi;
                c.axle = j;
                c.block = v.tyre_place(j);
                c.static_load_n = v.dynamics.axles[j].static_load_n;
                c.x_m = v.axle_x_m(j, next, dt);
                let spread = self.sleeper_spacing_m;
                let reach = spread.unwrap_or(0.0);
                c.on_span = [c.x_m - reach, c.x_m, c.x_m + reach]
                    .into_iter()
                    .any(|x| self.model.on_girder(x));
                c.active = true;
                count += 1;
                if !c.on_span {
                    // Off the girder every operator is empty.
                    c.h.clear();
                    c.h_slope.clear();
                    continue;
                }
                wheel_operators(
                    &self.model,
                    c.x_m,
                    spread,
                    [&mut c.h, &mut c.h_slope],
                    &mut self.spread_scratch,
                );
            }
        }
        self.contacts.truncate(count);
    }

    /// u0 = K_eff^-1 (history + external - H F_static); Z_j = K_eff^-1 h_j.
    fn prepare_bridge(&mut self) {
        self.rhs.copy_from(&self.external_load);
        self.bridge.add_history(&mut self.rhs);
        for contact in &self.contacts {
            if contact.on_span {
                contact
                    .h
                    .add_scaled_to(-contact.static_load_n, &mut self.rhs);
            }
        }
        self.bridge.solve_in_place(&mut self.rhs);
        for contact in &mut self.contacts {
            if contact.on_span {
                match &self.inverse_columns {
                    Some(columns) => {
                        // The first column scaled, then the others added: no zero fill.
                        let mut terms = contact.h.idx.iter().zip(&contact.h.val);
                        match terms.next() {
                            Some((&k, &w)) => contact.z.zip_apply(&columns[k], |z, c| *z = w * c),
                            None => contact.z.fill(0.0),
                        }
                        for (&k, &w) in terms {
                            contact.z.axpy(w, &columns[k], 1.0);
                        }
                    }
                    None => {
                        contact.z.fill(0.0);
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
        self.mark_resting_blocks();
        for v in &mut self.vehicles {
            if v.active && v.dynamics.n_dof() > 0 {
                v.predict();
            }
        }
        let u0 = &self.rhs;
        for contact in &mut self.contacts {
            let v = &self.vehicles[contact.vehicle];
            let axle = &v.dynamics.axles[contact.axle];
            contact.alpha.clear();
            let Some(dof) = axle.dof else {
                contact.kappa = 0.0;
                contact.rhs = 0.0;
                continue;
            };
            let (kt, ct, speed) = (
                axle.tyre_stiffness_n_m,
                axle.tyre_damping_n_s_m,
                v.velocity_m_s(),
            );
            contact.kappa = kt + c.a1 * ct;
            if v.stays_at_rest(contact.axle) {
                contact.rhs = 0.0;
                continue;
            }
            let beta_y = -c.a1 * v.state.u[dof] - c.a4 * v.state.v[dof] - c.a5 * v.state.a[dof];
            let (r, r_slope) = (contact.road_m, contact.road_slope);
            let mut known = kt * r + ct * speed * r_slope - ct * beta_y;
            let mut alpha_u0 = 0.0;
            if contact.on_span {
                // The part of the new velocity known before the step is -(a1 u + a4 v
                // + a5 a), the history's velocity part.
                known -= ct * contact.h.dot(self.bridge.velocity_history());
                combine(
                    (contact.kappa, &contact.h),
                    (ct * speed, &contact.h_slope),
                    &mut contact.alpha,
                );
                alpha_u0 = contact.alpha.dot(u0);
            }
            contact.rhs = alpha_u0 - contact.kappa * v.y0[dof] + known;
        }
    }

    /// The road under every tyre, and the vehicle blocks this step leaves at rest (see
    /// [`CoupledVehicle::mark_resting`]): a long train's cars on a level approach cost
    /// nothing until their first tyre reaches the span or an irregularity.
    fn mark_resting_blocks(&mut self) {
        for contact in &mut self.contacts {
            (contact.road_m, contact.road_slope) = self.road.elevation_and_slope(contact.x_m);
        }
        let mut first = 0;
        for (vi, v) in self.vehicles.iter_mut().enumerate() {
            if !v.active {
                continue;
            }
            // Contacts are gathered vehicle by vehicle, axle by axle.
            let axles = v.dynamics.axles.len();
            let own = &self.contacts[first..first + axles];
            debug_assert!(own.iter().all(|c| c.vehicle == vi));
            // A tyre with no static load could lift off under unilateral contact (its force
            // then pinned at -F_static): its car is stepped, never skipped.
            let excited = (own.iter().enumerate())
                .filter(|(_, c)| {
                    !self.rest_skip
                        || c.on_span
                        || c.road_m != 0.0
                        || c.road_slope != 0.0
                        || c.static_load_n <= 0.0
                })
                .map(|(j, _)| j);
            self.resting_block_steps += v.mark_resting(excited) as u64;
            first += axles;
        }
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
            v.contact_force_n[contact.axle] = contact.static_load_n + self.forces[k];
            v.in_contact[contact.axle] = contact.active;
        }
        // Contacts are gathered vehicle by vehicle, axle by axle: each active vehicle's
        // dynamic forces are the next run of `forces`.
        let mut first = 0;
        for v in &mut self.vehicles {
            if !v.active {
                continue;
            }
            let axles = v.dynamics.axles.len();
            if v.in_contact.iter().any(|&t| !t) || v.contact_force_n.iter().any(|&f| f < 0.0) {
                v.contact_loss_steps += 1;
            }
            v.finish_step(&c, &self.forces[first..first + axles]);
            first += axles;
        }
    }

    /// The point loads the last step put on the girder, into `out`: (x m, force N upward
    /// positive), one per wheel on it, or its three sleepers' 1/4, 1/2, 1/4 shares under a
    /// `sleeper_spacing_m` (a sleeper off the girder carries its share to the ground). Each
    /// load is the one the step's load vector was built from, so whatever reads the
    /// girder's equilibrium (a moment gauge, a support reaction) sees exactly it.
    pub fn deck_loads(&self, out: &mut Vec<(f64, f64)>) {
        out.clear();
        let dt_s = self.bridge.coefficients.dt_s;
        for v in self.vehicles.iter().filter(|v| v.is_active()) {
            for (j, &force_n) in v.contact_force_n.iter().enumerate() {
                let x_m = v.axle_x_m(j, self.step, dt_s);
                // Tyre force: compression positive, a downward load on the girder.
                let shares: &[(f64, f64)] = match self.sleeper_spacing_m {
                    None => &[(0.0, 1.0)],
                    Some(a) => &[(-a, 0.25), (0.0, 0.5), (a, 0.25)],
                };
                for &(dx_m, share) in shares {
                    if self.model.on_girder(x_m + dx_m) {
                        out.push((x_m + dx_m, -share * force_n));
                    }
                }
            }
        }
    }

    /// The elastic bending moment `gauge` reads in the current state (N m, sagging
    /// positive), the deck's loads gathered into `loads` (a buffer kept by the caller, so
    /// that reading every step allocates nothing).
    pub fn gauge_moment_n_m(&self, gauge: &MomentGauge, loads: &mut Vec<(f64, f64)>) -> f64 {
        self.deck_loads(loads);
        let s = &self.bridge.state;
        gauge.read(&GaugeState {
            u: &s.u,
            v: &s.v,
            a: &s.a,
            loads,
        })
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
