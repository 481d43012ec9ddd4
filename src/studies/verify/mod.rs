//! The verification ladder: every model checked against closed forms and independent
//! solutions. `bridgetwin verify` prints these rows; `tests/suite/verification.rs` asserts them.
//!
//! Each check explains its tolerance where it is computed: the tolerance is the size of
//! the error the discretization or the time step is expected to leave, not a fudge.

mod beam_checks;
mod girder_checks;
mod harness;
mod spectra;
mod support_checks;
mod track_checks;
mod train_checks;
mod vbi;

use serde::Serialize;

pub use beam_checks::{
    daf_table, frequencies, lumped_frequency_error, manufactured_solution, moving_force,
    newmark_oscillator, static_deflection,
};
pub use girder_checks::{girder_frequencies, girder_moving_force, girder_statics};
pub use harness::{
    history_errors, manufactured_history, moving_force_history, moving_force_history_at,
    train_history, ManufacturedCase, MovingForceCase,
};
pub use support_checks::girder_supports;
pub use track_checks::track_profiles;
pub use train_checks::{train_moving_forces, train_resonance, train_vehicles};
pub use vbi::{
    approach_equilibrium, road_profiles, sine_road_response, sprung_mass_crossing, static_loads,
    suspension_limits, truck_vs_moving_forces, unilateral_contact, TRUCK_COUPLED_REFERENCE,
};

/// One row of the ladder.
#[derive(Debug, Clone, Serialize)]
pub struct CheckRow {
    /// Group ("frequencies", "moving_force", ...).
    pub group: String,
    /// What is checked.
    pub check: String,
    /// What it is compared with.
    pub reference: String,
    pub reference_value: f64,
    pub value: f64,
    /// The error measure (relative unless the check says otherwise).
    pub error: f64,
    pub tolerance: f64,
    pub pass: bool,
}

impl CheckRow {
    /// A row whose error is `|value - reference| / |reference|`.
    pub fn relative(
        group: &str,
        check: String,
        reference: &str,
        reference_value: f64,
        value: f64,
        tolerance: f64,
    ) -> Self {
        let error = ((value - reference_value) / reference_value).abs();
        Self::with_error(
            group,
            check,
            reference,
            reference_value,
            value,
            error,
            tolerance,
        )
    }

    /// A row with an error computed by the caller.
    pub fn with_error(
        group: &str,
        check: String,
        reference: &str,
        reference_value: f64,
        value: f64,
        error: f64,
        tolerance: f64,
    ) -> Self {
        CheckRow {
            group: group.to_string(),
            check,
            reference: reference.to_string(),
            reference_value,
            value,
            error,
            tolerance,
            // NaN fails.
            pass: error <= tolerance,
        }
    }
}

/// A named group of checks.
pub struct CheckGroup {
    pub name: &'static str,
    pub run: fn() -> crate::Result<Vec<CheckRow>>,
}

/// Every group of the ladder, in the order they are printed.
pub fn ladder() -> Vec<CheckGroup> {
    vec![
        CheckGroup {
            name: "frequencies",
            run: frequencies,
        },
        CheckGroup {
            name: "static",
            run: static_deflection,
        },
        CheckGroup {
            name: "newmark",
            run: newmark_oscillator,
        },
        CheckGroup {
            name: "moving_force",
            run: moving_force,
        },
        CheckGroup {
            name: "daf",
            run: daf_table,
        },
        CheckGroup {
            name: "manufactured",
            run: manufactured_solution,
        },
        CheckGroup {
            name: "girder_frequencies",
            run: girder_frequencies,
        },
        CheckGroup {
            name: "girder_statics",
            run: girder_statics,
        },
        CheckGroup {
            name: "girder_moving_force",
            run: girder_moving_force,
        },
        CheckGroup {
            name: "girder_supports",
            run: girder_supports,
        },
        CheckGroup {
            name: "vbi_equilibrium",
            run: approach_equilibrium,
        },
        CheckGroup {
            name: "vbi_static_loads",
            run: static_loads,
        },
        CheckGroup {
            name: "vbi_harmonic",
            run: sine_road_response,
        },
        CheckGroup {
            name: "vbi_sprung_mass",
            run: sprung_mass_crossing,
        },
        CheckGroup {
            name: "vbi_limits",
            run: suspension_limits,
        },
        CheckGroup {
            name: "vbi_truck",
            run: truck_vs_moving_forces,
        },
        CheckGroup {
            name: "vbi_road",
            run: road_profiles,
        },
        CheckGroup {
            name: "vbi_contact",
            run: unilateral_contact,
        },
        CheckGroup {
            name: "train_moving_forces",
            run: train_moving_forces,
        },
        CheckGroup {
            name: "train_resonance",
            run: train_resonance,
        },
        CheckGroup {
            name: "train_vehicles",
            run: train_vehicles,
        },
        CheckGroup {
            name: "track",
            run: track_profiles,
        },
    ]
}
