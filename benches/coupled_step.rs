//! One coupled vehicle-bridge step with the two-axle truck on the bridge, on each path of
//! `bridgetwin bench` (the setup is the library's `bench::setup`, so both measure the same
//! thing): the low-rank contact coupling (`CoupledSolver`, bridge factorized once) on the
//! lumped-mass, banded FE and 10-mode modal models, and the paper's direct method
//! (`DirectSolver`, full coupled system assembled and LU-factorized every step) on the
//! lumped model, vs the node count.
//!
//! Ids: `solver/coupled_step/{lumped_low_rank,fe_banded,modal_10,direct_paper}/nodes=N`
//! (N masses, elements, or the elements the 10 modes come from). The direct method is
//! O(n^3) per step: up to 300 nodes here (`bridgetwin bench` times a few steps at 1000).
//! Sized for a 2-core machine: a few minutes in all.

use std::cell::OnceCell;
use std::time::Duration;

use bridgetwin::studies::bench::setup::{path_timer, truck, BenchPath};
use criterion::{criterion_group, criterion_main, Criterion};

/// Largest node count the direct method is benched at.
const DIRECT_MAX_NODES: usize = 300;

fn coupled_step(c: &mut Criterion) {
    let vehicle = truck().expect("the two_axle_truck preset builds");
    let mut group = c.benchmark_group("solver/coupled_step");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for nodes in [50, 100, 300, 1000] {
        for path in BenchPath::ALL {
            if path == BenchPath::Direct && nodes > DIRECT_MAX_NODES {
                continue;
            }
            // Built on first use, so a filter skips the slow builds (the dense eigensolve
            // behind the Rayleigh fit costs seconds at 1000 elements).
            let model = OnceCell::new();
            group.bench_function(format!("{}/nodes={nodes}", path.name()), |b| {
                let model = model.get_or_init(|| path.model(nodes).expect("the model builds"));
                let mut timer = path_timer(path, model, &vehicle);
                b.iter_custom(&mut timer)
            });
        }
    }
    group.finish();
}

criterion_group!(benches, coupled_step);
criterion_main!(benches);
