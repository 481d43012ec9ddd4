//! One Newmark step vs model size, each discretization solved the paper's way (dense
//! effective matrix factorized every step) and with its structure exploited (factorized
//! once; banded FE through sparse Cholesky; diagonal modal).
//! Run: `cargo bench --bench newmark_step`.

use std::time::Duration;

use bridgetwin::physics::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use bridgetwin::physics::solver::{
    Newmark, NewmarkCoefficients, NewmarkParams, SolveMode, Storage,
};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::DVector;

fn integrator(spec: &ModelSpec, mode: SolveMode) -> Newmark {
    let model = BridgeModel::build(&BeamProperties::paper_default(), spec, 0.02).expect("model");
    let coefficients = NewmarkCoefficients::new(1e-3, NewmarkParams::default()).expect("dt");
    Newmark::new(
        &model.mass,
        &model.damping,
        &model.stiffness,
        coefficients,
        mode,
    )
    .expect("newmark")
}

fn bench_steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("solver/newmark_step");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(2));
    group.warm_up_time(Duration::from_millis(300));
    for n in [50usize, 100, 300, 1000] {
        let cases: Vec<(&str, ModelSpec, &str, SolveMode)> = vec![
            (
                "lumped_mass",
                ModelSpec::LumpedMass {
                    nodes: n,
                    stiffness: LumpedStiffness::Auto,
                },
                "prefactored_dense",
                SolveMode::Prefactored(Storage::Dense),
            ),
            (
                "finite_element",
                ModelSpec::FiniteElement { elements: n },
                "prefactored_dense",
                SolveMode::Prefactored(Storage::Dense),
            ),
            (
                "finite_element",
                ModelSpec::FiniteElement { elements: n },
                "prefactored_banded",
                SolveMode::Prefactored(Storage::Sparse),
            ),
            (
                "lumped_mass",
                ModelSpec::LumpedMass {
                    nodes: n,
                    stiffness: LumpedStiffness::Auto,
                },
                "paper_dense_each_step",
                SolveMode::FactorEachStep,
            ),
            (
                "finite_element",
                ModelSpec::FiniteElement { elements: n },
                "paper_dense_each_step",
                SolveMode::FactorEachStep,
            ),
        ];
        for (model, spec, way, mode) in cases {
            // A dense LU of 2000 unknowns per step takes ~1 s: not worth sampling.
            if mode == SolveMode::FactorEachStep && n > 300 {
                continue;
            }
            let mut nm = integrator(&spec, mode);
            let load = DVector::from_fn(nm.state.u.len(), |i, _| -1.0e3 * (i as f64 * 0.1).sin());
            group.bench_with_input(
                BenchmarkId::new(format!("{model}/{way}"), format!("nodes={n}")),
                &n,
                |b, _| b.iter(|| nm.step(&load)),
            );
        }
        if n <= 300 {
            let mut nm = integrator(
                &ModelSpec::Modal {
                    modes: 20,
                    elements: Some(n.max(40)),
                },
                SolveMode::Prefactored(Storage::Dense),
            );
            let load = DVector::from_element(20, -1.0e3);
            group.bench_with_input(
                BenchmarkId::new("modal_20/prefactored_diagonal", format!("fe_elements={n}")),
                &n,
                |b, _| b.iter(|| nm.step(&load)),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench_steps);
criterion_main!(benches);
