//! What the time loop reads off the bridge each step: every sensor's point operators,
//! the deflected shape's nodes, midspan, the support reactions, and the static effect of
//! settled supports added to them. All are built once per model (and again after a
//! rebuild), so reading them allocates nothing.

use crate::error::Result;
use crate::physics::bridge::{
    BridgeModel, GaugeFactors, GaugeState, MomentGauge, PointQuantity, ReactionOperator,
    ReactionState, SettlementField, SparseVec,
};
use crate::physics::solver::CoupledSolver;
use crate::record::{Quantities, SensorKind};
use crate::scenario::Resolved;

/// One sensor's operators on the running model.
#[derive(Debug, Clone, Default)]
struct SensorProbe {
    deflection: SparseVec,
    slope: SparseVec,
    /// The bending moment, from the equilibrium of the element the sensor sits in.
    moment: MomentGauge,
    /// Bending strain per moment at the gauge, microstrain per N m.
    strain_per_moment: f64,
    /// The support a load cell sits on (index in the girder's order).
    support: Option<usize>,
    inclinometer: bool,
    thermometer: bool,
    /// A sensor riding on a vehicle: (vehicle id, its DOF combination, upward positive).
    mount: Option<(u32, Vec<(usize, f64)>)>,
    /// The settlements' static (displacement m downward, rotation rad, moment N m) here.
    settled: (f64, f64, f64),
}

/// The supports' settlements now and their static effect.
struct Settlement {
    field: SettlementField,
    /// Downward settlement of each support (m).
    now_m: Vec<f64>,
    /// Downward displacement at each shape node (m).
    shape_m: Vec<f64>,
    /// Reaction of each support (N, upward on the girder).
    reaction_n: Vec<f64>,
}

/// The operators of a run on its running model.
pub(super) struct Probes {
    sensors: Vec<SensorProbe>,
    /// Deflection at each shape node (`/truth/bridge`).
    pub(super) shape: Vec<SparseVec>,
    /// Deflection at the middle of the longest span (the run summary's peak).
    pub(super) midspan: SparseVec,
    reactions: ReactionOperator,
    /// Whether a load cell reads the reactions every step (else only with the shapes).
    every_step: bool,
    /// The wheel loads on the girder this step: (x m, force N upward positive), read by
    /// the moment gauges and the reactions.
    loads: Vec<(f64, f64)>,
    /// The support reactions at the last [`Probes::update_loads`] (N, upward on the
    /// girder), settlements included.
    pub(super) reaction_n: Vec<f64>,
    settlement: Option<Settlement>,
    /// The deck temperature now (degC), for thermometers.
    temperature_c: f64,
}

impl Probes {
    pub(super) fn new(model: &BridgeModel, resolved: &Resolved) -> Result<Self> {
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
                    .then(|| nearest(sensor.position_m))
                    .flatten(),
                inclinometer: sensor.spec.kind == SensorKind::Inclinometer,
                thermometer: sensor.spec.kind == SensorKind::Thermometer,
                mount: sensor
                    .mount
                    .as_ref()
                    .map(|m| (m.vehicle_id, m.dofs.clone())),
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
            settlement: None,
            temperature_c: crate::physics::environment::DEFAULT_AIR_C,
        };
        probes.operators(model, resolved)?;
        Ok(probes)
    }

    /// Rebuilds every operator on `model` (after a model rebuild: EI or a spring moved,
    /// so the moment, strain and reaction operators, a lumped model's interpolation and
    /// the settlements' static field did).
    pub(super) fn rebuild(&mut self, model: &BridgeModel, resolved: &Resolved) -> Result<()> {
        self.operators(model, resolved)?;
        if let Some(now) = self.settlement.take().map(|s| s.now_m) {
            self.settle(model, resolved, &now)?;
        }
        Ok(())
    }

    fn operators(&mut self, model: &BridgeModel, resolved: &Resolved) -> Result<()> {
        let factors = GaugeFactors::new(model)?;
        for (probe, sensor) in self.sensors.iter_mut().zip(&resolved.sensors) {
            let x = sensor.position_m;
            model.point_operator(x, PointQuantity::Deflection, &mut probe.deflection);
            model.point_operator(x, PointQuantity::Slope, &mut probe.slope);
            probe.moment = MomentGauge::with_factors(model, &factors, x);
            // Bending strain at the gauge: eps = M c / EI(x) (sagging M stretches the
            // bottom).
            probe.strain_per_moment = 1e6 * sensor.gauge_depth_m / model.beam.ei_at_n_m2(x);
        }
        for (op, &x) in self.shape.iter_mut().zip(model.shape_positions_m()) {
            model.point_operator(x, PointQuantity::Deflection, op);
        }
        let middle = longest_span_middle_m(model);
        model.point_operator(middle, PointQuantity::Deflection, &mut self.midspan);
        self.reactions = ReactionOperator::new(model);
        Ok(())
    }

    /// Takes the supports' downward settlements `settlement_m` (girder order): their
    /// static effect is added to every reading from now on. Free when nothing moved.
    pub(super) fn settle(
        &mut self,
        model: &BridgeModel,
        resolved: &Resolved,
        settlement_m: &[f64],
    ) -> Result<()> {
        let unchanged = match &self.settlement {
            Some(s) => s.now_m == settlement_m,
            None => settlement_m.iter().all(|&d| d == 0.0),
        };
        if unchanged {
            return Ok(());
        }
        let field = match self.settlement.take() {
            Some(s) => s.field,
            None => SettlementField::new(model)?,
        };
        let values = field.node_values(settlement_m);
        for (probe, sensor) in self.sensors.iter_mut().zip(&resolved.sensors) {
            let x = sensor.position_m;
            probe.settled = (
                -field.read(&values, x, PointQuantity::Deflection),
                -field.read(&values, x, PointQuantity::Slope),
                field.read(&values, x, PointQuantity::Moment),
            );
        }
        let mut reaction_n = vec![0.0; self.reaction_n.len()];
        field.reactions(settlement_m, &mut reaction_n);
        self.settlement = Some(Settlement {
            shape_m: values.iter().map(|v| -v[0]).collect(),
            now_m: settlement_m.to_vec(),
            reaction_n,
            field,
        });
        Ok(())
    }

    /// The deck temperature the thermometers read from now on (degC).
    pub(super) fn set_temperature(&mut self, structure_c: f64) {
        self.temperature_c = structure_c;
    }

    /// Takes the loads the solver's last step put on the girder (every step: the moment
    /// gauges read them), and the support reactions of its state, when a load cell needs
    /// them every step or `shape_due` (a `/truth/bridge` message is written this step).
    pub(super) fn update_loads(&mut self, solver: &CoupledSolver, shape_due: bool) {
        solver.deck_loads(&mut self.loads);
        if !(self.every_step || shape_due) {
            return;
        }
        let s = &solver.bridge.state;
        let state = ReactionState {
            u: &s.u,
            v: Some(&s.v),
            a: Some(&s.a),
            loads: &self.loads,
        };
        self.reactions.reactions(&state, &mut self.reaction_n);
        if let Some(settled) = &self.settlement {
            for (r, s) in self.reaction_n.iter_mut().zip(&settled.reaction_n) {
                *r += s;
            }
        }
    }

    /// The deflected shape now (m, downward positive at each shape node).
    pub(super) fn deflected_shape(&self, solver: &CoupledSolver) -> Vec<f64> {
        let u = &solver.bridge.state.u;
        let dynamic = self.shape.iter().map(|op| -op.dot(u));
        match &self.settlement {
            Some(s) => dynamic.zip(&s.shape_m).map(|(d, s)| d + s).collect(),
            None => dynamic.collect(),
        }
    }

    /// Sensor `i`'s response quantities now, output signs (downward deflection: the model
    /// is upward positive).
    pub(super) fn quantities(&self, i: usize, solver: &CoupledSolver) -> Quantities {
        let probe = &self.sensors[i];
        if let Some((vehicle_id, dofs)) = &probe.mount {
            return vehicle_quantities(*vehicle_id, dofs, solver);
        }
        let s = &solver.bridge.state;
        let (settled_m, settled_rad, settled_n_m) = probe.settled;
        let gauge = GaugeState {
            u: &s.u,
            v: &s.v,
            a: &s.a,
            loads: &self.loads,
        };
        let moment_n_m = probe.moment.read(&gauge) + settled_n_m;
        Quantities {
            displacement_m: -probe.deflection.dot(&s.u) + settled_m,
            velocity_m_s: -probe.deflection.dot(&s.v),
            acceleration_m_s2: -probe.deflection.dot(&s.a),
            strain_microstrain: probe.strain_per_moment * moment_n_m,
            moment_n_m,
            // Only an inclinometer's truth carries its rotation: a column of it on every
            // sensor would grow every truth stream by a sixth for nobody.
            rotation_rad: match probe.inclinometer {
                true => -probe.slope.dot(&s.u) + settled_rad,
                false => 0.0,
            },
            reaction_n: probe.support.map_or(0.0, |k| self.reaction_n[k]),
            temperature_c: match probe.thermometer {
                true => self.temperature_c,
                false => 0.0,
            },
        }
    }
}

/// A vehicle sensor's quantities now, downward positive as the bridge's: the motion of
/// its mount from static equilibrium; zero while the vehicle is not on the modelled road
/// (before it appears, after it has left).
fn vehicle_quantities(
    vehicle_id: u32,
    dofs: &[(usize, f64)],
    solver: &CoupledSolver,
) -> Quantities {
    let Some(v) = solver
        .vehicles
        .iter()
        .find(|v| v.id == vehicle_id && v.is_active())
    else {
        return Quantities::default();
    };
    let read = |x: &nalgebra::DVector<f64>| -dofs.iter().map(|&(d, c)| c * x[d]).sum::<f64>();
    Quantities {
        displacement_m: read(&v.state.u),
        velocity_m_s: read(&v.state.v),
        acceleration_m_s2: read(&v.state.a),
        ..Quantities::default()
    }
}

/// The middle of the girder's longest span (the middle of the girder for one span).
fn longest_span_middle_m(model: &BridgeModel) -> f64 {
    let supports = model.beam.girder.support_positions_m();
    supports
        .windows(2)
        .max_by(|a, b| (a[1] - a[0]).total_cmp(&(b[1] - b[0])))
        .map_or(0.5 * model.length_m(), |w| 0.5 * (w[0] + w[1]))
}
