//! Same seed, same bytes, whatever the machine's speed: chunk boundaries and flushes
//! follow simulated time (`output.flush_every_s`) and the chunk size, never the wall
//! clock. A run slowed down on both threads (a slow disk under the writer, a slow time
//! loop) writes the very bytes of an unhindered one.

use std::io::{Cursor, Seek, SeekFrom, Write};
use std::time::Duration;

use bridgetwin::app::run::{write_run, WriterThread};
use bridgetwin::output::{McapSink, SinkOptions};
use bridgetwin::scenario::{Resolved, Scenario};
use bridgetwin::sim::{prepare, Control, RunProgress};

/// A disk that takes `delay` per write call.
struct SlowDisk {
    inner: Cursor<Vec<u8>>,
    delay: Duration,
    /// Delay injected so far.
    waited: Duration,
}

impl Write for SlowDisk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        std::thread::sleep(self.delay);
        self.waited += self.delay;
        self.inner.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

impl Seek for SlowDisk {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.inner.seek(pos)
    }
}

/// 70 s of the hour-of-traffic example (the block layout, 20 sensors on DAQ clocks,
/// generated traffic): one simulated-time flush at the default 60 s.
fn scenario() -> Resolved {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/hour_of_traffic.toml");
    let (mut s, text) = Scenario::from_file(std::path::Path::new(path)).unwrap();
    s.duration_s = Some(70.0);
    s.output.split_every_s = None;
    let mut resolved = s.resolve().unwrap();
    resolved.source_toml = text;
    resolved
}

/// How much slower than the machine allows.
#[derive(Clone, Copy)]
struct Slowdown {
    /// Per write call of the MCAP writer to its disk (thousands per run).
    per_write: Duration,
    /// Per progress report of the time loop (every 5000 steps).
    per_report: Duration,
}

const UNHINDERED: Slowdown = Slowdown {
    per_write: Duration::ZERO,
    per_report: Duration::ZERO,
};

/// The run's bytes and the delay injected on (the writer's, the time loop's) thread.
fn run(
    resolved: &Resolved,
    slowdown: Slowdown,
    thread: WriterThread,
) -> (Vec<u8>, (Duration, Duration)) {
    let prepared = prepare(resolved).unwrap();
    let disk = SlowDisk {
        inner: Cursor::new(Vec::new()),
        delay: slowdown.per_write,
        waited: Duration::ZERO,
    };
    let mut sink = McapSink::on_writer(disk, &SinkOptions::default(), "slow.mcap").unwrap();
    let mut loop_waited = Duration::ZERO;
    let mut progress = |_: &RunProgress| {
        std::thread::sleep(slowdown.per_report);
        loop_waited += slowdown.per_report;
    };
    let mut control = Control {
        progress: &mut progress,
        stop: None,
    };
    write_run(&mut sink, resolved, &prepared, &mut control, thread).unwrap();
    let disk = sink.finish_to_writer().unwrap();
    (disk.inner.into_inner(), (disk.waited, loop_waited))
}

#[test]
fn a_slowed_run_writes_the_same_bytes() {
    let resolved = scenario();
    let (fast, _) = run(&resolved, UNHINDERED, WriterThread::Background);
    // 1 ms per write call and 100 ms per progress report: the run takes seconds longer on
    // both threads. The wall-clock flush this replaced (every 2 s) put its chunk
    // boundaries elsewhere in such a run.
    let slowdown = Slowdown {
        per_write: Duration::from_millis(1),
        per_report: Duration::from_millis(100),
    };
    let (slow, (writer_waited, loop_waited)) = run(&resolved, slowdown, WriterThread::Background);
    println!(
        "{} bytes; delay injected: writer {:.2} s, time loop {:.2} s",
        fast.len(),
        writer_waited.as_secs_f64(),
        loop_waited.as_secs_f64()
    );
    assert!(fast.len() > 1_000_000, "{}", fast.len());
    // The injected delay, counted (not timed), spans several of the old 2 s periods on
    // each thread.
    assert!(writer_waited >= Duration::from_secs(2), "{writer_waited:?}");
    assert!(loop_waited >= Duration::from_secs(1), "{loop_waited:?}");
    assert!(slow == fast, "a slowed run changed the bytes");
    // The same bytes again on one thread.
    let (inline, _) = run(&resolved, UNHINDERED, WriterThread::Inline);
    assert!(inline == fast, "the writer thread changed the bytes");
}

#[test]
fn flushes_follow_simulated_time() {
    // More frequent flushes close more chunks: the interval is honoured, in simulated time.
    let mut resolved = scenario();
    // Without the 3D scene (about 100 kB/s before compression), which would close chunks
    // by size every 4 s, so that size alone leaves chunks longer than the 5 s interval.
    resolved.scene = None;
    let (default_flush, _) = run(&resolved, UNHINDERED, WriterThread::Inline);
    resolved.flush_every_ns = 5_000_000_000;
    let (frequent, _) = run(&resolved, UNHINDERED, WriterThread::Inline);
    // The longest stretch of log time one chunk holds (ns), and the number of chunks.
    let chunks = |bytes: &[u8]| {
        let summary = mcap::Summary::read(bytes).unwrap().expect("summary");
        let longest = summary
            .chunk_indexes
            .iter()
            .map(|c| c.message_end_time - c.message_start_time)
            .max()
            .unwrap_or(0);
        (summary.chunk_indexes.len(), longest)
    };
    let ((few, few_longest), (many, many_longest)) = (chunks(&default_flush), chunks(&frequent));
    println!("{few} chunks at 60 s (longest {few_longest} ns), {many} at 5 s (longest {many_longest} ns)");
    // A flush follows the first record at or past each multiple of 5 s, so no chunk spans
    // more than 5 s of log time; by size alone (1 MiB, about 8 s of this run) they do.
    assert!(many_longest <= 5_000_000_000, "{many_longest}");
    assert!(few_longest > 5_000_000_000, "{few_longest}");
    assert!(
        many >= 14 && many > few,
        "{few} chunks at 60 s, {many} at 5 s"
    );
}
