//! One coupled vehicle-bridge step with the two-axle truck on the bridge: the low-rank
//! contact coupling (`CoupledSolver`, bridge factorized once) against the paper's direct
//! method (`DirectSolver`, full coupled system assembled and LU-factorized every step),
//! vs the size of the bridge model.
//!
//! Ids: `solver/coupled_step/{lumped_mass,finite_element}/nodes=N/{low_rank,direct}` (N
//! masses or elements; FE has 2N DOFs) and `solver/coupled_step/modal/modes=N/...`.
//! The truck drives at 20 m/s with dt = 1 ms from 4.5 m (both axles on the span) to 29.5 m;
//! a fresh solver (untimed) takes over when it gets there, so every timed step has both
//! contacts on the bridge. Sized for a 2-core machine: a few minutes in all.

use std::hint::black_box;
use std::time::{Duration, Instant};

use bridgetwin::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use bridgetwin::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, DirectSolver, LevelRoad, NewmarkCoefficients,
    NewmarkParams, SolveMode, Storage,
};
use bridgetwin::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};
use criterion::{criterion_group, criterion_main, Criterion};

const SPEED_M_S: f64 = 20.0;
const DT_S: f64 = 1e-3;
const START_M: f64 = 4.5;
const END_M: f64 = 29.5;

fn truck() -> VehicleDynamics {
    VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some("two_axle_truck".into()),
        ..Default::default()
    })
    .build("vehicle")
    .expect("the two_axle_truck preset builds")
}

fn coefficients() -> NewmarkCoefficients {
    NewmarkCoefficients::new(DT_S, NewmarkParams::default()).expect("valid Newmark step")
}

/// Steps a fresh solver takes before the truck reaches `END_M`.
fn steps_per_solver() -> u64 {
    ((END_M - START_M) / (SPEED_M_S * DT_S)) as u64
}

/// Times `iters` steps, replacing the solver (untimed) whenever the truck would leave
/// the stretch where both axles are on the span.
fn time_steps<S>(iters: u64, make: impl Fn() -> S, step: impl Fn(&mut S)) -> Duration {
    let mut total = Duration::ZERO;
    let mut done = 0;
    while done < iters {
        let mut solver = make();
        let chunk = steps_per_solver().min(iters - done);
        let start = Instant::now();
        for _ in 0..chunk {
            step(&mut solver);
        }
        total += start.elapsed();
        black_box(&mut solver);
        done += chunk;
    }
    total
}

fn bench_model(c: &mut Criterion, kind: &str, label: &str, spec: ModelSpec, storage: Storage) {
    let model = BridgeModel::build(&BeamProperties::paper_default(), &spec, 0.02)
        .expect("the bridge model builds");
    let road = LevelRoad;
    let vehicle = truck();
    let mut group = c.benchmark_group("solver/coupled_step");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    group.bench_function(format!("{kind}/{label}/low_rank"), |b| {
        b.iter_custom(|iters| {
            time_steps(
                iters,
                || {
                    let mut s = CoupledSolver::new(
                        &model,
                        &road,
                        coefficients(),
                        SolveMode::Prefactored(storage),
                        ContactLaw::Full,
                    )
                    .expect("the effective matrix factorizes");
                    s.add_vehicle(CoupledVehicle::new(
                        0,
                        vehicle.clone(),
                        SPEED_M_S,
                        START_M,
                        0,
                    ));
                    s
                },
                |s| s.advance().expect("step"),
            )
        })
    });
    // The direct method is O(n^3) per step: only up to 300 DOF-ish models.
    if model.n_dof() <= 600 {
        group.bench_function(format!("{kind}/{label}/direct"), |b| {
            b.iter_custom(|iters| {
                time_steps(
                    iters,
                    || {
                        let mut s = DirectSolver::new(&model, &road, coefficients())
                            .expect("solver builds");
                        s.add_vehicle(CoupledVehicle::new(
                            0,
                            vehicle.clone(),
                            SPEED_M_S,
                            START_M,
                            0,
                        ));
                        s
                    },
                    |s| s.advance().expect("step"),
                )
            })
        });
    }
    group.finish();
}

fn coupled_step(c: &mut Criterion) {
    for n in [50, 100, 300, 1000] {
        let spec = ModelSpec::LumpedMass {
            nodes: n,
            stiffness: LumpedStiffness::Auto,
        };
        // The lumped stiffness F^-1 is dense.
        bench_model(
            c,
            "lumped_mass",
            &format!("nodes={n}"),
            spec,
            Storage::Dense,
        );
    }
    for n in [50, 100, 300] {
        let spec = ModelSpec::FiniteElement { elements: n };
        // Banded Hermite matrices: sparse Cholesky keeps the band.
        bench_model(
            c,
            "finite_element",
            &format!("nodes={n}"),
            spec,
            Storage::Sparse,
        );
    }
    for n in [50, 100, 300] {
        // n modes of an FE model with 2n elements (the least `ModelSpec` allows): diagonal
        // matrices, whatever the storage.
        let spec = ModelSpec::Modal {
            modes: n,
            elements: Some(2 * n),
        };
        bench_model(c, "modal", &format!("modes={n}"), spec, Storage::Dense);
    }
}

criterion_group!(benches, coupled_step);
criterion_main!(benches);
