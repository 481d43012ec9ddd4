//! What the time loop reads off the bridge each step: every sensor's point operators,
//! the deflected shape's nodes, midspan, and the support reactions. All are built once
//! per model (and again after a rebuild), so reading them allocates nothing.

use crate::physics::bridge::{
    BridgeModel, PointQuantity, ReactionOperator, ReactionState, SparseVec,
};
use crate::physics::solver::CoupledSolver;
use crate::record::{Quantities, SensorKind};
use crate::scenario::Resolved;

/// One sensor's operators on the running model.
#[derive(Debug, Clone, Default)]
struct SensorProbe {
    deflection: SparseVec,
    slope: SparseVec,
    moment: SparseVec,
    /// Bending strain per moment at the gauge, microstrain per N m.
    strain_per_moment: f64,
    /// The support a load cell sits on (index in the girder's order).
    support: Option<usize>,
    inclinometer: bool,
}

/// The operators of a run on its running model.
pub(super) struct Probes {
    sensors: Vec<SensorProbe>,
    /// Deflection at each shape node (`/truth/bridge`).
    pub(super) shape: Vec<SparseVec>,
    /// Deflection at the middle of the girder (the run summary's peak).
    pub(super) midspan: SparseVec,
    reactions: ReactionOperator,
    /// Whether a load cell reads the reactions every step (else only with the shapes).
    every_step: bool,
    /// The wheel loads on the girder this step: (x m, force N upward positive).
    loads: Vec<(f64, f64)>,
    /// The support reactions at the last [`Probes::update_reactions`] (N, upward on the
    /// girder).
    pub(super) reaction_n: Vec<f64>,
}

impl Probes {
    pub(super) fn new(model: &BridgeModel, resolved: &Resolved) -> Self {
        let supports = model.beam.girder.support_positions_m();
        // The nearest support: the scenario placed each load cell on one.
        let nearest = |x: f64| {
            (0..supports.len())
                .min_by(|&a, &b| (supports[a] - x).abs().total_cmp(&(supports[b] - x).abs()))
        };
        let sensors = resolved
            .sensors
            .iter()
            .map(|sensor| SensorProbe {
                support: (sensor.spec.kind == SensorKind::LoadCell)
                    .then(|| nearest(sensor.spec.position_m))
                    .flatten(),
                inclinometer: sensor.spec.kind == SensorKind::Inclinometer,
                ..SensorProbe::default()
            })
            .collect();
        let reactions = ReactionOperator::new(model);
        let mut probes = Self {
            sensors,
            shape: vec![SparseVec::default(); model.shape_positions_m().len()],
            midspan: SparseVec::default(),
            every_step: resolved
                .sensors
                .iter()
                .any(|s| s.spec.kind == SensorKind::LoadCell),
            loads: Vec::new(),
            reaction_n: vec![0.0; reactions.len()],
            reactions,
        };
        probes.rebuild(model, resolved);
        probes
    }

    /// Rebuilds every operator on `model` (after a model rebuild: EI moved, so the
    /// moment, strain and reaction operators and a lumped model's interpolation did).
    pub(super) fn rebuild(&mut self, model: &BridgeModel, resolved: &Resolved) {
        for (probe, sensor) in self.sensors.iter_mut().zip(&resolved.sensors) {
            let x = sensor.spec.position_m;
            model.point_operator(x, PointQuantity::Deflection, &mut probe.deflection);
            model.point_operator(x, PointQuantity::Slope, &mut probe.slope);
            model.point_operator(x, PointQuantity::Moment, &mut probe.moment);
            // Bending strain at the gauge: eps = M c / EI(x) (sagging M stretches the
            // bottom).
            probe.strain_per_moment = 1e6 * sensor.gauge_depth_m / model.beam.ei_at_n_m2(x);
        }
        for (op, &x) in self.shape.iter_mut().zip(model.shape_positions_m()) {
            model.point_operator(x, PointQuantity::Deflection, op);
        }
        model.point_operator(
            0.5 * model.length_m(),
            PointQuantity::Deflection,
            &mut self.midspan,
        );
        self.reactions = ReactionOperator::new(model);
    }

    /// Reads the support reactions of the solver's state now, when a load cell needs
    /// them every step or `shape_due` (a `/truth/bridge` message is written this step).
    pub(super) fn update_reactions(&mut self, solver: &CoupledSolver, shape_due: bool) {
        if !(self.every_step || shape_due) {
            return;
        }
        let dt_s = solver.bridge.coefficients.dt_s;
        let length_m = solver.model.length_m();
        self.loads.clear();
        for v in solver.vehicles.iter().filter(|v| v.is_active()) {
            for (j, &force) in v.contact_force_n.iter().enumerate() {
                let x = v.axle_x_m(j, solver.step, dt_s);
                if (0.0..=length_m).contains(&x) {
                    // Tyre force: compression positive, a downward load on the girder.
                    self.loads.push((x, -force));
                }
            }
        }
        let s = &solver.bridge.state;
        let state = ReactionState {
            u: &s.u,
            v: Some(&s.v),
            a: Some(&s.a),
            loads: &self.loads,
        };
        self.reactions.reactions(&state, &mut self.reaction_n);
    }

    /// Sensor `i`'s response quantities now, output signs (downward deflection: the model
    /// is upward positive).
    pub(super) fn quantities(&self, i: usize, solver: &CoupledSolver) -> Quantities {
        let probe = &self.sensors[i];
        let s = &solver.bridge.state;
        let moment_n_m = probe.moment.dot(&s.u);
        Quantities {
            displacement_m: -probe.deflection.dot(&s.u),
            velocity_m_s: -probe.deflection.dot(&s.v),
            acceleration_m_s2: -probe.deflection.dot(&s.a),
            strain_microstrain: probe.strain_per_moment * moment_n_m,
            moment_n_m,
            // Only an inclinometer's truth carries its rotation: a column of it on every
            // sensor would grow every truth stream by a sixth for nobody.
            rotation_rad: match probe.inclinometer {
                true => -probe.slope.dot(&s.u),
                false => 0.0,
            },
            reaction_n: probe.support.map_or(0.0, |k| self.reaction_n[k]),
        }
    }
}
