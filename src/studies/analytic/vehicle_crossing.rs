//! A linear vehicle on several tyres crossing a simply supported beam: semi-analytical
//! modal solution, the multi-axle companion of [`super::sprung_mass`].
//!
//! The vehicle is given by its matrices (mass, suspension damping and stiffness, tyres
//! excluded) and its tyres, so a half car, a multi-axle truck or an articulated vehicle
//! crosses the beam the same way; the caller supplies the matrices. The beam is expanded
//! in its exact modes `sin(n pi x / L)` and everything is integrated together by the
//! adaptive Dormand-Prince method of [`super::dopri45`], as for the sprung mass (whose
//! module docs give the reasons for the method and its step cap).
//!
//! # Conventions and equations
//!
//! Displacements and forces positive DOWNWARD; road elevation `r(x)` positive UPWARD.
//! The vehicle DOFs `y` are measured from static equilibrium on the level rigid road.
//! Tyre `j` sits `d_j` behind the front axle, at `x_j(t) = x_0 - d_j + v t`, between
//! vehicle DOF `i_j` and the road surface on the deflected beam, whose downward
//! displacement is `u_j = w(x_j, t) - r(x_j)` (`w = 0` off the beam). The tyre's
//! compression beyond static and its rate are
//!
//! `s_j = y_(i_j) - u_j`,
//! `s_j' = y_(i_j)' - (dw/dt + v dw/dx)(x_j, t) + v dr/dx(x_j)`   (convective terms kept),
//!
//! its dynamic force `f_j = kt_j s_j + ct_j s_j'`, and, with `P_j` the static axle load,
//!
//! `M y'' + C y' + K y = - sum_j e_(i_j) f_j`,
//! `q_n'' + 2 zeta_n w_n q_n' + w_n^2 q_n = (2 / (m L)) sum_(j on the beam) (P_j + f_j)
//! sin(n pi x_j / L)`.
//!
//! With `M = [m_v]`, `C = K = 0` and the suspension as the one "tyre" this is the sprung
//! mass's system (`src/studies/analytic/sprung_mass.rs`), which the tests use. The upward
//! convention of a vehicle model maps onto this one by negating every DOF, which leaves
//! `M`, `C` and `K` unchanged.
//!
//! The beam starts at rest and undeformed, the vehicle at rest in static equilibrium on
//! the road under its tyres, `(K + sum kt_j e e^T) y = sum kt_j e u_j(0)`, with every tyre
//! at or before the entry (`x_j(0) <= 0`). The integration restarts where a tyre enters
//! or leaves the beam and where the road under a tyre has a kink. The wheels never lift
//! off (the contact force may go negative).

use nalgebra::{DMatrix, DVector};

use super::beam::{harmonics, SimplySupportedBeam};
use super::crossing::{
    midspan_truncation_bound_m, validate_sample_times, BeamModes, ContactTail, CrossingDefaults,
    CrossingOptions,
};
use super::dopri45::Dopri45Stats;
use super::road_irregularity::RoadIrregularity;
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};

/// One tyre: a spring and dashpot between a vehicle DOF and the road surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tyre {
    /// Distance behind the front axle, m (>= 0).
    pub offset_m: f64,
    /// The vehicle DOF the tyre acts on.
    pub dof: usize,
    /// Tyre stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Tyre damping, N s/m.
    pub damping_n_s_m: f64,
    /// Static load on a level rigid road, N (downward).
    pub static_load_n: f64,
}

/// The vehicle: matrices of the suspended system (tyres excluded) and its tyres.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearVehicle {
    /// Mass matrix (kg, kg m^2), symmetric positive definite.
    pub mass: DMatrix<f64>,
    /// Suspension damping matrix.
    pub damping: DMatrix<f64>,
    /// Suspension stiffness matrix.
    pub stiffness: DMatrix<f64>,
    /// The tyres, at least one.
    pub tyres: Vec<Tyre>,
}

impl LinearVehicle {
    /// Number of vehicle DOFs.
    pub fn n_dof(&self) -> usize {
        self.mass.nrows()
    }

    /// Stiffness with the tyres on a rigid road.
    fn stiffness_with_tyres(&self) -> DMatrix<f64> {
        let mut k = self.stiffness.clone();
        for t in &self.tyres {
            k[(t.dof, t.dof)] += t.stiffness_n_m;
        }
        k
    }

    /// Damping with the tyres on a rigid road.
    fn damping_with_tyres(&self) -> DMatrix<f64> {
        let mut c = self.damping.clone();
        for t in &self.tyres {
            c[(t.dof, t.dof)] += t.damping_n_s_m;
        }
        c
    }

    /// Checks shapes, a positive definite mass matrix and every tyre; errors name
    /// `vehicle.<field>`.
    pub fn validate(&self) -> Result<()> {
        let n = self.n_dof();
        if n == 0 || self.mass.ncols() != n {
            return Err(Error::invalid(
                "vehicle.mass",
                format!("{}x{}", self.mass.nrows(), self.mass.ncols()),
                "must be square with at least one DOF",
            ));
        }
        for (name, m) in [
            ("vehicle.damping", &self.damping),
            ("vehicle.stiffness", &self.stiffness),
        ] {
            if m.nrows() != n || m.ncols() != n {
                return Err(Error::invalid(
                    name,
                    format!("{}x{}", m.nrows(), m.ncols()),
                    format!("must be {n}x{n} like vehicle.mass"),
                ));
            }
        }
        if self.mass.clone().cholesky().is_none() {
            return Err(Error::invalid(
                "vehicle.mass",
                "not positive definite",
                "must be symmetric positive definite",
            ));
        }
        if self.tyres.is_empty() {
            return Err(Error::invalid(
                "vehicle.tyres",
                "[]",
                "needs at least one tyre",
            ));
        }
        for (j, t) in self.tyres.iter().enumerate() {
            require_non_negative(&format!("vehicle.tyres[{j}].offset_m"), t.offset_m)?;
            if t.dof >= n {
                return Err(Error::invalid(
                    format!("vehicle.tyres[{j}].dof"),
                    t.dof,
                    format!("must be < {n}, the number of vehicle DOFs"),
                ));
            }
            require_non_negative(
                &format!("vehicle.tyres[{j}].stiffness_n_m"),
                t.stiffness_n_m,
            )?;
            require_non_negative(
                &format!("vehicle.tyres[{j}].damping_n_s_m"),
                t.damping_n_s_m,
            )?;
            require_finite(
                &format!("vehicle.tyres[{j}].static_load_n"),
                t.static_load_n,
            )?;
        }
        Ok(())
    }
}

/// Model and integration settings: 50 modes and steps of at most 1e-4 s by default (the
/// common defaults are at [`CrossingOptions`]). The peak is taken at the accepted steps;
/// a step h samples a peak of frequency w within (w h)^2 / 8 (1e-5 at 4 Hz, and the
/// stability cap of 50 modes keeps h far below the limit).
pub type VehicleCrossingOptions = CrossingOptions<VehicleCrossingProblem>;

impl CrossingDefaults for VehicleCrossingProblem {
    const N_MODES: usize = 50;
    const MAX_STEP_S: f64 = 1e-4;
}

/// The crossing to solve.
#[derive(Debug)]
pub struct VehicleCrossingProblem {
    /// The beam.
    pub beam: SimplySupportedBeam,
    /// The vehicle.
    pub vehicle: LinearVehicle,
    /// Constant forward speed, m/s.
    pub speed_m_s: f64,
    /// Position of the front axle at t = 0, m (<= 0: every tyre starts off the beam).
    pub start_front_m: f64,
    /// Road irregularity (on and off the beam); `None` = level road.
    pub road: Option<RoadIrregularity>,
    /// Settings.
    pub options: VehicleCrossingOptions,
}

/// The response at one sample time.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleCrossingSample {
    /// Time since the start, s.
    pub time_s: f64,
    /// Beam deflection at midspan (downward positive), m.
    pub midspan_deflection_m: f64,
    /// Downward force of each tyre on the beam or road, static load included, N.
    pub contact_forces_n: Vec<f64>,
    /// Vehicle displacements from static equilibrium (downward positive).
    pub vehicle_displacements: Vec<f64>,
}

/// Time series and peaks of a crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleCrossingSolution {
    /// One sample per requested time, in order.
    pub samples: Vec<VehicleCrossingSample>,
    /// Largest midspan deflection over every integration step up to the last sample, m.
    pub peak_midspan_deflection_m: f64,
    /// When it occurred, s.
    pub peak_time_s: f64,
    /// Per tyre, the largest |contact force| over the steps with that tyre on the beam, N.
    pub max_contact_forces_on_beam_n: Vec<f64>,
    /// Per tyre, the smallest contact force over all steps, N (negative = tension).
    pub min_contact_forces_n: Vec<f64>,
    /// Bound on the mode-truncation error of the midspan deflection while tyres are on
    /// the beam, m: [`super::crossing::midspan_truncation_bound_m`] with each tyre's
    /// largest force on the beam plus its dashpot's jumps at road kinks, and `w_c` twice
    /// the larger of the vehicle's fastest rigid-road frequency bound and the beam's first.
    pub truncation_bound_m: f64,
    /// Integrator work counters.
    pub stats: Dopri45Stats,
}

/// A time interval with no discontinuity of the RHS inside.
#[derive(Debug, Clone)]
struct Segment {
    t_lo_s: f64,
    t_hi_s: f64,
    /// Per tyre: on the beam throughout the segment.
    on_beam: Vec<bool>,
}

/// The coupled ODE.
struct Model<'a> {
    n: usize,
    speed_m_s: f64,
    start_front_m: f64,
    modes: BeamModes,
    force_to_modal: f64,
    vehicle: &'a LinearVehicle,
    inverse_mass: DMatrix<f64>,
    road: Option<&'a RoadIrregularity>,
}

/// Work buffers: mode shapes and slopes at each tyre, vehicle vectors.
struct Workspace {
    sin: Vec<Vec<f64>>,
    cos: Vec<Vec<f64>>,
    forces: Vec<f64>,
    rhs: DVector<f64>,
}

impl Workspace {
    fn new(n: usize, vehicle: &LinearVehicle) -> Self {
        let tyres = vehicle.tyres.len();
        Self {
            sin: vec![vec![0.0; n]; tyres],
            cos: vec![vec![0.0; n]; tyres],
            forces: vec![0.0; tyres],
            rhs: DVector::zeros(vehicle.n_dof()),
        }
    }
}

impl Model<'_> {
    fn tyre_x_m(&self, j: usize, t: f64) -> f64 {
        self.start_front_m - self.vehicle.tyres[j].offset_m + self.speed_m_s * t
    }

    /// Dynamic tyre forces `f_j` into `ws.forces`; leaves the mode shapes at each tyre on
    /// the beam in `ws.sin[j]`.
    fn tyre_forces(&self, ws: &mut Workspace, t: f64, y: &[f64], seg: &Segment) {
        let n = self.n;
        let nv = self.vehicle.n_dof();
        let v = self.speed_m_s;
        for (j, tyre) in self.vehicle.tyres.iter().enumerate() {
            let x = self.tyre_x_m(j, t);
            let (mut w, mut w_rate) = (0.0, 0.0);
            if seg.on_beam[j] {
                let (sin, cos) = (&mut ws.sin[j], &mut ws.cos[j]);
                harmonics(self.modes.wavenumber_per_m * x, sin, cos);
                let mut slope = 0.0;
                for i in 0..n {
                    w += y[i] * sin[i];
                    w_rate += y[n + i] * sin[i];
                    slope += y[i] * (i + 1) as f64 * cos[i];
                }
                // dw/dt + v dw/dx (the convective term).
                w_rate += v * self.modes.wavenumber_per_m * slope;
            }
            let (elevation, road_rate) = match self.road {
                Some(road) => {
                    // The slope strictly inside the segment: one-sided at kinks.
                    let lo = self.tyre_x_m(j, seg.t_lo_s);
                    let hi = self.tyre_x_m(j, seg.t_hi_s);
                    let margin = 1e-9 * (hi - lo).max(1e-9);
                    let inside = x.clamp(lo + margin, (hi - margin).max(lo + margin));
                    (road.elevation_m(x), v * road.slope(inside))
                }
                None => (0.0, 0.0),
            };
            let compression = y[2 * n + tyre.dof] - (w - elevation);
            let compression_rate = y[2 * n + nv + tyre.dof] - (w_rate - road_rate);
            ws.forces[j] = tyre.stiffness_n_m * compression + tyre.damping_n_s_m * compression_rate;
        }
    }

    fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dydt: &mut [f64], seg: &Segment) {
        let n = self.n;
        let nv = self.vehicle.n_dof();
        self.tyre_forces(ws, t, y, seg);
        for i in 0..n {
            dydt[i] = y[n + i];
            dydt[n + i] = -self.modes.two_zeta_omega[i] * y[n + i] - self.modes.omega_sq[i] * y[i];
        }
        for (j, tyre) in self.vehicle.tyres.iter().enumerate() {
            if seg.on_beam[j] {
                let modal = self.force_to_modal * (tyre.static_load_n + ws.forces[j]);
                for i in 0..n {
                    dydt[n + i] += modal * ws.sin[j][i];
                }
            }
        }
        // M y'' = -C y' - K y - sum e f.
        let (q_v, rates) = y[2 * n..].split_at(nv);
        for r in 0..nv {
            let mut acc = 0.0;
            for c in 0..nv {
                acc -= self.vehicle.damping[(r, c)] * rates[c]
                    + self.vehicle.stiffness[(r, c)] * q_v[c];
            }
            ws.rhs[r] = acc;
        }
        for (j, tyre) in self.vehicle.tyres.iter().enumerate() {
            ws.rhs[tyre.dof] -= ws.forces[j];
        }
        for r in 0..nv {
            dydt[2 * n + r] = rates[r];
            dydt[2 * n + nv + r] = (0..nv).map(|c| self.inverse_mass[(r, c)] * ws.rhs[c]).sum();
        }
    }

    fn sample(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        seg: &Segment,
    ) -> VehicleCrossingSample {
        self.tyre_forces(ws, t, y, seg);
        let n = self.n;
        let nv = self.vehicle.n_dof();
        VehicleCrossingSample {
            time_s: t,
            midspan_deflection_m: self.modes.midspan(y),
            contact_forces_n: self
                .vehicle
                .tyres
                .iter()
                .zip(&ws.forces)
                .map(|(tyre, f)| tyre.static_load_n + f)
                .collect(),
            vehicle_displacements: y[2 * n..2 * n + nv].to_vec(),
        }
    }
}

impl VehicleCrossingProblem {
    /// Checks every input.
    pub fn validate(&self) -> Result<()> {
        self.beam.validate()?;
        self.vehicle.validate()?;
        require_positive("speed_m_s", self.speed_m_s)?;
        require_finite("start_front_m", self.start_front_m)?;
        if self.start_front_m > 0.0 {
            return Err(Error::invalid(
                "start_front_m",
                self.start_front_m,
                "must be <= 0 (every tyre starts off the beam)",
            ));
        }
        self.options.validate()?;
        Ok(())
    }

    /// Time at which the last tyre leaves the beam, s.
    pub fn exit_time_s(&self) -> f64 {
        let last = self
            .vehicle
            .tyres
            .iter()
            .map(|t| t.offset_m)
            .fold(0.0, f64::max);
        (self.beam.span_m + last - self.start_front_m) / self.speed_m_s
    }

    /// Integrates from t = 0 to the last sample time and returns the response at
    /// `sample_times_s` (finite, >= 0, non-decreasing).
    pub fn solve(&self, sample_times_s: &[f64]) -> Result<VehicleCrossingSolution> {
        self.validate()?;
        validate_sample_times(sample_times_s)?;
        let t_end = sample_times_s.last().copied().unwrap_or(0.0);
        let beam = &self.beam;
        let o = &self.options;
        let n = o.n_modes;
        let vehicle = &self.vehicle;
        let nv = vehicle.n_dof();
        let tyres = vehicle.tyres.len();
        let v = self.speed_m_s;
        let inverse_mass =
            vehicle
                .mass
                .clone()
                .try_inverse()
                .ok_or_else(|| Error::Factorization {
                    what: "vehicle mass matrix".into(),
                    reason: "singular".into(),
                })?;
        let model = Model {
            n,
            speed_m_s: v,
            start_front_m: self.start_front_m,
            modes: BeamModes::new(beam, n, &o.damping),
            force_to_modal: 2.0 / (beam.mass_per_length_kg_m * beam.span_m),
            vehicle,
            inverse_mass,
            road: self.road.as_ref(),
        };

        // Breakpoints: each tyre's entry and exit, and the road's kinks under each tyre.
        let mut breaks = vec![0.0];
        for j in 0..tyres {
            let at = |x: f64| (x - model.tyre_x_m(j, 0.0)) / v;
            breaks.push(at(0.0));
            breaks.push(at(beam.span_m));
            if let Some(road) = &self.road {
                breaks.extend(road.kinks_m().iter().map(|&x| at(x)));
            }
        }
        breaks.retain(|&t| t > 0.0 && t < t_end);
        breaks.push(0.0);
        breaks.push(t_end);
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();

        // Initial state: beam at rest; the vehicle at rest in static equilibrium on the
        // road under its tyres.
        let mut state = vec![0.0; 2 * n + 2 * nv];
        if let Some(road) = &self.road {
            let mut load = DVector::zeros(nv);
            for (j, tyre) in vehicle.tyres.iter().enumerate() {
                load[tyre.dof] -= tyre.stiffness_n_m * road.elevation_m(model.tyre_x_m(j, 0.0));
            }
            let y0 = vehicle
                .stiffness_with_tyres()
                .lu()
                .solve(&load)
                .ok_or_else(|| Error::Factorization {
                    what: "vehicle stiffness with tyres".into(),
                    reason: "singular (a DOF without spring support?)".into(),
                })?;
            state[2 * n..2 * n + nv].copy_from_slice(y0.as_slice());
        }

        let mut atol = vec![o.atol_displacement_m; 2 * n + 2 * nv];
        atol[n..2 * n].fill(o.atol_velocity_m_s);
        atol[2 * n + nv..].fill(o.atol_velocity_m_s);
        let vehicle_rad_s = fastest_rate_bound(vehicle, &model.inverse_mass);
        let mut solver = o.integrator_covering(&model.modes, vehicle_rad_s, atol)?;
        let mut rhs_ws = Workspace::new(n, vehicle);
        let mut observer_ws = Workspace::new(n, vehicle);
        let mut samples = Vec::with_capacity(sample_times_s.len());
        let mut next_sample = 0;
        let mut peak = (0.0, 0.0);
        let mut max_on_beam = vec![0.0_f64; tyres];
        let mut min_force = vec![f64::INFINITY; tyres];
        let mut t = 0.0;
        for window in breaks
            .windows(2)
            .chain(std::iter::once(&[t_end, t_end][..]))
        {
            let (seg_start, seg_end) = (window[0], window[1]);
            let mid_t = 0.5 * (seg_start + seg_end);
            let seg = Segment {
                t_lo_s: seg_start,
                t_hi_s: seg_end,
                on_beam: (0..tyres)
                    .map(|j| {
                        let x = model.tyre_x_m(j, mid_t);
                        x > 0.0 && x < beam.span_m
                    })
                    .collect(),
            };
            loop {
                while next_sample < sample_times_s.len() && sample_times_s[next_sample] <= t {
                    samples.push(model.sample(&mut observer_ws, t, &state, &seg));
                    next_sample += 1;
                }
                let target = match sample_times_s.get(next_sample) {
                    Some(&ts) if ts < seg_end => ts,
                    _ => seg_end,
                };
                if target <= t {
                    break;
                }
                let mut rhs =
                    |tt: f64, y: &[f64], d: &mut [f64]| model.rhs(&mut rhs_ws, tt, y, d, &seg);
                solver.advance(&mut rhs, t, target, &mut state, &mut |tt, y| {
                    let w_mid = model.modes.midspan(y);
                    if w_mid > peak.1 {
                        peak = (tt, w_mid);
                    }
                    model.tyre_forces(&mut observer_ws, tt, y, &seg);
                    for (j, tyre) in vehicle.tyres.iter().enumerate() {
                        let force = tyre.static_load_n + observer_ws.forces[j];
                        min_force[j] = min_force[j].min(force);
                        if seg.on_beam[j] {
                            max_on_beam[j] = max_on_beam[j].max(force.abs());
                        }
                    }
                })?;
                t = target;
                if state.iter().any(|s| !s.is_finite()) {
                    return Err(Error::Divergence {
                        time_s: t,
                        step: solver.stats().accepted_steps,
                        quantity: "state".into(),
                        value: f64::NAN,
                        hint: "non-finite vehicle-crossing state".into(),
                    });
                }
            }
        }
        let truncation_bound_m = self.truncation_bound_m(&max_on_beam, vehicle_rad_s);
        Ok(VehicleCrossingSolution {
            samples,
            peak_midspan_deflection_m: peak.1,
            peak_time_s: peak.0,
            max_contact_forces_on_beam_n: max_on_beam,
            min_contact_forces_n: min_force,
            truncation_bound_m,
            stats: solver.stats(),
        })
    }

    fn truncation_bound_m(&self, max_on_beam_n: &[f64], vehicle_rad_s: f64) -> f64 {
        let beam = &self.beam;
        let v = self.speed_m_s;
        let h = 1e-9 * beam.span_m;
        let contacts: Vec<ContactTail> = self
            .vehicle
            .tyres
            .iter()
            .zip(max_on_beam_n)
            .map(|(tyre, &max_n)| {
                // The dashpot force jumps by ct v |d(dr/dx)| where the road's slope jumps.
                let jumps_n: f64 = match &self.road {
                    Some(road) => road
                        .kinks_m()
                        .iter()
                        .filter(|&&x| x > 0.0 && x < beam.span_m)
                        .map(|&x| {
                            tyre.damping_n_s_m * v * (road.slope(x + h) - road.slope(x - h)).abs()
                        })
                        .sum(),
                    None => 0.0,
                };
                ContactTail {
                    force_bound_n: max_n + jumps_n,
                    stiffness_n_m: tyre.stiffness_n_m,
                    damping_n_s_m: tyre.damping_n_s_m,
                }
            })
            .collect();
        midspan_truncation_bound_m(
            beam,
            self.options.n_modes,
            v,
            2.0 * vehicle_rad_s.max(beam.omega_rad_s(1)),
            &contacts,
        )
    }
}

/// Bound on the largest eigenvalue magnitude of the vehicle on a rigid road (1/s): the
/// roots of `lambda^2 + a lambda + b` with `a = ||M^-1 C||` and `b = ||M^-1 K||` (row-sum
/// norms, tyres included) have `|lambda| <= a + sqrt(b)`.
fn fastest_rate_bound(vehicle: &LinearVehicle, inverse_mass: &DMatrix<f64>) -> f64 {
    let norm = |m: DMatrix<f64>| {
        m.row_iter()
            .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let a = norm(inverse_mass * vehicle.damping_with_tyres());
    let b = norm(inverse_mass * vehicle.stiffness_with_tyres());
    a + b.sqrt()
}

#[cfg(test)]
mod tests;
