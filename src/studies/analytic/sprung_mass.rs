//! A single sprung mass crossing a simply supported beam: semi-analytical modal solution.
//!
//! The beam is expanded in its exact modes `sin(n pi x / L)` (N modes, default 100); the
//! mass `m_v` rides on a spring `k_v` and dashpot `c_v` whose lower end follows the road
//! surface on the deflected beam. The modal ODEs and the mass's ODE are integrated together
//! by the adaptive Dormand-Prince 5(4) method of [`super::dopri45`] with tight tolerances.
//! The formulation follows Yang, Yau & Wu, Vehicle-Bridge Interaction Dynamics (2004),
//! chapter 2 ("sprung mass model"), and Fryba (1972) chapter 1 for the modal projection.
//!
//! # Conventions and equations
//!
//! Displacements positive DOWNWARD: beam deflection `w(x, t) = sum q_n sin(n pi x / L)`,
//! mass displacement `y_v` measured from its static-equilibrium position on the undeformed,
//! level road. The road irregularity `r(x)` is the road-surface ELEVATION, positive UPWARD.
//! The contact point (bottom of the spring, rigidly on the road) therefore sits at the
//! downward displacement `u = w(x_v, t) - r(x_v)`, and the dynamic compression of the
//! suspension (beyond its static compression `m_v g / k_v`) is
//!
//! `s = y_v - u = y_v - w(x_v, t) + r(x_v)`,
//! `s' = y_v' - (dw/dt + v dw/dx)(x_v, t) + v dr/dx(x_v)`   (convective terms included),
//!
//! with `x_v = v t`. The mass and the beam modes obey
//!
//! `m_v y_v'' = -(k_v s + c_v s')`,
//! `q_n'' + 2 zeta_n w_n q_n' + w_n^2 q_n = (2 / (m L)) F sin(n pi x_v / L)` for
//! `0 <= x_v <= L`, where `F = m_v g + k_v s + c_v s'` is the downward contact force.
//!
//! The mass starts at `x = 0`, `t = 0` in static equilibrium on the road (`s = s' = 0`),
//! the beam at rest and undeformed (the weight enters with the mass; its modal force is
//! zero at the support). After the mass leaves (`x_v > L`) the beam vibrates freely and
//! the mass rides on the rigid road (`w = 0`). The wheel has no mass and the spring no
//! contact limit: the contact force may go negative (see
//! [`SprungMassSolution::min_contact_force_n`]).
//!
//! # Why adaptive Dormand-Prince on every mode, with a stability cap
//!
//! The system is stiff: the highest kept mode (`w_100` ~ 2.6e5 rad/s for the 25 m
//! reference beam) bounds an explicit step, while the physics of interest is below 100 Hz.
//! Treating high modes quasi-statically would turn the dashpot coupling into a stiff
//! differential-algebraic loop and change the model; an implicit method would share the
//! character of the production solvers this module checks. So every mode is integrated
//! dynamically, and the step is capped at `y / |lambda|_max` with `|lambda|_max` the largest
//! modal eigenvalue (`w_N` for under-damped modes) and `y` =
//! [`CrossingOptions::step_stability_factor`](super::CrossingOptions::step_stability_factor) (default 0.5). Reason: on the imaginary
//! axis the Dormand-Prince stability function satisfies `|R(iy)| < 1` only for
//! `|y| < ~0.99`. Left to the error controller alone, undamped top modes sit at `w h ~ 1`,
//! grow slowly, and are reined in only once their amplitude reaches ~1e3 x atol (the
//! embedded error estimate is ~1e-3 of the amplitude there): a noise floor that made the
//! peaks depend on the tolerance at 1e-7 relative. Below the cap every mode is damped by
//! the method by `~y^6 / 10 700` per step (1.5e-6 for the top mode at y = 0.5, 2e-8 for
//! the mode at half its frequency): with a dashpot the top modes feed back into the contact
//! force, and y = 0.8 left a 1e-7 bias in the peaks that y = 0.5 removes. The tolerances
//! then control the real truncation error of the modes that matter.
//! Cost: ~2 w_N steps per second simulated (~5e5 at N = 100 on the reference beam),
//! growing as N^3 (steps ~ w_N ~ N^2, work per step ~ N). The right-hand side is
//! discontinuous where the mass leaves the beam and at kinks of the road profile: the
//! integration restarts exactly there.

use super::beam::{harmonics, SimplySupportedBeam};
use super::crossing::{
    midspan_truncation_bound_m, validate_sample_times, BeamModes, ContactTail, CrossingDefaults,
    CrossingOptions,
};
use super::dopri45::Dopri45Stats;
use super::road_irregularity::RoadIrregularity;
use crate::error::{require_non_negative, require_positive, Error, Result};

pub use super::crossing::MAX_MODES;

/// The vehicle: a mass on a linear spring and dashpot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SprungMassVehicle {
    /// Sprung mass, kg.
    pub mass_kg: f64,
    /// Suspension stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Suspension damping, N s/m.
    pub damping_n_s_m: f64,
}

impl SprungMassVehicle {
    /// Checks mass > 0, stiffness and damping >= 0 (with both 0 the mass floats and the
    /// beam carries exactly its weight: the moving-force case).
    pub fn validate(&self) -> Result<()> {
        require_positive("vehicle.mass_kg", self.mass_kg)?;
        require_non_negative("vehicle.stiffness_n_m", self.stiffness_n_m)?;
        require_non_negative("vehicle.damping_n_s_m", self.damping_n_s_m)?;
        Ok(())
    }
}

/// Model and integration settings: 100 modes and no step limit but the stability cap by
/// default (the common defaults are at [`CrossingOptions`]).
pub type SprungMassOptions = CrossingOptions<SprungMassProblem>;

impl CrossingDefaults for SprungMassProblem {
    const N_MODES: usize = 100;
    const MAX_STEP_S: f64 = f64::INFINITY;
}

/// The crossing to solve.
#[derive(Debug)]
pub struct SprungMassProblem {
    /// The beam.
    pub beam: SimplySupportedBeam,
    /// The vehicle.
    pub vehicle: SprungMassVehicle,
    /// Constant forward speed, m/s.
    pub speed_m_s: f64,
    /// Road irregularity (on and off the beam); `None` = level road.
    pub road: Option<RoadIrregularity>,
    /// Settings.
    pub options: SprungMassOptions,
}

/// The response at one sample time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SprungMassSample {
    /// Time since the mass entered the beam, s.
    pub time_s: f64,
    /// Position of the mass, `v t`, m.
    pub position_m: f64,
    /// Beam deflection at midspan (downward positive), m.
    pub midspan_deflection_m: f64,
    /// Beam deflection under the mass (0 off the beam), m.
    pub contact_deflection_m: f64,
    /// Downward contact force on the beam or road, static weight included, N.
    pub contact_force_n: f64,
    /// Mass displacement from static equilibrium on the level road (downward positive), m.
    pub mass_displacement_m: f64,
    /// Mass velocity (downward positive), m/s.
    pub mass_velocity_m_s: f64,
    /// Velocity of the contact point, `dw/dt + v dw/dx - v dr/dx` (downward), m/s.
    pub contact_point_velocity_m_s: f64,
    /// Road elevation under the mass (upward positive), m.
    pub road_elevation_m: f64,
    /// Vibration energy of the beam, `sum (m L / 4) (q_n'^2 + w_n^2 q_n^2)`, J.
    pub beam_energy_j: f64,
    /// Vibration energy of the vehicle about static equilibrium,
    /// `m_v y_v'^2 / 2 + k_v s^2 / 2`, J.
    pub vehicle_energy_j: f64,
}

/// Time series and peaks of a crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct SprungMassSolution {
    /// One sample per requested time, in order.
    pub samples: Vec<SprungMassSample>,
    /// Largest midspan deflection over every integration step up to the last sample, m.
    pub peak_midspan_deflection_m: f64,
    /// When it occurred, s.
    pub peak_time_s: f64,
    /// Largest midspan deflection while the mass is on the beam (`t <= L / v`), m.
    pub peak_midspan_deflection_on_beam_m: f64,
    /// Smallest contact force over the integration steps, N (negative = tension, i.e. the
    /// wheel would lift off; not modelled).
    pub min_contact_force_n: f64,
    /// Largest |contact force| over the integration steps with the mass on the beam, N.
    pub max_contact_force_on_beam_n: f64,
    /// Bound on the mode-truncation error of the midspan deflection while the mass is on
    /// the beam, m: [`super::crossing::midspan_truncation_bound_m`] with this solution's
    /// largest contact force, the dashpot's force jumps at the road's kinks on the beam,
    /// and `w_c` twice the larger of the vehicle's and the beam's first frequency.
    pub truncation_bound_m: f64,
    /// Integrator work counters.
    pub stats: Dopri45Stats,
}

/// Where the RHS is evaluated: a time interval with no discontinuity inside.
#[derive(Debug, Clone, Copy)]
struct Segment {
    on_beam: bool,
    x_lo_m: f64,
    x_hi_m: f64,
}

/// Contact kinematics at one instant.
#[derive(Debug, Clone, Copy)]
struct Contact {
    deflection_m: f64,
    point_velocity_m_s: f64,
    elevation_m: f64,
    compression_m: f64,
    force_n: f64,
    dynamic_force_n: f64,
}

/// The coupled ODE with its work buffers.
struct Model<'a> {
    n: usize,
    speed_m_s: f64,
    modes: BeamModes,
    force_to_modal: f64,
    vehicle: SprungMassVehicle,
    weight_n: f64,
    road: Option<&'a RoadIrregularity>,
}

/// Mode-shape buffers (one per concurrent user of the model).
struct Workspace {
    sin: Vec<f64>,
    cos: Vec<f64>,
}

impl Workspace {
    fn new(n: usize) -> Self {
        Self {
            sin: vec![0.0; n],
            cos: vec![0.0; n],
        }
    }
}

impl Model<'_> {
    /// Contact kinematics; leaves the mode shapes at the mass in `ws.sin` when on the beam.
    fn contact(&self, ws: &mut Workspace, t: f64, y: &[f64], seg: Segment) -> Contact {
        let n = self.n;
        let x = self.speed_m_s * t;
        let (mut w, mut w_rate) = (0.0, 0.0);
        if seg.on_beam {
            harmonics(self.modes.wavenumber_per_m * x, &mut ws.sin, &mut ws.cos);
            let mut slope = 0.0;
            for j in 0..n {
                w += y[j] * ws.sin[j];
                w_rate += y[n + j] * ws.sin[j];
                slope += y[j] * (j + 1) as f64 * ws.cos[j];
            }
            // dw/dt + v dw/dx (the convective term).
            w_rate += self.speed_m_s * self.modes.wavenumber_per_m * slope;
        }
        let (elevation_m, road_rate) = match self.road {
            Some(road) => {
                // Evaluate the slope strictly inside the segment: one-sided at kinks.
                let span = seg.x_hi_m - seg.x_lo_m;
                let inside = x.clamp(seg.x_lo_m + 1e-9 * span, seg.x_hi_m - 1e-9 * span);
                (road.elevation_m(x), self.speed_m_s * road.slope(inside))
            }
            None => (0.0, 0.0),
        };
        let point_velocity_m_s = w_rate - road_rate;
        let compression_m = y[2 * n] - w + elevation_m;
        let compression_rate = y[2 * n + 1] - point_velocity_m_s;
        let dynamic_force_n = self.vehicle.stiffness_n_m * compression_m
            + self.vehicle.damping_n_s_m * compression_rate;
        Contact {
            deflection_m: w,
            point_velocity_m_s,
            elevation_m,
            compression_m,
            force_n: self.weight_n + dynamic_force_n,
            dynamic_force_n,
        }
    }

    fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dydt: &mut [f64], seg: Segment) {
        let n = self.n;
        let contact = self.contact(ws, t, y, seg);
        let modal_force = if seg.on_beam {
            self.force_to_modal * contact.force_n
        } else {
            0.0
        };
        for j in 0..n {
            dydt[j] = y[n + j];
            let load = if seg.on_beam {
                modal_force * ws.sin[j]
            } else {
                0.0
            };
            dydt[n + j] =
                load - self.modes.two_zeta_omega[j] * y[n + j] - self.modes.omega_sq[j] * y[j];
        }
        dydt[2 * n] = y[2 * n + 1];
        dydt[2 * n + 1] = -contact.dynamic_force_n / self.vehicle.mass_kg;
    }

    fn sample(&self, ws: &mut Workspace, t: f64, y: &[f64], seg: Segment) -> SprungMassSample {
        let n = self.n;
        let contact = self.contact(ws, t, y, seg);
        let beam_energy_j = (0..n)
            .map(|j| {
                0.5 * self.modes.modal_mass_kg
                    * (y[n + j].powi(2) + self.modes.omega_sq[j] * y[j].powi(2))
            })
            .sum();
        let vehicle_energy_j = 0.5 * self.vehicle.mass_kg * y[2 * n + 1].powi(2)
            + 0.5 * self.vehicle.stiffness_n_m * contact.compression_m.powi(2);
        SprungMassSample {
            time_s: t,
            position_m: self.speed_m_s * t,
            midspan_deflection_m: self.modes.midspan(y),
            contact_deflection_m: contact.deflection_m,
            contact_force_n: contact.force_n,
            mass_displacement_m: y[2 * n],
            mass_velocity_m_s: y[2 * n + 1],
            contact_point_velocity_m_s: contact.point_velocity_m_s,
            road_elevation_m: contact.elevation_m,
            beam_energy_j,
            vehicle_energy_j,
        }
    }
}

impl SprungMassProblem {
    /// Checks every input.
    pub fn validate(&self) -> Result<()> {
        self.beam.validate()?;
        self.vehicle.validate()?;
        require_positive("speed_m_s", self.speed_m_s)?;
        self.options.validate()?;
        Ok(())
    }

    /// Time the mass leaves the beam, `L / v`, s.
    pub fn exit_time_s(&self) -> f64 {
        self.beam.span_m / self.speed_m_s
    }

    /// Integrates from t = 0 to the last sample time and returns the response at
    /// `sample_times_s` (finite, >= 0, non-decreasing).
    pub fn solve(&self, sample_times_s: &[f64]) -> Result<SprungMassSolution> {
        self.validate()?;
        validate_sample_times(sample_times_s)?;
        let t_end = sample_times_s.last().copied().unwrap_or(0.0);
        let beam = &self.beam;
        let o = &self.options;
        let n = o.n_modes;
        let v = self.speed_m_s;
        let model = Model {
            n,
            speed_m_s: v,
            modes: BeamModes::new(beam, n, &o.damping),
            force_to_modal: 2.0 / (beam.mass_per_length_kg_m * beam.span_m),
            vehicle: self.vehicle,
            weight_n: self.vehicle.mass_kg * o.gravity_m_s2,
            road: self.road.as_ref(),
        };
        let mut rhs_ws = Workspace::new(n);
        let mut observer_ws = Workspace::new(n);

        // Breakpoints: entry, exit, road kinks; the RHS is smooth between them.
        let exit_s = self.exit_time_s();
        let mut breaks = vec![0.0, exit_s];
        if let Some(road) = &self.road {
            breaks.extend(road.kinks_m().iter().filter(|&&x| x > 0.0).map(|x| x / v));
        }
        breaks.retain(|&t| t < t_end);
        breaks.push(t_end);
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();

        // Initial state: beam at rest; the mass in static equilibrium on the road,
        // moving with it (s = 0, s' = 0).
        let mut state = vec![0.0; 2 * n + 2];
        if let Some(road) = &self.road {
            let ahead = 1e-9 * beam.span_m;
            state[2 * n] = -road.elevation_m(0.0);
            state[2 * n + 1] = -v * road.slope(ahead);
        }
        let mut atol = vec![o.atol_displacement_m; 2 * n + 2];
        atol[n..2 * n].fill(o.atol_velocity_m_s);
        atol[2 * n + 1] = o.atol_velocity_m_s;
        let mut solver = o.integrator(&model.modes, atol)?;
        let mut samples = Vec::with_capacity(sample_times_s.len());
        let mut next_sample = 0;
        let mut peak = (0.0, 0.0);
        let mut peak_on_beam = 0.0_f64;
        let mut min_force = f64::INFINITY;
        let mut max_force_on_beam = 0.0_f64;
        let mut t = 0.0;
        for window in breaks
            .windows(2)
            .chain(std::iter::once(&[t_end, t_end][..]))
        {
            let (seg_start, seg_end) = (window[0], window[1]);
            let mid_x = v * 0.5 * (seg_start + seg_end);
            let seg = Segment {
                on_beam: mid_x > 0.0 && mid_x < beam.span_m,
                x_lo_m: v * seg_start,
                x_hi_m: v * seg_end,
            };
            // Samples at this segment's start (and at t_end, in the final empty window).
            loop {
                while next_sample < sample_times_s.len() && sample_times_s[next_sample] <= t {
                    samples.push(model.sample(&mut observer_ws, t, &state, seg));
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
                    |tt: f64, y: &[f64], d: &mut [f64]| model.rhs(&mut rhs_ws, tt, y, d, seg);
                solver.advance(&mut rhs, t, target, &mut state, &mut |tt, y| {
                    let w_mid = model.modes.midspan(y);
                    if w_mid > peak.1 {
                        peak = (tt, w_mid);
                    }
                    if tt <= exit_s {
                        peak_on_beam = peak_on_beam.max(w_mid);
                    }
                    let force = model.contact(&mut observer_ws, tt, y, seg).force_n;
                    min_force = min_force.min(force);
                    if seg.on_beam {
                        max_force_on_beam = max_force_on_beam.max(force.abs());
                    }
                })?;
                t = target;
                if state.iter().any(|s| !s.is_finite()) {
                    return Err(Error::Divergence {
                        time_s: t,
                        step: solver.stats().accepted_steps,
                        quantity: "state".into(),
                        value: f64::NAN,
                        hint: "non-finite sprung-mass state".into(),
                    });
                }
            }
        }
        Ok(SprungMassSolution {
            samples,
            peak_midspan_deflection_m: peak.1,
            peak_time_s: peak.0,
            peak_midspan_deflection_on_beam_m: peak_on_beam,
            min_contact_force_n: min_force,
            max_contact_force_on_beam_n: max_force_on_beam,
            truncation_bound_m: self.truncation_bound_m(max_force_on_beam),
            stats: solver.stats(),
        })
    }

    /// The truncation bound of this crossing for a largest contact force on the beam of
    /// `max_force_n` (see [`SprungMassSolution::truncation_bound_m`]).
    fn truncation_bound_m(&self, max_force_n: f64) -> f64 {
        let beam = &self.beam;
        let v = self.speed_m_s;
        // The dashpot force jumps by c v |d(dr/dx)| where the road's slope jumps.
        let jumps_n: f64 = match &self.road {
            Some(road) => {
                let h = 1e-9 * beam.span_m;
                road.kinks_m()
                    .iter()
                    .filter(|&&x| x > 0.0 && x < beam.span_m)
                    .map(|&x| {
                        self.vehicle.damping_n_s_m
                            * v
                            * (road.slope(x + h) - road.slope(x - h)).abs()
                    })
                    .sum()
            }
            None => 0.0,
        };
        let vehicle_rad_s = (self.vehicle.stiffness_n_m / self.vehicle.mass_kg).sqrt();
        midspan_truncation_bound_m(
            beam,
            self.options.n_modes,
            v,
            2.0 * vehicle_rad_s.max(beam.omega_rad_s(1)),
            &[ContactTail {
                force_bound_n: max_force_n + jumps_n,
                stiffness_n_m: self.vehicle.stiffness_n_m,
                damping_n_s_m: self.vehicle.damping_n_s_m,
            }],
        )
    }
}
