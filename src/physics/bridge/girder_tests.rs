//! Continuous girders against closed forms: frequencies of the classic support cases,
//! Clapeyron's support moment, the force method against the finite elements, and the
//! lumped model on three spans.

use nalgebra::DVector;

use super::*;

const EI: f64 = 5.629e10;
const MASS: f64 = 12_000.0;

fn girder_beam(spans: &[f64], supports: &[Support]) -> BeamProperties {
    BeamProperties {
        girder: Girder {
            spans_m: spans.to_vec(),
            supports: supports.to_vec(),
            overhang_left_m: 0.0,
            overhang_right_m: 0.0,
        },
        ..BeamProperties::paper_default()
    }
}

/// omega for a wavenumber `lambda / l` of the uniform section (Hz).
fn frequency_hz(lambda: f64, l: f64) -> f64 {
    (lambda / l).powi(2) * (EI / MASS).sqrt() / (2.0 * std::f64::consts::PI)
}

fn fe(beam: &BeamProperties, elements: usize) -> BridgeModel {
    BridgeModel::build(beam, &ModelSpec::FiniteElement { elements }, 0.0).unwrap()
}

/// Static FE deflection under a downward unit load at `a_m` (upward-positive state).
fn static_state(model: &BridgeModel, a_m: f64) -> DVector<f64> {
    let mut op = SparseVec::default();
    model.point_operator(a_m, PointQuantity::Deflection, &mut op);
    let mut load = DVector::zeros(model.n_dof());
    op.add_scaled_to(-1.0, &mut load);
    model.stiffness.to_dense().cholesky().unwrap().solve(&load)
}

/// Frequencies of the classic cases (Blevins 1979, table 8-1): FE with 100 elements per
/// span converges from above at O(h^4) (about 1e-9 here), to the round-off of the fine
/// mesh's eigen-solution (1e-9 either side); 1e-6 relative bounds the first two modes.
#[test]
fn frequencies_match_the_classic_support_cases() {
    let l = 30.0;
    let two_spans = girder_beam(
        &[l, l],
        &[Support::Pinned, Support::Roller, Support::Roller],
    );
    let model = fe(&two_spans, 200);
    let cases = [
        (model.frequency_hz(1), frequency_hz(std::f64::consts::PI, l)),
        (
            model.frequency_hz(2),
            frequency_hz(3.926_602_312_047_919, l),
        ),
    ];
    let clamped = fe(&girder_beam(&[l], &[Support::Fixed, Support::Fixed]), 100);
    let cantilever = fe(
        &BeamProperties {
            girder: Girder {
                spans_m: vec![],
                supports: vec![Support::Fixed],
                overhang_left_m: 0.0,
                overhang_right_m: l,
            },
            ..BeamProperties::paper_default()
        },
        100,
    );
    let more = [
        (
            clamped.frequency_hz(1),
            frequency_hz(4.730_040_744_862_704, l),
        ),
        (
            cantilever.frequency_hz(1),
            frequency_hz(1.875_104_068_711_961, l),
        ),
    ];
    for (i, (numerical, exact)) in cases.iter().chain(&more).enumerate() {
        let error = numerical / exact - 1.0;
        assert!(
            error.abs() < 1e-6,
            "case {i}: {numerical} vs {exact}: {error:e}"
        );
    }
}

/// Clapeyron: two equal spans, unit load at `a` in span one, interior support moment
/// `M = -a (L^2 - a^2) / (4 L^2)`; with the load at a node the Hermite solution is exact,
/// so only round-off separates them. The deflection under a load at midspan of span one is
/// 23 P L^3 / (1536 EI) (the simple span's P L^3 / 48 EI less the pier moment's share).
#[test]
fn support_moment_and_deflection_of_two_equal_spans() {
    let l = 30.0;
    let beam = girder_beam(
        &[l, l],
        &[Support::Pinned, Support::Roller, Support::Roller],
    );
    let model = fe(&beam, 60);
    for a in [3.0, 7.5, 15.0, 24.0] {
        let u = static_state(&model, a);
        let m = model.read(l, PointQuantity::Moment, &u);
        let exact = -a * (l * l - a * a) / (4.0 * l * l);
        assert!(
            (m - exact).abs() < 1e-9 * exact.abs(),
            "a = {a}: {m} vs {exact}"
        );
    }
    let u = static_state(&model, 15.0);
    let w = -model.read(15.0, PointQuantity::Deflection, &u);
    let exact = 23.0 * l.powi(3) / (1536.0 * EI);
    assert!((w / exact - 1.0).abs() < 1e-9, "{w} vs {exact}");
}

/// The force method's closed-form deflections equal the FE statics (exact for loads at
/// nodes on a uniform girder) on three spans with a clamped end and two overhangs.
#[test]
fn force_method_equals_the_finite_elements() {
    let cases = [
        girder_beam(
            &[20.0, 30.0, 20.0],
            &[
                Support::Pinned,
                Support::Roller,
                Support::Roller,
                Support::Roller,
            ],
        ),
        BeamProperties {
            girder: Girder {
                spans_m: vec![24.0, 30.0, 24.0],
                supports: vec![
                    Support::Pinned,
                    Support::Roller,
                    Support::Roller,
                    Support::Pinned,
                ],
                overhang_left_m: 6.0,
                overhang_right_m: 3.0,
            },
            ..BeamProperties::paper_default()
        },
        girder_beam(
            &[25.0, 25.0],
            &[Support::Fixed, Support::Roller, Support::Roller],
        ),
    ];
    for beam in cases {
        let method = ForceMethod::new(&beam).expect("applies");
        let length = beam.length_m();
        // 1 m elements: every integer abscissa is a node.
        let model = fe(&beam, length as usize);
        let inside = |v: &[f64]| {
            v.iter()
                .copied()
                .filter(|&x| x < length)
                .collect::<Vec<_>>()
        };
        for a in inside(&[1.0, 5.0, 13.0, 27.0, 40.0, 55.0, length - 1.0]) {
            let u = static_state(&model, a);
            for x in inside(&[2.0, 6.0, 15.0, 31.0, 50.0, length - 0.5]) {
                let numerical = -model.read(x, PointQuantity::Deflection, &u);
                let closed = method.deflection_m_per_n(x, a);
                let scale = method.deflection_m_per_n(a, a).abs();
                assert!(
                    (numerical - closed).abs() < 1e-9 * scale,
                    "{:?} x = {x}, a = {a}: FE {numerical:e} vs force method {closed:e}",
                    beam.girder
                );
            }
        }
    }
}

/// The lumped model on three spans: the flexibility (force method) and condensation
/// routes give the same stiffness to round-off, and both converge to the FE frequencies.
#[test]
fn lumped_routes_agree_on_three_spans() {
    let beam = girder_beam(
        &[24.0, 30.0, 24.0],
        &[
            Support::Pinned,
            Support::Roller,
            Support::Roller,
            Support::Roller,
        ],
    );
    let build = |stiffness| {
        BridgeModel::build(
            &beam,
            &ModelSpec::LumpedMass {
                nodes: 60,
                stiffness,
            },
            0.0,
        )
        .unwrap()
    };
    let flexibility = build(LumpedStiffness::Flexibility);
    let condensation = build(LumpedStiffness::Condensation);
    let (kf, kc) = (
        flexibility.stiffness.to_dense(),
        condensation.stiffness.to_dense(),
    );
    let rel = (&kf - &kc).norm() / kc.norm();
    assert!(rel < 1e-9, "stiffness routes differ by {rel:e}");
    let reference = fe(&beam, 240);
    // Lumped masses converge as 1/N^2: 60 masses (20 per span) err below 0.5 % on the
    // first three modes.
    for n in 1..=3 {
        let error = flexibility.frequency_hz(n) / reference.frequency_hz(n) - 1.0;
        assert!(error.abs() < 5e-3, "mode {n}: {error:e}");
    }
}

/// An elastic support adds its spring to the diagonal and a mass to the lumped model; a
/// stiff spring behaves as a rigid support.
#[test]
fn stiff_springs_act_as_rigid_supports() {
    let spring = Support::Elastic {
        vertical_n_m: 1e14,
        rotational_n_m_rad: 0.0,
    };
    let rigid = fe(
        &girder_beam(
            &[30.0, 30.0],
            &[Support::Pinned, Support::Roller, Support::Roller],
        ),
        60,
    );
    let elastic = fe(
        &girder_beam(&[30.0, 30.0], &[Support::Pinned, spring, Support::Roller]),
        60,
    );
    let error = elastic.frequency_hz(2) / rigid.frequency_hz(2) - 1.0;
    assert!(error.abs() < 1e-4, "{error:e}");
    let soft = Support::Elastic {
        vertical_n_m: 1e7,
        rotational_n_m_rad: 0.0,
    };
    let softer = fe(
        &girder_beam(&[30.0, 30.0], &[Support::Pinned, soft, Support::Roller]),
        60,
    );
    assert!(softer.frequency_hz(2) < 0.99 * rigid.frequency_hz(2));
    let lumped = BridgeModel::build(
        &girder_beam(&[30.0, 30.0], &[Support::Pinned, soft, Support::Roller]),
        &ModelSpec::LumpedMass {
            nodes: 40,
            stiffness: LumpedStiffness::Auto,
        },
        0.0,
    )
    .unwrap();
    assert_eq!(lumped.n_dof(), 41, "40 masses and the spring's");
    // The rigid end supports take half a spacing (30 m / 21) of girder each.
    let total: f64 = lumped.mass.diagonal().iter().sum();
    let expected = MASS * (60.0 - 30.0 / 21.0);
    assert!(
        (total / expected - 1.0).abs() < 1e-12,
        "{total} vs {expected}"
    );
    let error = lumped.frequency_hz(1) / softer.frequency_hz(1) - 1.0;
    assert!(error.abs() < 5e-3, "{error:e}");
}

/// A haunch raises EI linearly towards the pier: each element takes the section's mean EI
/// (exact integral), an O(h^2) approximation of the varying section, so refining converges
/// (mode 1 changes by < 1e-4 from 120 to 240 elements) and the haunched girder is stiffer
/// than the prismatic one.
#[test]
fn haunched_sections_stiffen_the_girder() {
    let prismatic = girder_beam(
        &[30.0, 30.0],
        &[Support::Pinned, Support::Roller, Support::Roller],
    );
    let mut haunched = prismatic.clone();
    haunched.sections = vec![Section {
        start_m: 24.0,
        end_m: 36.0,
        flexural_rigidity_n_m2: Some(Varying::Linear([EI, 2.0 * EI])),
        mass_per_length_kg_m: None,
    }];
    haunched.sections.push(Section {
        start_m: 36.0,
        end_m: 40.0,
        flexural_rigidity_n_m2: Some(Varying::Linear([2.0 * EI, EI])),
        mass_per_length_kg_m: Some(Varying::Constant(13_000.0)),
    });
    haunched.validate("bridge").unwrap();
    let (coarse, fine) = (fe(&haunched, 120), fe(&haunched, 240));
    let change = coarse.frequency_hz(1) / fine.frequency_hz(1) - 1.0;
    assert!(change.abs() < 1e-4, "{change:e}");
    assert!(fine.frequency_hz(2) > fe(&prismatic, 240).frequency_hz(2));
    let mut overlapping = haunched.clone();
    overlapping.sections[1].start_m = 30.0;
    let msg = overlapping.validate("bridge").unwrap_err().to_string();
    assert!(
        msg.contains("bridge.sections.1.start_m") && msg.contains("overlaps"),
        "{msg}"
    );
}

/// Reactions of two equal spans under a unit load at `a` in span one, from the pier moment
/// `M1 = -a (L^2 - a^2) / (4 L^2)`: `R0 = (L - a + M1) / L`, `R2 = M1 / L` (the far support
/// holds the girder down), `R1 = 1 - R0 - R2`; the load at a node makes FE exact.
#[test]
fn reactions_of_two_equal_spans() {
    let l = 30.0;
    let beam = girder_beam(
        &[l, l],
        &[Support::Pinned, Support::Roller, Support::Roller],
    );
    let model = fe(&beam, 60);
    for a in [4.5, 15.0, 27.0] {
        let u = static_state(&model, a);
        let r = model.support_reactions(&ReactionState {
            u: &u,
            v: None,
            a: None,
            loads: &[(a, -1.0)],
        });
        let m1 = -a * (l * l - a * a) / (4.0 * l * l);
        let (r0, r2) = ((l - a + m1) / l, m1 / l);
        let exact = [r0, 1.0 - r0 - r2, r2];
        for (got, want) in r.iter().zip(exact) {
            assert!((got - want).abs() < 1e-9, "a = {a}: {r:?} vs {exact:?}");
        }
    }
}

/// Three spans 20 + 25 + 20 m, clamped at the left, an elastic first pier (2e8 N/m, 1e9 N
/// m/rad), rollers, and a 4 m overhang on the right.
fn elastic_pier_girder() -> BeamProperties {
    let spring = Support::Elastic {
        vertical_n_m: 2e8,
        rotational_n_m_rad: 1e9,
    };
    BeamProperties {
        girder: Girder {
            spans_m: vec![20.0, 25.0, 20.0],
            supports: vec![Support::Fixed, spring, Support::Roller, Support::Roller],
            overhang_left_m: 0.0,
            overhang_right_m: 4.0,
        },
        ..BeamProperties::paper_default()
    }
}

/// Static equilibrium: the reactions sum to the loads on any girder and model, with a
/// clamped end, an elastic pier, an overhang, a load on the overhang's tip and one on a
/// support (which the support takes whole). A modal model's reactions are the shear of a
/// truncated series, which converges slowly and not monotonically near the loads (1.5e-2
/// of the load with 130 modes, while its deflections converge: 5e-6 with 130), so they
/// are not asserted here; `modal_shapes_of_a_symmetric_girder_are_finite` covers the
/// modal model.
#[test]
fn reactions_balance_the_loads() {
    let beam = elastic_pier_girder();
    let loads = [
        (3.3, -1.0e5),
        (20.0, -2.0e5),
        (31.7, -5.0e4),
        (69.0, -3.0e4),
        (45.0, -1.0e5),
    ];
    for spec in [
        ModelSpec::FiniteElement { elements: 69 },
        ModelSpec::LumpedMass {
            nodes: 60,
            stiffness: LumpedStiffness::Auto,
        },
    ] {
        let model = BridgeModel::build(&beam, &spec, 0.0).unwrap();
        let mut f = DVector::zeros(model.n_dof());
        for &(x, p) in &loads {
            f += model.point_load_vector(x, p);
        }
        let u = model.stiffness.to_dense().cholesky().unwrap().solve(&f);
        let r = model.support_reactions(&ReactionState {
            u: &u,
            v: None,
            a: None,
            loads: &loads,
        });
        let total: f64 = loads.iter().map(|l| -l.1).sum();
        let sum: f64 = r.iter().sum();
        // FE: exact. The lumped model's field between its masses is T u, the
        // condensation's, which leaves out the local response of a load between two
        // masses (the share of the load on the condensed-out rotations): 4e-4 of the load
        // here, within 1e-3.
        let tolerance = match spec {
            ModelSpec::FiniteElement { .. } => 1e-9,
            _ => 1e-3,
        };
        assert!(
            (sum / total - 1.0).abs() < tolerance,
            "{}: {r:?} sum {sum} vs {total}",
            spec.label()
        );
    }
}

/// Regression test of the band eigen-solver's normalization: on this girder's nearly
/// repeated modes (two equal end spans) the inverse iteration's shift hit an eigenvalue to
/// the last bit, the zero pivot's stand-in made entries of 1e150, the norm overflowed and
/// modes 38, 51 and 56 came out NaN.
#[test]
fn modal_shapes_of_a_symmetric_girder_are_finite() {
    let beam = elastic_pier_girder();
    let model = BridgeModel::build(
        &beam,
        &ModelSpec::Modal {
            modes: 60,
            elements: Some(138),
        },
        0.0,
    )
    .unwrap();
    for x in [3.3, 20.0, 31.7, 45.0, 69.0] {
        let f = model.point_load_vector(x, -1.0);
        assert!(f.iter().all(|v| v.is_finite()), "x = {x}");
    }
}
