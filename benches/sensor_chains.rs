//! The sensor chains' cost, measured in one run: 16 accelerometers as `ideal` sensors
//! against `mems_lownoise` chains on drifting, resynchronised DAQ node clocks with bursty
//! packet loss and spikes, 60 s of ambient excitation and a truck, end to end into an
//! in-memory MCAP (the library's `bench::chains`, which `bridgetwin bench` times too).
//! Target: realistic / ideal <= 1.5.

use std::time::Duration;

use bridgetwin::app::run::WriterThread;
use bridgetwin::studies::bench::chains::scenario;
use bridgetwin::studies::bench::write_mcap;
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("chains/16_accelerometers_60s");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    for (name, realistic) in [("ideal", false), ("mems_lownoise_clocks_faults", true)] {
        let (resolved, prepared) = scenario(realistic).expect("scenario");
        group.bench_function(name, |b| {
            b.iter(|| {
                write_mcap(&resolved, &prepared, None, WriterThread::Background).expect("run")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
