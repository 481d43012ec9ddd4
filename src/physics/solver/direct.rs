//! The paper's direct method, kept as a baseline for benches and comparisons only.
//!
//! Every step assembles the full coupled system over the bridge DOFs and the DOFs of every
//! active vehicle, with the tyre springs and dashpots at the current wheel positions
//! (including the convective `v dw/dx` term, which makes the coupled stiffness
//! nonsymmetric), and solves its Newmark effective matrix with a fresh dense LU: O(n^3) per
//! step. The time integration (Newmark displacement form) and the tyre law (bilateral,
//! `ContactLaw::Full`) are those of [`CoupledSolver`](super::CoupledSolver), so both give
//! the same response to round-off (tested below); use `CoupledSolver` for anything else.
//!
//! Coupled equations (signs as in `coupled.rs`: upward positive, vehicle DOFs from static
//! equilibrium on a level rigid road), with the dynamic tyre force
//! `f_j = kt (h.u + r - y_d) + ct (h.u' + v h'.u + v r' - y_d')`:
//! bridge `M u'' + C u' + K u + sum_j h_j f_j = -sum_j h_j F_static,j`,
//! vehicle `M_v y'' + C_v y' + K_v y - sum_j e_d f_j = 0`. Moving `f_j` to the left gives
//! `M x'' + C(t) x' + K(t) x = F(t)` over `x = (u, y_1, y_2, ...)`.

use nalgebra::{DMatrix, DVector};

use super::coupled::CoupledVehicle;
use super::linear::SmallLu;
use super::newmark::{NewmarkCoefficients, State};
use crate::error::Result;
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::RoadSurface;

/// The coupled system solved the paper's way: full assembly and dense LU every step.
pub struct DirectSolver<'a> {
    pub model: &'a BridgeModel,
    pub coefficients: NewmarkCoefficients,
    /// Bridge displacement, velocity and acceleration.
    pub bridge_state: State,
    /// The vehicles; their `state`, `contact_force_n`, `in_contact` and
    /// `contact_loss_steps` are kept up to date (their own `is_active` is not: use
    /// [`DirectSolver::vehicle_is_active`]).
    pub vehicles: Vec<CoupledVehicle>,
    /// Extra load on the bridge at the next step, reset by the caller.
    pub external_load: DVector<f64>,
    /// Index of the last completed step (time = step * dt).
    pub step: u64,
    /// A vehicle is retired once its last axle is this far past the bridge end (m).
    pub retire_after_m: f64,
    road: &'a dyn RoadSurface,
    active: Vec<bool>,
    retired: Vec<bool>,
    /// Offset of each active vehicle's DOFs in the coupled vector.
    offsets: Vec<usize>,
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    load: DVector<f64>,
    x: DVector<f64>,
    xd: DVector<f64>,
    xdd: DVector<f64>,
    scratch: DVector<f64>,
    h: SparseVec,
    h_slope: SparseVec,
    lu: SmallLu,
    /// The bridge's M, C and K as dense matrices: the paper's method assembles the whole
    /// coupled system densely every step.
    bridge_dense: (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>),
}

impl<'a> DirectSolver<'a> {
    /// A solver for `model` with vehicles rolling on `road`; nothing is factorized here.
    pub fn new(
        model: &'a BridgeModel,
        road: &'a dyn RoadSurface,
        coefficients: NewmarkCoefficients,
    ) -> Result<Self> {
        let n = model.n_dof();
        Ok(DirectSolver {
            model,
            coefficients,
            bridge_state: State::zeros(n),
            vehicles: Vec::new(),
            external_load: DVector::zeros(n),
            step: 0,
            retire_after_m: 50.0,
            road,
            active: Vec::new(),
            retired: Vec::new(),
            offsets: Vec::new(),
            mass: DMatrix::zeros(0, 0),
            damping: DMatrix::zeros(0, 0),
            stiffness: DMatrix::zeros(0, 0),
            load: DVector::zeros(0),
            x: DVector::zeros(0),
            xd: DVector::zeros(0),
            xdd: DVector::zeros(0),
            scratch: DVector::zeros(0),
            h: SparseVec::with_capacity(n),
            h_slope: SparseVec::with_capacity(n),
            lu: SmallLu::with_capacity(n + 8),
            bridge_dense: (
                model.mass.to_dense(),
                model.damping.to_dense(),
                model.stiffness.to_dense(),
            ),
        })
    }

    /// Adds a vehicle (it takes part from its entry step on).
    pub fn add_vehicle(&mut self, vehicle: CoupledVehicle) {
        self.vehicles.push(vehicle);
        self.active.push(false);
        self.retired.push(false);
    }

    /// True once vehicle `i` has appeared and until it is retired.
    pub fn vehicle_is_active(&self, i: usize) -> bool {
        self.active[i]
    }

    /// Time of the last completed step (s).
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.coefficients.dt_s
    }

    /// Advances one step: assemble, factorize, solve, update.
    pub fn advance(&mut self) -> Result<()> {
        let next = self.step + 1;
        let dt = self.coefficients.dt_s;
        let span = self.model.length_m();
        for (i, v) in self.vehicles.iter_mut().enumerate() {
            if !self.active[i] && !self.retired[i] && v.entry_step <= next {
                // Static equilibrium on the road under the axles at the current step (the
                // state being advanced), at rest (as CoupledSolver).
                let under: Vec<f64> = (0..v.dynamics.axles.len())
                    .map(|j| self.road.elevation_m(v.axle_x_m(j, self.step, dt)))
                    .collect();
                v.state = State::zeros(v.dynamics.n_dof());
                v.state.u = v.dynamics.equilibrium_on_road(&under);
                self.active[i] = true;
            }
            if self.active[i] {
                let last = v.dynamics.axles.len() - 1;
                if v.axle_x_m(last, next, dt) > span + self.retire_after_m {
                    self.active[i] = false;
                    self.retired[i] = true;
                }
            }
        }
        self.assemble(next);
        self.solve();
        self.commit(next);
        self.step = next;
        Ok(())
    }

    /// Fills M, C(t_{n+1}), K(t_{n+1}), F(t_{n+1}) and the state vector of the coupled system.
    fn assemble(&mut self, next: u64) {
        let nb = self.model.n_dof();
        self.offsets.clear();
        let mut n = nb;
        for (i, v) in self.vehicles.iter().enumerate() {
            self.offsets.push(n);
            if self.active[i] {
                n += v.dynamics.n_dof();
            }
        }
        if self.mass.nrows() != n {
            self.mass = DMatrix::zeros(n, n);
            self.damping = DMatrix::zeros(n, n);
            self.stiffness = DMatrix::zeros(n, n);
            self.load = DVector::zeros(n);
            self.x = DVector::zeros(n);
            self.xd = DVector::zeros(n);
            self.xdd = DVector::zeros(n);
            self.scratch = DVector::zeros(n);
        }
        self.mass.fill(0.0);
        self.damping.fill(0.0);
        self.stiffness.fill(0.0);
        let model = self.model;
        let (m, c, k) = &self.bridge_dense;
        self.mass.view_mut((0, 0), (nb, nb)).copy_from(m);
        self.damping.view_mut((0, 0), (nb, nb)).copy_from(c);
        self.stiffness.view_mut((0, 0), (nb, nb)).copy_from(k);
        self.load.fill(0.0);
        self.load.rows_mut(0, nb).copy_from(&self.external_load);
        let s = &self.bridge_state;
        self.x.rows_mut(0, nb).copy_from(&s.u);
        self.xd.rows_mut(0, nb).copy_from(&s.v);
        self.xdd.rows_mut(0, nb).copy_from(&s.a);
        let dt = self.coefficients.dt_s;
        for (i, v) in self.vehicles.iter().enumerate() {
            if !self.active[i] {
                continue;
            }
            let (o, nv) = (self.offsets[i], v.dynamics.n_dof());
            self.mass
                .view_mut((o, o), (nv, nv))
                .copy_from(&v.dynamics.mass);
            self.damping
                .view_mut((o, o), (nv, nv))
                .copy_from(&v.dynamics.damping);
            self.stiffness
                .view_mut((o, o), (nv, nv))
                .copy_from(&v.dynamics.stiffness);
            self.x.rows_mut(o, nv).copy_from(&v.state.u);
            self.xd.rows_mut(o, nv).copy_from(&v.state.v);
            self.xdd.rows_mut(o, nv).copy_from(&v.state.a);
            for (j, axle) in v.dynamics.axles.iter().enumerate() {
                let x_m = v.axle_x_m(j, next, dt);
                let on_span = model.on_girder(x_m);
                model.point_operator(x_m, PointQuantity::Deflection, &mut self.h);
                model.point_operator(x_m, PointQuantity::Slope, &mut self.h_slope);
                let Some(dof) = axle.dof else {
                    // A moving force: its static load only.
                    self.h.add_scaled_to(-axle.static_load_n, &mut self.load);
                    continue;
                };
                let (kt, ct, speed) = (
                    axle.tyre_stiffness_n_m,
                    axle.tyre_damping_n_s_m,
                    v.speed_m_s,
                );
                let road = kt * self.road.elevation_m(x_m) + ct * speed * self.road.slope(x_m);
                let d = o + dof;
                self.stiffness[(d, d)] += kt;
                self.damping[(d, d)] += ct;
                self.load[d] += road;
                if !on_span {
                    continue;
                }
                for (&a, &ha) in self.h.idx.iter().zip(&self.h.val) {
                    // Bridge row a: + h_a f_j on the left, - h_a F_static on the right.
                    for (&b, &hb) in self.h.idx.iter().zip(&self.h.val) {
                        self.stiffness[(a, b)] += kt * ha * hb;
                        self.damping[(a, b)] += ct * ha * hb;
                    }
                    for (&b, &gb) in self.h_slope.idx.iter().zip(&self.h_slope.val) {
                        self.stiffness[(a, b)] += ct * speed * ha * gb;
                    }
                    self.stiffness[(a, d)] -= kt * ha;
                    self.damping[(a, d)] -= ct * ha;
                    self.load[a] -= ha * (axle.static_load_n + road);
                    // Vehicle row d: - f_j on the left.
                    self.stiffness[(d, a)] -= kt * ha;
                    self.damping[(d, a)] -= ct * ha;
                }
                for (&b, &gb) in self.h_slope.idx.iter().zip(&self.h_slope.val) {
                    self.stiffness[(d, b)] -= ct * speed * gb;
                }
            }
        }
    }

    /// `(K + a0 M + a1 C) x_{n+1} = F + M (a0 x + a2 x' + a3 x'') + C (a1 x + a4 x' + a5 x'')`
    /// by a fresh dense LU with partial pivoting; the solution replaces `load`.
    fn solve(&mut self) {
        let c = self.coefficients;
        self.scratch.copy_from(&self.x);
        self.scratch.scale_mut(c.a0);
        self.scratch.axpy(c.a2, &self.xd, 1.0);
        self.scratch.axpy(c.a3, &self.xdd, 1.0);
        self.load.gemv(1.0, &self.mass, &self.scratch, 1.0);
        self.scratch.copy_from(&self.x);
        self.scratch.scale_mut(c.a1);
        self.scratch.axpy(c.a4, &self.xd, 1.0);
        self.scratch.axpy(c.a5, &self.xdd, 1.0);
        self.load.gemv(1.0, &self.damping, &self.scratch, 1.0);
        let (m, d, k) = (&self.mass, &self.damping, &self.stiffness);
        let n = m.nrows();
        self.lu.solve(
            n,
            |i, j| k[(i, j)] + c.a0 * m[(i, j)] + c.a1 * d[(i, j)],
            self.load.as_mut_slice(),
        );
    }

    /// Newmark updates of bridge and vehicles, and the tyre forces at the new state.
    fn commit(&mut self, next: u64) {
        let c = self.coefficients;
        let nb = self.model.n_dof();
        let update = |s: &mut State, x_next: &[f64]| {
            for (i, &x) in x_next.iter().enumerate() {
                let a_next = c.acceleration(x, s.u[i], s.v[i], s.a[i]);
                s.v[i] += c.dt_s * ((1.0 - c.gamma) * s.a[i] + c.gamma * a_next);
                s.a[i] = a_next;
                s.u[i] = x;
            }
        };
        update(&mut self.bridge_state, &self.load.as_slice()[..nb]);
        let model = self.model;
        for (i, v) in self.vehicles.iter_mut().enumerate() {
            if !self.active[i] {
                continue;
            }
            let (o, nv) = (self.offsets[i], v.dynamics.n_dof());
            update(&mut v.state, &self.load.as_slice()[o..o + nv]);
            for (j, axle) in v.dynamics.axles.iter().enumerate() {
                let x_m = v.axle_x_m(j, next, c.dt_s);
                let f = match axle.dof {
                    None => 0.0,
                    Some(dof) => {
                        let (kt, ct, speed) = (
                            axle.tyre_stiffness_n_m,
                            axle.tyre_damping_n_s_m,
                            v.speed_m_s,
                        );
                        model.point_operator(x_m, PointQuantity::Deflection, &mut self.h);
                        model.point_operator(x_m, PointQuantity::Slope, &mut self.h_slope);
                        let s = &self.bridge_state;
                        let z = self.h.dot(&s.u) + self.road.elevation_m(x_m);
                        let z_rate = self.h.dot(&s.v)
                            + speed * (self.h_slope.dot(&s.u) + self.road.slope(x_m));
                        kt * (z - v.state.u[dof]) + ct * (z_rate - v.state.v[dof])
                    }
                };
                v.contact_force_n[j] = axle.static_load_n + f;
                v.in_contact[j] = true;
            }
            if v.contact_force_n.iter().any(|&f| f < 0.0) {
                v.contact_loss_steps += 1;
            }
        }
    }

    /// Bridge quantity at x from the current state (`which` 0: u, 1: v, 2: a), as
    /// [`CoupledSolver::bridge_response`](super::CoupledSolver::bridge_response).
    pub fn bridge_response(
        &self,
        x_m: f64,
        quantity: PointQuantity,
        which: usize,
        op: &mut SparseVec,
    ) -> f64 {
        self.model.point_operator(x_m, quantity, op);
        let s = &self.bridge_state;
        op.dot(match which {
            0 => &s.u,
            1 => &s.v,
            _ => &s.a,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::bridge::{BeamProperties, LumpedStiffness, ModelSpec};
    use crate::physics::road::{IsoClass, RoadProfile, RoadProfileSpec};
    use crate::physics::solver::{ContactLaw, CoupledSolver, NewmarkParams, SolveMode, Storage};
    use crate::physics::vehicle::{HalfCarSpec, VehicleModelSpec};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn truck(start_front_x_m: f64, speed_m_s: f64) -> CoupledVehicle {
        let dynamics = VehicleModelSpec::HalfCar(HalfCarSpec {
            preset: Some("two_axle_truck".into()),
            ..Default::default()
        })
        .build("vehicle")
        .unwrap();
        CoupledVehicle::new(0, dynamics, speed_m_s, start_front_x_m, 0)
    }

    /// Runs both solvers side by side over a whole crossing and returns the largest
    /// differences of midspan deflection and tyre force relative to their peaks.
    fn compare(spec: ModelSpec, storage: Storage) -> (f64, f64) {
        let model = BridgeModel::build(&BeamProperties::paper_default(), &spec, 0.02).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(2021);
        let road = RoadProfile::build(
            &RoadProfileSpec::iso8608(IsoClass::A),
            -30.0,
            90.0,
            &mut rng,
        )
        .unwrap();
        let coef = NewmarkCoefficients::new(2e-3, NewmarkParams::default()).unwrap();
        let (start, speed) = (-20.0, 20.0);
        let mut low_rank = CoupledSolver::new(
            &model,
            &road,
            coef,
            SolveMode::Prefactored(storage),
            ContactLaw::Full,
        )
        .unwrap();
        low_rank.add_vehicle(truck(start, speed));
        let mut direct = DirectSolver::new(&model, &road, coef).unwrap();
        direct.add_vehicle(truck(start, speed));
        let mut op = SparseVec::default();
        let (mut du, mut u_peak, mut df, mut f_peak) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        // Until the rear axle is 10 m past the bridge: approach, crossing, free vibration.
        let steps = ((30.0 + 10.0 + 4.27 - start) / speed / coef.dt_s) as usize;
        for _ in 0..steps {
            low_rank.advance().unwrap();
            direct.advance().unwrap();
            let a = low_rank.bridge_response(15.0, PointQuantity::Deflection, 0, &mut op);
            let b = direct.bridge_response(15.0, PointQuantity::Deflection, 0, &mut op);
            du = du.max((a - b).abs());
            u_peak = u_peak.max(a.abs());
            for (fa, fb) in low_rank.vehicles[0]
                .contact_force_n
                .iter()
                .zip(&direct.vehicles[0].contact_force_n)
            {
                df = df.max((fa - fb).abs());
                f_peak = f_peak.max(fa.abs());
            }
        }
        assert!(u_peak > 1e-3, "the truck must load the bridge: {u_peak}");
        (du / u_peak, df / f_peak)
    }

    #[test]
    fn direct_method_matches_low_rank_coupling_finite_elements() {
        // Same Newmark, same linear tyre law, different linear algebra (Cholesky + a 2x2
        // contact system vs one LU of the whole system): only round-off may differ. The
        // effective matrices have condition numbers ~1e6, so 1e-9 relative leaves room.
        let (du, df) = compare(ModelSpec::FiniteElement { elements: 20 }, Storage::Sparse);
        assert!(du < 1e-9 && df < 1e-9, "deflection {du:e}, force {df:e}");
    }

    #[test]
    fn direct_method_matches_low_rank_coupling_lumped_mass() {
        // As above; the lumped-mass K = F^-1 is dense and the reduction maps the wheel
        // point onto every mass, so every bridge DOF couples to the tyres.
        let spec = ModelSpec::LumpedMass {
            nodes: 15,
            stiffness: LumpedStiffness::Auto,
        };
        let (du, df) = compare(spec, Storage::Dense);
        assert!(du < 1e-9 && df < 1e-9, "deflection {du:e}, force {df:e}");
    }
}
