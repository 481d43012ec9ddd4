//! The default scenario end to end, split into its parts, measured in one run:
//!
//! - `simulate/default/physics_and_sensors`: the coupled solver and the DAQ chains, with a
//!   recorder that drops every record;
//! - `simulate/default/writing_only`: the records of a run (collected beforehand, untimed)
//!   encoded as protobuf and written to an in-memory MCAP;
//! - `simulate/default/end_to_end`: both, as `bridgetwin simulate` does (in memory).
//!
//! Issue targets read off these: end_to_end / writing_only (physics close to free next to
//! output) for both layouts.

use std::hint::black_box;
use std::time::Duration;

use bridgetwin::scenario::{Layout, Resolved, Scenario};
use bridgetwin::sim::{prepare, run, Prepared, Record, Recorder, VecRecorder};
use bridgetwin::sink::{McapRecorder, McapSink, SinkOptions};
use criterion::{criterion_group, criterion_main, Criterion};

/// Counts records and drops them.
struct Discard(u64);

impl Recorder for Discard {
    fn record(&mut self, record: Record) -> bridgetwin::Result<()> {
        self.0 += black_box(&record).t_ns() & 1;
        Ok(())
    }
}

fn scenario(layout: Layout) -> (Resolved, Prepared) {
    let mut s = Scenario::default_scenario();
    s.output.layout = layout;
    let resolved = s.resolve().expect("default scenario");
    let prepared = prepare(&resolved).expect("prepared");
    (resolved, prepared)
}

/// Writes `records` (or runs the simulation when `None`) into an in-memory MCAP.
fn write_mcap(resolved: &Resolved, prepared: &Prepared, records: Option<&[Record]>) -> usize {
    let mut sink = McapSink::in_memory(&SinkOptions::default()).expect("sink");
    let nodes = prepared.model.shape_positions_m().to_vec();
    let mut recorder = McapRecorder::new(&mut sink, resolved, nodes).expect("channels");
    match records {
        Some(records) => {
            for r in records {
                recorder.record(r.clone()).expect("write");
            }
            recorder.finish().expect("finish");
        }
        None => {
            run(resolved, prepared, &mut recorder, &mut |_, _| {}).expect("run");
        }
    }
    sink.finish_to_bytes().expect("bytes").len()
}

fn bench(c: &mut Criterion) {
    for (layout, name) in [(Layout::Sample, "sample"), (Layout::Block, "block")] {
        let (resolved, prepared) = scenario(layout);
        let mut collected = VecRecorder::default();
        run(&resolved, &prepared, &mut collected, &mut |_, _| {}).expect("run");
        let mut group = c.benchmark_group(format!("simulate/default_{name}"));
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(8));
        group.bench_function("physics_and_sensors", |b| {
            b.iter(|| {
                let mut discard = Discard(0);
                run(&resolved, &prepared, &mut discard, &mut |_, _| {}).expect("run");
                discard.0
            })
        });
        group.bench_function("writing_only", |b| {
            b.iter(|| write_mcap(&resolved, &prepared, Some(&collected.records)))
        });
        group.bench_function("end_to_end", |b| {
            b.iter(|| write_mcap(&resolved, &prepared, None))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
