//! Stepping a coupled run with its divergence check.
//!
//! Every time loop over a [`CoupledSolver`] (the simulation, the verification ladder, the
//! studies) stops on the same two signs of a diverged integration, with the same
//! [`Error::Divergence`]: a non-finite bridge state, checked every step (one NaN poisons
//! every later step, and the step it appeared at is what the user needs), and a runaway
//! deflection, checked every [`RUNAWAY_CHECK_STRIDE`] steps (an unstable mode grows by
//! orders of magnitude over that many steps, so the sparser check finds it as surely and
//! skips most of the read-back).

use super::coupled::CoupledSolver;
use super::newmark::NewmarkCoefficients;
use crate::error::{Error, Result};
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec};

/// Steps between runaway checks (the non-finite check runs every step).
pub const RUNAWAY_CHECK_STRIDE: u64 = 32;

/// A deflection of this fraction of the span is far beyond any linear response.
const RUNAWAY_SPAN_FRACTION: f64 = 0.1;

/// What to try when a run from a scenario diverges, the likeliest cause first: a Newmark
/// rule that is only conditionally stable, then the step, the parameters and the contact.
pub fn divergence_hint(coefficients: &NewmarkCoefficients) -> String {
    let (gamma, beta) = (coefficients.gamma, coefficients.beta);
    let mut hint = String::new();
    if 2.0 * beta < gamma {
        hint.push_str(&format!(
            "solver.newmark (gamma = {gamma}, beta = {beta}) is only conditionally stable: use \
             beta >= gamma / 2 (the default 0.5, 0.25 is unconditionally stable); "
        ));
    }
    hint.push_str(
        "reduce solver.dt_s, check vehicle and bridge parameters, or use \
         solver.contact = \"unilateral\"",
    );
    hint
}

/// Stops the run on a non-finite or runaway bridge state after the solver's last step
/// (`solver.step`, at `solver.time_s()`). The state may be modal coordinates, so the
/// runaway test reads the physical deflection through `deflection_ops` (one operator per
/// read-back point, e.g. the shape nodes).
pub fn check_state(solver: &CoupledSolver, deflection_ops: &[SparseVec], hint: &str) -> Result<()> {
    let u = &solver.bridge.state.u;
    let step = solver.step;
    let diverged = |quantity: &str, value: f64| Error::Divergence {
        time_s: solver.time_s(),
        step,
        quantity: quantity.into(),
        value,
        hint: hint.into(),
    };
    if let Some(bad) = u.iter().find(|v| !v.is_finite()) {
        return Err(diverged("bridge state (non-finite)", *bad));
    }
    if step.is_multiple_of(RUNAWAY_CHECK_STRIDE) {
        let worst = deflection_ops
            .iter()
            .fold(0.0f64, |a, op| a.max(op.dot(u).abs()));
        if worst > RUNAWAY_SPAN_FRACTION * solver.model.length_m() {
            return Err(diverged("bridge deflection (m)", worst));
        }
    }
    Ok(())
}

/// Advances a [`CoupledSolver`] one step at a time and checks each new state
/// ([`check_state`] on the deflection at the model's shape nodes). For loops whose model
/// does not change; a loop that rebuilds the model calls [`check_state`] with its own
/// operators.
#[derive(Debug, Clone)]
pub struct Stepper {
    deflection_ops: Vec<SparseVec>,
    hint: String,
}

impl Stepper {
    /// A stepper for runs on `model`; `hint` ends the divergence message (what to try).
    pub fn new(model: &BridgeModel, hint: impl Into<String>) -> Self {
        let deflection_ops = model
            .shape_positions_m()
            .iter()
            .map(|&x| {
                let mut op = SparseVec::default();
                model.point_operator(x, PointQuantity::Deflection, &mut op);
                op
            })
            .collect();
        Stepper {
            deflection_ops,
            hint: hint.into(),
        }
    }

    /// Advances `solver` one step, then checks its state.
    pub fn advance(&self, solver: &mut CoupledSolver) -> Result<()> {
        solver.advance()?;
        check_state(solver, &self.deflection_ops, &self.hint)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::bridge::{BeamProperties, ModelSpec};
    use crate::physics::road::LevelRoad;
    use crate::physics::solver::{ContactLaw, NewmarkParams, SolveMode, Storage};

    fn solver(model: &BridgeModel) -> CoupledSolver<'_> {
        let coefficients = NewmarkCoefficients::new(1e-3, NewmarkParams::default()).unwrap();
        CoupledSolver::new(
            model,
            &LevelRoad,
            coefficients,
            SolveMode::Prefactored(Storage::Dense),
            ContactLaw::Full,
        )
        .unwrap()
    }

    fn model(spec: ModelSpec) -> BridgeModel {
        BridgeModel::build(&BeamProperties::paper_default(), &spec, 0.02).unwrap()
    }

    #[test]
    fn a_non_finite_state_stops_at_its_step() {
        let model = model(ModelSpec::FiniteElement { elements: 10 });
        let mut s = solver(&model);
        let stepper = Stepper::new(&model, "try less");
        for _ in 0..3 {
            stepper.advance(&mut s).unwrap();
        }
        s.bridge.state.u[4] = f64::NAN;
        let err = stepper.advance(&mut s).unwrap_err().to_string();
        assert!(
            err.starts_with(
                "divergence at t = 0.004 s (step 4): bridge state (non-finite) = NaN; try less"
            ),
            "{err}"
        );
    }

    #[test]
    fn a_runaway_deflection_stops_at_the_next_check() {
        // Modal coordinates are not deflections: a modal state of 1.0 is a deflection of
        // phi_1(L/2) = sqrt(2 / (m L)) = 2.4e-3 m, far from a runaway, while a physical
        // deflection of 0.2 L is one. The check reads the deflection, so only the second
        // state stops the run, at the first multiple of the stride.
        let model = model(ModelSpec::Modal {
            modes: 4,
            elements: None,
        });
        let mut s = solver(&model);
        let stepper = Stepper::new(&model, "hint");
        s.bridge.state.u[0] = 1.0;
        for _ in 0..RUNAWAY_CHECK_STRIDE {
            stepper.advance(&mut s).unwrap();
        }
        let phi_mid = (2.0f64 / (model.beam.mass_per_length_kg_m * model.length_m())).sqrt();
        s.bridge.state.u[0] = 0.2 * model.length_m() / phi_mid;
        s.bridge.state.v.fill(0.0);
        s.bridge.state.a.fill(0.0);
        let mut stopped = None;
        for _ in 0..RUNAWAY_CHECK_STRIDE {
            if let Err(e) = stepper.advance(&mut s) {
                stopped = Some((s.step, e.to_string()));
                break;
            }
        }
        let (step, err) = stopped.expect("the runaway was not reported");
        assert_eq!(step, 2 * RUNAWAY_CHECK_STRIDE);
        assert!(err.contains("bridge deflection (m) = "), "{err}");
    }

    #[test]
    fn the_hint_names_a_conditionally_stable_rule_first() {
        let unstable = NewmarkParams {
            gamma: 0.5,
            beta: 0.1,
        };
        let hint = divergence_hint(&NewmarkCoefficients::new(1e-3, unstable).unwrap());
        assert!(hint
            .starts_with("solver.newmark (gamma = 0.5, beta = 0.1) is only conditionally stable"));
        let stable =
            divergence_hint(&NewmarkCoefficients::new(1e-3, NewmarkParams::default()).unwrap());
        assert!(stable.starts_with("reduce solver.dt_s"), "{stable}");
    }
}
