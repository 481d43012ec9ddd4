//! Big models: the modes of models above the dense
//! eigen-solution's size come from the band by Sturm bisection and inverse iteration.
//! Checked against the dense solution of the same matrices (moderate n, where the dense
//! solution's own round-off is small enough to be a reference), against closed forms
//! (any n), and the memory estimate against the limit.

use nalgebra::DMatrix;

use bridgetwin::physics::bridge::{
    generalized_modes, BeamProperties, BridgeModel, LumpedStiffness, ModelSpec, Wanted,
    DENSE_EIGEN_MAX_DOF,
};
use bridgetwin::physics::linalg::{lowest_eigenpairs, SymMatrix};
use bridgetwin::studies::verify::lumped_frequency_error;

fn band(m: &SymMatrix) -> bridgetwin::physics::linalg::SymBand {
    match m {
        SymMatrix::Band(b) => b.clone(),
        other => panic!("expected a band matrix, got {other:?}"),
    }
}

#[test]
fn banded_modes_of_a_finite_element_model_equal_the_dense_ones() {
    // 40 elements (80 DOFs): the dense solution errs by about eps lambda_max / lambda_j
    // (at most 1.5e-8 for mode 1, measured 0.04 of that), so 1e-9 relative is a test of
    // the banded route and not of the reference's round-off.
    let beam = BeamProperties::paper_default();
    let model =
        BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 40 }, 0.02).unwrap();
    let (k, m) = (model.stiffness.to_dense(), model.mass.to_dense());
    let dense = generalized_modes(&k, &m).unwrap();
    let (values, vectors) =
        lowest_eigenpairs(&band(&model.stiffness), &band(&model.mass), 10).unwrap();
    for (j, lambda) in values.iter().enumerate() {
        let omega = lambda.sqrt();
        let rel = (omega - dense.omega_rad_s[j]).abs() / dense.omega_rad_s[j];
        assert!(
            rel < 1e-9,
            "mode {}: relative frequency error {rel:e}",
            j + 1
        );
        let mac = model.mass.modal_assurance(
            &vectors.column(j).into_owned(),
            &dense.shapes.column(j).into_owned(),
        );
        assert!(mac > 0.999, "mode {}: MAC {mac}", j + 1);
        assert!(
            mac > 1.0 - 1e-9,
            "mode {}: MAC {mac} (1 - {:e})",
            j + 1,
            1.0 - mac
        );
    }
}

#[test]
fn large_finite_element_and_modal_models_meet_the_closed_form() {
    // Above the dense threshold the model's own modes come from the band. The Hermite
    // mesh's frequency error is (j pi / N)^4 / 1440 from above (docs/physics.md section
    // 3); round-off adds `c eps kappa` with `kappa = 25.9 N^4` as for any solver of the
    // assembled matrices. Measured c for the Sturm counts: 2e-4 (150 elements), 9e-4
    // (1000), 1.7e-4 (5000), 2.4e-4 (modal, 800); the dense solution's is 0.04. The bound
    // takes c = 2e-3.
    let beam = BeamProperties::paper_default();
    for elements in [150, 1000, 5000] {
        let model =
            BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements }, 0.02).unwrap();
        assert!(model.n_dof() > DENSE_EIGEN_MAX_DOF);
        for j in 1..=5 {
            let err = model.frequency_hz(j) / beam.closed_form_frequency_hz(j) - 1.0;
            let leading = (j as f64 * std::f64::consts::PI / elements as f64).powi(4) / 1440.0;
            let round_off = round_off(elements);
            assert!(
                (-round_off..=leading + round_off).contains(&err),
                "FE {elements}, mode {j}: error {err:e} outside +-{round_off:e} of [0, {leading:e}]"
            );
        }
    }
    // A modal model of 200 modes on 800 elements: its frequencies are its mesh's.
    let modal = BridgeModel::build(
        &beam,
        &ModelSpec::Modal {
            modes: 200,
            elements: None,
        },
        0.02,
    )
    .unwrap();
    assert_eq!(modal.n_dof(), 200);
    assert_eq!(
        modal.omega_rad_s.len(),
        200,
        "a modal model reports every kept mode"
    );
    for j in [1, 2, 3, 50, 200] {
        let f_exact = beam.closed_form_frequency_hz(j);
        let f = modal.frequency_hz(j);
        let leading = (j as f64 * std::f64::consts::PI / 800.0).powi(4) / 1440.0;
        let err = f / f_exact - 1.0;
        let round_off = round_off(800);
        assert!(
            (-round_off..=leading + round_off).contains(&err),
            "modal mode {j}: error {err:e} outside +-{round_off:e} of [0, {leading:e}]"
        );
    }
}

/// Round-off allowance of the banded frequencies of an `elements` mesh (see above).
fn round_off(elements: usize) -> f64 {
    2e-3 * f64::EPSILON * 25.9 * (elements as f64).powi(4)
}

#[test]
fn large_lumped_models_meet_the_exact_lumped_frequencies() {
    // A lumped model's frequencies are known in closed form for any N
    // (`lumped_frequency_error`); above the dense threshold they come from the band of the
    // condensation mesh, whose condensed stiffness equals the flexibility route's. Their
    // round-off grows as eps kappa with kappa = (2 (N + 1) / pi)^4 (measured 0.017 of it
    // at 300 masses, 0.13 at 800); the bound takes half of it.
    let beam = BeamProperties::paper_default();
    for nodes in [300, 800] {
        for route in [LumpedStiffness::Flexibility, LumpedStiffness::Condensation] {
            let spec = ModelSpec::LumpedMass {
                nodes,
                stiffness: route,
            };
            let model = BridgeModel::build(&beam, &spec, 0.02).unwrap();
            for j in 1..=5 {
                let expected =
                    beam.closed_form_frequency_hz(j) * (1.0 + lumped_frequency_error(j, nodes));
                let rel = (model.frequency_hz(j) - expected).abs() / expected;
                let kappa = (2.0 * (nodes as f64 + 1.0) / std::f64::consts::PI).powi(4);
                let bound = 0.5 * f64::EPSILON * kappa;
                assert!(
                    rel < bound,
                    "lumped {nodes} {route:?} mode {j}: {rel:e} above {bound:e}"
                );
            }
        }
    }
}

#[test]
fn shapes_are_mass_normalized_and_ambient_counts_follow_the_cutoff() {
    let beam = BeamProperties::paper_default();
    let model =
        BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 400 }, 0.02).unwrap();
    // Every mode below 100 Hz: f_j = 3.78 j^2 Hz, so j = 1..5.
    let modes = model
        .modes(Wanted::Below(2.0 * std::f64::consts::PI * 100.0))
        .unwrap();
    assert_eq!(modes.omega_rad_s.len(), 5);
    let m = model.mass.to_dense();
    // M-orthonormal to the accuracy of the vectors (measured 1.1e-8 at 400 elements).
    let gram = modes.shapes.transpose() * &m * &modes.shapes;
    let off = (gram - DMatrix::identity(5, 5)).amax();
    assert!(off < 1e-7, "M-orthonormality off by {off:e}");
    assert!(model.modes(Wanted::Lowest(model.n_dof() + 1)).is_err());
}

#[test]
fn the_memory_estimate_bounds_models_before_they_are_built() {
    let fe = ModelSpec::FiniteElement { elements: 20_000 };
    assert!(fe.memory_estimate_bytes() < 200 << 20, "FE is O(n)");
    let modal = ModelSpec::Modal {
        modes: 5000,
        elements: Some(20_000),
    };
    let err = modal.validate("bridge.model").unwrap_err().to_string();
    assert!(
        err.contains("bridge.model.modes = 5000") && err.contains("limit of 2.0 GiB"),
        "{err}"
    );
    // Lumped: dense, n^2.
    let small = ModelSpec::LumpedMass {
        nodes: 1000,
        stiffness: LumpedStiffness::Auto,
    };
    let large = ModelSpec::LumpedMass {
        nodes: 2000,
        stiffness: LumpedStiffness::Auto,
    };
    let ratio = large.memory_estimate_bytes() as f64 / small.memory_estimate_bytes() as f64;
    assert!((3.9..4.1).contains(&ratio), "ratio {ratio}");
}

/// The largest mesh the scenario format accepts builds, factorizes and runs (through the
/// binary, as a user would run it). Round-off sets that limit (the stiffness's condition
/// number grows as about 26 N^4): 30 000 and 100 000 elements, once accepted, failed in
/// the band Cholesky as "not positive definite".
#[test]
fn the_largest_accepted_mesh_builds_and_runs() {
    let default = bridgetwin::scenario::DEFAULT_SCENARIO_TOML;
    let line = "model = { kind = \"finite_element\", elements = 50 }";
    assert!(
        default.contains(line),
        "the default scenario changed its model line"
    );
    let largest = bridgetwin::physics::bridge::MAX_ELEMENTS;
    let toml = default.replace(
        line,
        &format!("model = {{ kind = \"finite_element\", elements = {largest} }}"),
    );
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("largest.toml");
    std::fs::write(&scenario, toml).unwrap();
    crate::common::simulate_file(Some(&scenario), &dir.path().join("run.mcap"), 0.001);
}
