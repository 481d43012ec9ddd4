//! One passage of a train over a span: the time loop and the peaks EN 1991-2 6.4.6 asks
//! for (deck acceleration with the modes up to the cut-off, midspan deflection and
//! moment).

use nalgebra::DVector;

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, MomentGauge, PointQuantity, SparseVec, Wanted};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::DIVERGENCE_HINT;

/// Free vibration simulated after the last axle has left (s): the peak acceleration of a
/// resonant passage can come just after it.
const FREE_TIME_S: f64 = 0.5;

/// Deck points the acceleration is read at (fractions of the span).
const DECK_POINTS: [f64; 7] = [0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875];

/// The model and what is read from it, built once per bridge.
pub struct Deck {
    pub model: BridgeModel,
    /// The acceleration at each deck point, as weights on the kept modes' coordinates
    /// (`phi_n(x)`), and the projections `M phi_n` that give those coordinates.
    mode_at_point: Vec<Vec<f64>>,
    projections: Vec<DVector<f64>>,
    midspan_deflection: SparseVec,
    midspan_moment: MomentGauge,
    pub dt_s: f64,
    /// Kept modes and the cut-off (Hz).
    pub kept_modes: usize,
    pub cutoff_hz: f64,
    pub frequencies_hz: Vec<f64>,
}

/// What a passage gives.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Peaks {
    /// Largest |deck acceleration| over the deck points, modes up to the cut-off (m/s^2).
    pub acceleration_m_s2: f64,
    /// Largest downward midspan deflection (m).
    pub deflection_m: f64,
    /// Largest sagging midspan moment (N m).
    pub moment_n_m: f64,
    /// Smallest wheel force over its static load while on the span (1 for moving forces;
    /// 0: a wheel lifted off).
    pub min_wheel_ratio: f64,
}

impl Deck {
    /// The model with the modes up to `cutoff_hz` (at least three) for the acceleration.
    pub fn new(model: BridgeModel, cutoff_hz: f64, dt_s: f64) -> Result<Deck> {
        let n = model.n_dof();
        let modes = model.modes(Wanted::Lowest(6.min(n)))?;
        let two_pi = 2.0 * std::f64::consts::PI;
        let frequencies_hz: Vec<f64> = modes.omega_rad_s.iter().map(|w| w / two_pi).collect();
        let kept = frequencies_hz
            .iter()
            .filter(|&&f| f <= cutoff_hz * (1.0 + 1e-9))
            .count()
            .max(3.min(n));
        let mut projections = Vec::new();
        let mut mode_at_point = vec![Vec::new(); DECK_POINTS.len()];
        let mut op = SparseVec::with_capacity(n);
        for k in 0..kept {
            let shape = modes.shapes.column(k).into_owned();
            let mut m_phi = DVector::zeros(n);
            model.mass.mul_add(1.0, &shape, &mut m_phi);
            projections.push(m_phi);
            for (p, &fraction) in DECK_POINTS.iter().enumerate() {
                model.point_operator(
                    fraction * model.length_m(),
                    PointQuantity::Deflection,
                    &mut op,
                );
                mode_at_point[p].push(op.dot(&shape));
            }
        }
        let mid = 0.5 * model.length_m();
        let mut midspan_deflection = SparseVec::with_capacity(n);
        model.point_operator(mid, PointQuantity::Deflection, &mut midspan_deflection);
        let midspan_moment = MomentGauge::new(&model, mid)?;
        Ok(Deck {
            model,
            mode_at_point,
            projections,
            midspan_deflection,
            midspan_moment,
            dt_s,
            kept_modes: kept,
            cutoff_hz,
            frequencies_hz,
        })
    }

    /// Runs `train` over the span at `speed_m_s` from its first axle at the left support
    /// until its last has left, plus the free vibration.
    pub fn passage(&self, train: &VehicleDynamics, speed_m_s: f64) -> Result<Peaks> {
        let coefficients = NewmarkCoefficients::new(self.dt_s, NewmarkParams::default())?;
        let road = LevelRoad;
        let mode = SolveMode::Prefactored(Storage::Sparse);
        // Vehicle models roll on unilateral contacts: at resonance the deck throws the
        // wheels off the rail, and a wheel that would pull is lifted instead.
        let law = match train.n_dof() {
            0 => ContactLaw::Full,
            _ => ContactLaw::Unilateral,
        };
        let mut solver = CoupledSolver::new(&self.model, &road, coefficients, mode, law)?;
        solver.retire_after_m = 1.0;
        solver.add_vehicle(CoupledVehicle::new(0, train.clone(), speed_m_s, 0.0, 0));
        let stepper = Stepper::new(&self.model, DIVERGENCE_HINT);
        let span = self.model.length_m();
        let travel_m = span + train.wheelbase_m() + speed_m_s * FREE_TIME_S;
        let steps = (travel_m / (speed_m_s * self.dt_s)).ceil() as u64;
        let mut modal = vec![0.0; self.projections.len()];
        let mut peaks = Peaks {
            min_wheel_ratio: 1.0,
            ..Peaks::default()
        };
        let mut loads = Vec::new();
        for _ in 0..steps {
            stepper.advance(&mut solver)?;
            let moment_n_m = solver.gauge_moment_n_m(&self.midspan_moment, &mut loads);
            let s = &solver.bridge.state;
            for (q, r) in modal.iter_mut().zip(&self.projections) {
                *q = r.dot(&s.a);
            }
            for weights in &self.mode_at_point {
                let a: f64 = weights.iter().zip(&modal).map(|(w, q)| w * q).sum();
                peaks.acceleration_m_s2 = peaks.acceleration_m_s2.max(a.abs());
            }
            peaks.deflection_m = peaks.deflection_m.max(-self.midspan_deflection.dot(&s.u));
            peaks.moment_n_m = peaks.moment_n_m.max(moment_n_m);
            if let Some(v) = solver.vehicles.first().filter(|v| v.is_active()) {
                for (j, axle) in v.dynamics.axles.iter().enumerate() {
                    if axle.dof.is_some()
                        && self.model.on_girder(v.axle_x_m(j, solver.step, self.dt_s))
                    {
                        let ratio = v.contact_force_n[j] / axle.static_load_n;
                        peaks.min_wheel_ratio = peaks.min_wheel_ratio.min(ratio);
                    }
                }
            }
        }
        Ok(peaks)
    }
}
