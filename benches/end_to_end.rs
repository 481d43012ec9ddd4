//! The default scenario end to end, split into its parts, measured in one run (the parts
//! are the library's `bench` functions, which `bridgetwin bench` times too):
//!
//! - `simulate/default/physics_and_sensors`: the coupled solver and the DAQ chains, with a
//!   recorder that drops every record;
//! - `simulate/default/writing_only`: the records of a run (collected beforehand, untimed)
//!   encoded as protobuf and written to an in-memory MCAP;
//! - `simulate/default/end_to_end`: both, as `bridgetwin simulate` does (in memory, the
//!   writer on a second thread);
//! - `simulate/default/end_to_end_one_thread`: both on one thread, as a sweep job does.
//!
//! Issue targets read off these: end_to_end / writing_only (physics close to free next to
//! output) for both layouts.

use std::time::Duration;

use bridgetwin::app::run::WriterThread;
use bridgetwin::scenario::Layout;
use bridgetwin::studies::bench::{collect_records, default_scenario, physics_only, write_mcap};
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    for (layout, name) in [(Layout::Sample, "sample"), (Layout::Block, "block")] {
        let (resolved, prepared) = default_scenario(layout).expect("default scenario");
        let records = collect_records(&resolved, &prepared).expect("run");
        let mut group = c.benchmark_group(format!("simulate/default_{name}"));
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(8));
        group.bench_function("physics_and_sensors", |b| {
            b.iter(|| physics_only(&resolved, &prepared).expect("run"))
        });
        group.bench_function("writing_only", |b| {
            b.iter(|| {
                write_mcap(&resolved, &prepared, Some(&records), WriterThread::Inline)
                    .expect("write")
            })
        });
        group.bench_function("end_to_end", |b| {
            b.iter(|| {
                write_mcap(&resolved, &prepared, None, WriterThread::Background).expect("run")
            })
        });
        group.bench_function("end_to_end_one_thread", |b| {
            b.iter(|| write_mcap(&resolved, &prepared, None, WriterThread::Inline).expect("run"))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
