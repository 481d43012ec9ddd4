//! Model-level tests: frequencies, point operators and statics against closed forms.

use nalgebra::DVector;

use super::*;

fn paper() -> BeamProperties {
    BeamProperties::paper_default()
}

fn static_solve(model: &BridgeModel, load: &DVector<f64>) -> DVector<f64> {
    model.stiffness.to_dense().cholesky().unwrap().solve(load)
}

#[test]
fn frequencies_converge_to_closed_form() {
    let beam = paper();
    // docs/physics.md: N = 7 lumped masses already give f1..f3 within 0.2 %; FE converges
    // from above at O(h^4), below (n pi h / L)^4 / 720: 6.8e-5 for mode 3 at 20 elements.
    let lumped = BridgeModel::build(
        &beam,
        &ModelSpec::LumpedMass {
            nodes: 7,
            stiffness: LumpedStiffness::Auto,
        },
        0.02,
    )
    .unwrap();
    let fe = BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 20 }, 0.02).unwrap();
    for n in 1..=3 {
        let exact = beam.closed_form_frequency_hz(n);
        let el = (lumped.frequency_hz(n) - exact) / exact;
        let ef = (fe.frequency_hz(n) - exact) / exact;
        assert!(el < 0.0 && el > -2e-3, "lumped mode {n}: {el:e}");
        let bound = (n as f64 * std::f64::consts::PI / 20.0).powi(4) / 720.0;
        assert!(ef >= 0.0 && ef < bound, "FE mode {n}: {ef:e}");
    }
}

#[test]
fn lumped_point_operator_equals_k_times_flexibility_column() {
    // h(x) = K f(x): the statically consistent load of a force at x (docs/physics.md 2).
    let beam = paper();
    let n = 9;
    let model = BridgeModel::build(
        &beam,
        &ModelSpec::LumpedMass {
            nodes: n,
            stiffness: LumpedStiffness::Auto,
        },
        0.0,
    )
    .unwrap();
    let xs = mass_positions_m(beam.length_m(), n);
    let mut op = SparseVec::default();
    for x in [0.7, 4.1, 15.0, 22.22, 29.9] {
        model.point_operator(x, PointQuantity::Deflection, &mut op);
        let f = DVector::from_iterator(
            n,
            xs.iter()
                .map(|&xi| unit_load_deflection_m_per_n(&beam, xi, x)),
        );
        let expected = model.stiffness.mul(&f);
        let got = op.to_dense(n);
        assert!(
            (&got - &expected).norm() < 1e-9 * expected.norm(),
            "x = {x}"
        );
    }
}

#[test]
fn static_deflection_is_nodally_exact_for_every_model() {
    // Hermite elements with the consistent point load give exact nodal displacements,
    // and with the load on a node the interpolated field is exact everywhere (no load
    // inside any element): only round-off remains.
    let beam = paper();
    let p_n = -100_000.0;
    for spec in [
        ModelSpec::LumpedMass {
            nodes: 10,
            stiffness: LumpedStiffness::Auto,
        },
        ModelSpec::LumpedMass {
            nodes: 10,
            stiffness: LumpedStiffness::Condensation,
        },
        ModelSpec::FiniteElement { elements: 7 },
    ] {
        let model = BridgeModel::build(&beam, &spec, 0.0).unwrap();
        let nodes = model.shape_positions_m().to_vec();
        let (node_a, node_b) = (nodes[3], nodes[5]);
        let between = 0.5 * (nodes[4] + nodes[5]);
        // (load position, read position): load on a node read anywhere; load anywhere read on a node.
        for (a, x) in [
            (node_a, node_a),
            (node_a, 13.7),
            (node_b, 2.2),
            (between, node_a),
            (between, node_b),
        ] {
            let mut op = SparseVec::default();
            model.point_operator(a, PointQuantity::Deflection, &mut op);
            let u = static_solve(&model, &op.to_dense(model.n_dof()).scale(p_n));
            let w = model.read(x, PointQuantity::Deflection, &u);
            let exact = p_n * unit_load_deflection_m_per_n(&beam, x, a);
            assert!(
                (w - exact).abs() < 1e-8 * exact.abs(),
                "{spec:?} a={a} x={x}: {w} vs {exact}"
            );
        }
        // Under a load between nodes the read-back is the discretized f(x)^T K f(x): it
        // converges with the mesh; 10 masses or 7 elements leave < 0.1 %.
        let mut op = SparseVec::default();
        model.point_operator(between, PointQuantity::Deflection, &mut op);
        let u = static_solve(&model, &op.to_dense(model.n_dof()).scale(p_n));
        let w = model.read(between, PointQuantity::Deflection, &u);
        let exact = p_n * unit_load_deflection_m_per_n(&beam, between, between);
        assert!(
            (w - exact).abs() < 1e-3 * exact.abs(),
            "{spec:?}: {w} vs {exact}"
        );
    }
}

#[test]
fn moment_read_back_matches_statics() {
    // Load at a mass position: the lumped model's moment is exact (piecewise-linear
    // moment between nodal loads). M(x) = -P x (L - a) / L for x <= a (upward P).
    let beam = paper();
    let model = BridgeModel::build(
        &beam,
        &ModelSpec::LumpedMass {
            nodes: 11,
            stiffness: LumpedStiffness::Auto,
        },
        0.0,
    )
    .unwrap();
    let a = 15.0;
    let p_n = -1.0e5;
    let mut op = SparseVec::default();
    model.point_operator(a, PointQuantity::Deflection, &mut op);
    let u = static_solve(&model, &op.to_dense(model.n_dof()).scale(p_n));
    for x in [2.0, 10.0, 15.0, 24.0] {
        let m = model.read(x, PointQuantity::Moment, &u);
        let l = beam.length_m();
        let exact = if x <= a {
            -p_n * x * (l - a) / l
        } else {
            -p_n * a * (l - x) / l
        };
        assert!(
            (m - exact).abs() < 1e-6 * exact.abs(),
            "x={x}: {m} vs {exact}"
        );
    }
}

#[test]
fn modal_model_reproduces_fe_frequencies_and_static_midspan() {
    let beam = paper();
    let modal = BridgeModel::build(
        &beam,
        &ModelSpec::Modal {
            modes: 20,
            elements: None,
        },
        0.02,
    )
    .unwrap();
    assert_eq!(modal.n_dof(), 20);
    for n in 1..=3 {
        let exact = beam.closed_form_frequency_hz(n);
        assert!((modal.frequency_hz(n) - exact).abs() < 1e-5 * exact);
    }
    // Static midspan deflection from 20 modes (odd terms decay as 1/n^4): within 0.02 %.
    let mut op = SparseVec::default();
    modal.point_operator(15.0, PointQuantity::Deflection, &mut op);
    let u = static_solve(&modal, &op.to_dense(20).scale(-1.0));
    let w = modal.read(15.0, PointQuantity::Deflection, &u);
    let exact = -beam.length_m().powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
    assert!((w - exact).abs() < 2e-4 * exact.abs(), "{w} vs {exact}");
}

#[test]
fn rayleigh_damping_gives_the_ratio_on_modes_1_and_2() {
    let beam = paper();
    let model =
        BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 20 }, 0.03).unwrap();
    let r = model.rayleigh;
    assert!((r.ratio_at(model.omega_rad_s[0]) - 0.03).abs() < 1e-14);
    assert!((r.ratio_at(model.omega_rad_s[1]) - 0.03).abs() < 1e-14);
}

#[test]
fn bad_inputs_name_field_and_value() {
    let beam = paper();
    let cases: Vec<(BeamProperties, ModelSpec, f64, &str)> = vec![
        (
            BeamProperties {
                girder: Girder::simply_supported(0.0),
                ..paper()
            },
            ModelSpec::FiniteElement { elements: 10 },
            0.02,
            "bridge.spans_m.0",
        ),
        (
            BeamProperties {
                flexural_rigidity_n_m2: -1.0,
                ..paper()
            },
            ModelSpec::FiniteElement { elements: 10 },
            0.02,
            "bridge.flexural_rigidity_n_m2",
        ),
        (
            BeamProperties {
                mass_per_length_kg_m: f64::INFINITY,
                ..paper()
            },
            ModelSpec::FiniteElement { elements: 10 },
            0.02,
            "bridge.mass_per_length_kg_m",
        ),
        (
            beam.clone(),
            ModelSpec::FiniteElement { elements: 0 },
            0.02,
            "bridge.model.elements",
        ),
        (
            beam.clone(),
            ModelSpec::LumpedMass {
                nodes: 0,
                stiffness: LumpedStiffness::Auto,
            },
            0.02,
            "bridge.model.nodes",
        ),
        (
            beam.clone(),
            ModelSpec::FiniteElement { elements: 10 },
            1.0,
            "bridge.damping_ratio",
        ),
        (
            beam.clone(),
            ModelSpec::FiniteElement { elements: 10 },
            -0.1,
            "bridge.damping_ratio",
        ),
        (
            beam.clone(),
            ModelSpec::FiniteElement { elements: 10 },
            f64::NAN,
            "bridge.damping_ratio",
        ),
    ];
    for (b, spec, zeta, field) in cases {
        let msg = BridgeModel::build(&b, &spec, zeta).unwrap_err().to_string();
        assert!(msg.starts_with(field), "{msg}");
    }
}

#[test]
fn damaged_region_lowers_f1_and_flexibility_route_refuses_it() {
    let mut beam = paper();
    beam.stiffness_regions.push(StiffnessRegion {
        start_m: 14.0,
        end_m: 16.0,
        ei_factor: 0.5,
    });
    let spec = ModelSpec::LumpedMass {
        nodes: 29,
        stiffness: LumpedStiffness::Auto,
    };
    let damaged = BridgeModel::build(&beam, &spec, 0.02).unwrap();
    let fe = BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 30 }, 0.02).unwrap();
    let intact = BridgeModel::build(&paper(), &spec, 0.02).unwrap();
    assert!(damaged.frequency_hz(1) < intact.frequency_hz(1));
    // Lumped (condensed) and FE agree on the damaged f1 to the lumped model's
    // discretization error (0.2 % at N = 29 is generous; it is ~0.02 %).
    assert!((damaged.frequency_hz(1) - fe.frequency_hz(1)).abs() < 2e-3 * fe.frequency_hz(1));
    let forced = ModelSpec::LumpedMass {
        nodes: 29,
        stiffness: LumpedStiffness::Flexibility,
    };
    assert!(BridgeModel::build(&beam, &forced, 0.02).is_err());
}
