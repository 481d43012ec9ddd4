//! Matrix invariants of random beams (family 3 of `properties`), for the three
//! discretizations: symmetric, positive definite M and K, positive ascending frequencies,
//! f1 within the known accuracy of the closed form; EI reduced over regions keeps all that
//! and lowers f1.

use nalgebra::DMatrix;
use proptest::prelude::*;

use bridgetwin::physics::bridge::{
    BeamProperties, BridgeModel, LumpedStiffness, ModelSpec, StiffnessRegion, Wanted,
};

use bridgetwin::studies::verify::lumped_frequency_error;

use super::{beam_strategy, config, ei_for, model_strategy};

fn check_symmetric(name: &str, m: &DMatrix<f64>) -> Result<(), TestCaseError> {
    prop_assert_eq!(m.nrows(), m.ncols(), "{} is not square", name);
    let scale = m.amax();
    prop_assert!(
        scale.is_finite() && scale > 0.0,
        "{name}: max |entry| {scale}"
    );
    for i in 0..m.nrows() {
        for j in 0..i {
            let d = (m[(i, j)] - m[(j, i)]).abs();
            prop_assert!(
                d <= 1e-10 * scale,
                "{name} not symmetric at ({i}, {j}): {} vs {}",
                m[(i, j)],
                m[(j, i)]
            );
        }
    }
    Ok(())
}

fn check_positive_definite(name: &str, m: &DMatrix<f64>) -> Result<(), TestCaseError> {
    // Symmetrize exactly (symmetry is checked separately) and factorize.
    let sym = (m + m.transpose()) * 0.5;
    prop_assert!(
        sym.cholesky().is_some(),
        "{name} ({}x{}) is not positive definite",
        m.nrows(),
        m.ncols()
    );
    Ok(())
}

/// Symmetry, definiteness and ordered positive frequencies; returns f1 (Hz).
fn check_model(model: &BridgeModel) -> Result<f64, TestCaseError> {
    let label = model.spec.label();
    check_symmetric(&format!("{label}: M"), &model.mass.to_dense())?;
    check_symmetric(&format!("{label}: K"), &model.stiffness.to_dense())?;
    if model.damping_ratio > 0.0 {
        check_symmetric(&format!("{label}: C"), &model.damping.to_dense())?;
    }
    check_positive_definite(&format!("{label}: M"), &model.mass.to_dense())?;
    check_positive_definite(&format!("{label}: K"), &model.stiffness.to_dense())?;
    let w = all_omega_rad_s(model)?;
    prop_assert_eq!(w.len(), model.n_dof(), "{}: one frequency per DOF", label);
    prop_assert!(
        w.iter().all(|x| x.is_finite() && *x > 0.0),
        "{label}: frequencies {w:?}"
    );
    prop_assert!(
        w.windows(2).all(|p| p[0] <= p[1]),
        "{label}: frequencies not ascending {w:?}"
    );
    Ok(model.frequency_hz(1))
}

/// The interval the relative f1 error of a Hermite mesh of `elements >= 2` elements with
/// consistent mass must lie in (docs/physics.md section 3).
///
/// Discretization: the eigenvalue error of the cubic interpolant is `(k h)^4 / 720` with
/// `k h = pi / elements` for mode 1, so the frequency errs by half of it, from above; the
/// next term is negative, so the leading term bounds it (measured: 0.93 to 1.0 of it for
/// 2 to 60 elements). Round-off: a backward-stable symmetric eigen-solver errs by about
/// `eps ||A||` in each eigenvalue, so f1 by `eps lambda_max / (2 lambda_1)`; the bound
/// takes `eps kappa` with `kappa = (omega_max / omega_1)^2` of the mesh (25.9 N^4) because
/// its sign and size vary with the beam's numbers (measured down to -0.04 eps kappa at 80
/// elements, where it exceeds the discretization error: that was the modal models' "f1
/// below the mesh's" of up to 1.4e-8).
fn mesh_f1_error_interval(elements: usize, kappa: f64) -> (f64, f64) {
    let leading = (std::f64::consts::PI / elements as f64).powi(4) / 1440.0;
    let round_off = f64::EPSILON * kappa;
    (-round_off, leading + round_off)
}

/// `(omega_max / omega_1)^2` of a model: the eigen-solution's condition.
fn eigen_condition(model: &BridgeModel) -> f64 {
    let w = all_omega_rad_s(model).expect("every mode of a small model");
    (w[w.len() - 1] / w[0]).powi(2)
}

/// Every natural circular frequency of the model (rad/s), ascending.
fn all_omega_rad_s(model: &BridgeModel) -> Result<Vec<f64>, TestCaseError> {
    let modes = model
        .modes(Wanted::Lowest(model.n_dof()))
        .map_err(|e| TestCaseError::fail(format!("{}: {e}", model.spec.label())))?;
    Ok(modes.omega_rad_s.iter().copied().collect())
}

fn uniform_beam(span: f64, mass: f64, f1: f64) -> BeamProperties {
    BeamProperties::simply_supported(span, ei_for(span, mass, f1), mass)
}

fn lumped_route() -> impl Strategy<Value = LumpedStiffness> {
    prop::sample::select(vec![
        LumpedStiffness::Auto,
        LumpedStiffness::Flexibility,
        LumpedStiffness::Condensation,
    ])
}

proptest! {
    #![proptest_config(config(96))]

    #[test]
    fn lumped_mass_matrices_are_symmetric_definite_with_accurate_f1(
        (span, mass, f1) in beam_strategy(),
        nodes in 1usize..=60,
        route in lumped_route(),
        zeta in 0.0f64..0.05,
    ) {
        let beam = uniform_beam(span, mass, f1);
        let spec = ModelSpec::LumpedMass { nodes, stiffness: route };
        let model = BridgeModel::build(&beam, &spec, zeta)
            .map_err(|e| TestCaseError::fail(format!("{}: {e}", spec.label())))?;
        prop_assert!(model.diagonal_mass);
        let f1_model = check_model(&model)?;
        // Every stiffness route gives the exact nodal flexibility, whose f1 error with N
        // equal masses is known in closed form (-(pi h / L)^4 / 1440 to leading order):
        // 1.5x it, plus 1e-9 for the round-off of the eigen-solution (3e-10 measured at
        // N = 100; the error itself is 5e-9 at N = 60).
        let err = (f1_model / beam.closed_form_frequency_hz(1) - 1.0).abs();
        let bound = 1.5 * lumped_frequency_error(1, nodes).abs() + 1e-9;
        prop_assert!(err <= bound, "lumped n={nodes}: f1 error {err:e} above {bound:e}");
    }

    #[test]
    fn finite_element_matrices_are_symmetric_definite_with_accurate_f1(
        (span, mass, f1) in beam_strategy(),
        elements in 1usize..=80,
        zeta in 0.0f64..0.05,
    ) {
        let beam = uniform_beam(span, mass, f1);
        let spec = ModelSpec::FiniteElement { elements };
        let model = BridgeModel::build(&beam, &spec, zeta)
            .map_err(|e| TestCaseError::fail(format!("{}: {e}", spec.label())))?;
        let f1_model = check_model(&model)?;
        if elements >= 2 {
            let err = f1_model / beam.closed_form_frequency_hz(1) - 1.0;
            let (lo, hi) = mesh_f1_error_interval(elements, eigen_condition(&model));
            prop_assert!(
                (lo..=hi).contains(&err),
                "FE n={elements}: f1 error {err:e} outside [{lo:e}, {hi:e}]"
            );
        }
    }

    #[test]
    fn modal_matrices_are_symmetric_definite_with_accurate_f1(
        (span, mass, f1) in beam_strategy(),
        modes in 1usize..=20,
        extra in proptest::option::of(0usize..=40),
        zeta in 0.0f64..0.05,
    ) {
        let beam = uniform_beam(span, mass, f1);
        let elements = extra.map(|e| 2 * modes + e);
        let spec = ModelSpec::Modal { modes, elements };
        let model = BridgeModel::build(&beam, &spec, zeta)
            .map_err(|e| TestCaseError::fail(format!("{}: {e}", spec.label())))?;
        prop_assert_eq!(model.n_dof(), modes);
        let f1_model = check_model(&model)?;
        // The modal model keeps the modes of its Hermite mesh (default 4 x modes, at least
        // 40 elements): its f1 is that mesh's to round-off, and so within the mesh's bound.
        let elements = elements.unwrap_or((4 * modes).max(40));
        let mesh = BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements }, zeta)
            .map_err(|e| TestCaseError::fail(format!("FE n={elements}: {e}")))?;
        let f1_mesh = mesh.frequency_hz(1);
        prop_assert!(
            (f1_model / f1_mesh - 1.0).abs() <= 4.0 * f64::EPSILON,
            "modal m={modes} on {elements} elements: f1 {f1_model} vs its mesh's {f1_mesh}"
        );
        let err = f1_model / beam.closed_form_frequency_hz(1) - 1.0;
        let (lo, hi) = mesh_f1_error_interval(elements, eigen_condition(&mesh));
        prop_assert!(
            (lo..=hi).contains(&err),
            "modal m={modes} on {elements} elements: f1 error {err:e} outside [{lo:e}, {hi:e}]"
        );
    }
}

fn regions_strategy(span: f64) -> impl Strategy<Value = Vec<StiffnessRegion>> {
    prop::collection::vec((0.0f64..1.0, 0.01f64..1.0, 0.3f64..=1.0), 1..=3).prop_map(
        move |regions| {
            regions
                .into_iter()
                .map(|(a, len, factor)| {
                    let start = a * span;
                    let end = ((a + len * (1.0 - a)) * span).max(start + 1e-3 * span);
                    StiffnessRegion {
                        start_m: start,
                        end_m: end.min(span),
                        ei_factor: factor,
                    }
                })
                .filter(|r| r.end_m > r.start_m)
                .collect()
        },
    )
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn reduced_ei_keeps_invariants_and_does_not_raise_f1(
        ((span, mass, f1), regions) in beam_strategy()
            .prop_flat_map(|b| (Just(b), regions_strategy(b.0))),
        model in model_strategy(),
        zeta in 0.0f64..0.05,
    ) {
        let uniform = uniform_beam(span, mass, f1);
        let mut damaged = uniform.clone();
        damaged.stiffness_regions = regions;
        let build = |beam: &BeamProperties| {
            BridgeModel::build(beam, &model, zeta)
                .map_err(|e| TestCaseError::fail(format!("{}: {e}", model.label())))
        };
        let f1_uniform = check_model(&build(&uniform)?)?;
        let f1_damaged = check_model(&build(&damaged)?)?;
        prop_assert!(
            f1_damaged <= f1_uniform * (1.0 + 1e-9),
            "{}: f1 {f1_damaged} with reduced EI above the uniform beam's {f1_uniform}",
            model.label()
        );
    }
}

// ---------------------------------------------------------------------------------------
// Regressions found by the properties above
// ---------------------------------------------------------------------------------------

/// with factor 0.3 gave the elements under both a mean EI factor of 1 + 2 (0.3 - 1) =
/// -0.4 (the mean added the factors' deviations while `ei_at_n_m2` multiplies them), so
/// the lumped model failed with "factorization of rotational stiffness block failed: not
/// positive definite". Overlapping factors multiply: the two regions are one region with
/// factor 0.09.
#[test]
fn overlapping_stiffness_regions_multiply_their_factors() {
    let region = |end_m: f64, ei_factor: f64| StiffnessRegion {
        start_m: 0.0,
        end_m,
        ei_factor,
    };
    let mut overlapping = uniform_beam(5.0, 2_000.0, 6.0);
    overlapping.stiffness_regions = vec![region(2.5, 0.3), region(2.5, 0.3)];
    let mut single = overlapping.clone();
    single.stiffness_regions = vec![region(2.5, 0.09)];
    assert_eq!(overlapping.ei_at_n_m2(1.0), single.ei_at_n_m2(1.0));
    let ei = overlapping.flexural_rigidity_n_m2;
    let mean = overlapping.mean_ei_n_m2(0.0, 5.0);
    assert!(
        (mean - 0.545 * ei).abs() <= 1e-12 * ei,
        "mean EI factor over the span {} (expected 0.545)",
        mean / ei
    );
    for spec in [
        ModelSpec::LumpedMass {
            nodes: 5,
            stiffness: LumpedStiffness::Auto,
        },
        ModelSpec::FiniteElement { elements: 10 },
        ModelSpec::Modal {
            modes: 4,
            elements: None,
        },
    ] {
        let a = BridgeModel::build(&overlapping, &spec, 0.02)
            .unwrap_or_else(|e| panic!("{}: {e}", spec.label()));
        let b = BridgeModel::build(&single, &spec, 0.02).unwrap();
        let (fa, fb) = (a.frequency_hz(1), b.frequency_hz(1));
        assert!(
            (fa - fb).abs() <= 1e-9 * fb,
            "{}: f1 {fa} vs {fb}",
            spec.label()
        );
    }
}
