//! Physics and output on two threads: the time loop hands its records over in batches to a
//! writer thread that encodes, compresses and writes them, so on a machine with a spare
//! core the physics costs (almost) no wall time next to the output.
//!
//! - Batches of [`BATCH_RECORDS`] records go through a bounded channel
//!   ([`BATCHES_IN_FLIGHT`] deep), so memory stays bounded however long the run: when the
//!   writer falls behind, the time loop waits.
//! - Emptied batches come back on a second channel and are refilled: no allocation per
//!   batch once the pipeline is primed.
//! - Records arrive at the writer in the order they were produced, so the file is
//!   byte-identical to a run written inline (`tests/suite/simulate_mcap.rs` checks it).
//! - The first writer error stops the pipeline: the time loop's next hand-over fails, and
//!   the writer's own error (the informative one) is returned.
//!
//! A sweep runs one job per core and writes inline: a second thread per run would only
//! compete with the other jobs.

use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TryRecvError};

use crate::error::{Error, Result};
use crate::record::{Record, Recorder, RunManifest};

/// Records per hand-over: large enough that the channel costs nothing per record, small
/// enough that the writer starts early.
pub const BATCH_RECORDS: usize = 1024;
/// Batches queued between the threads at most.
pub const BATCHES_IN_FLIGHT: usize = 8;

/// Runs `produce` on this thread with a recorder that forwards every record to `writer`,
/// which runs on a second thread. Returns what `produce` returned and the writer (for its
/// counters) once both have finished and `writer.finish()` has run.
pub fn record_in_background<R, T>(
    writer: R,
    produce: impl FnOnce(&mut dyn Recorder) -> Result<T>,
) -> Result<(T, R)>
where
    R: Recorder + Send,
{
    let (full_tx, full_rx) = sync_channel::<Vec<Record>>(BATCHES_IN_FLIGHT);
    let (empty_tx, empty_rx) = sync_channel::<Vec<Record>>(BATCHES_IN_FLIGHT + 2);
    let (manifest_tx, manifest_rx) = sync_channel::<Box<RunManifest>>(1);
    std::thread::scope(|scope| {
        let handle = std::thread::Builder::new()
            .name("bridgetwin-writer".into())
            .spawn_scoped(scope, move || drain(writer, manifest_rx, full_rx, empty_tx))
            .map_err(|e| Error::Output {
                path: "writer thread".into(),
                reason: e.to_string(),
            })?;
        let mut handoff = Handoff {
            manifest: Some(manifest_tx),
            batch: Vec::with_capacity(BATCH_RECORDS),
            full: Some(full_tx),
            empty: empty_rx,
        };
        let produced = produce(&mut handoff);
        // Closing the channel ends the writer's loop (after a failure too).
        drop(handoff);
        let written = handle.join().map_err(|_| Error::Output {
            path: "writer thread".into(),
            reason: "panicked".into(),
        })?;
        // The writer's error explains a failed hand-over better than the hand-over does.
        let writer = written?;
        Ok((produced?, writer))
    })
}

/// The writer thread: takes the manifest, records every batch, returns emptied batches,
/// then finishes. A producer that stops before its manifest leaves the writer untouched.
fn drain<R: Recorder>(
    mut writer: R,
    manifest: Receiver<Box<RunManifest>>,
    full: Receiver<Vec<Record>>,
    empty: SyncSender<Vec<Record>>,
) -> Result<R> {
    let Ok(manifest) = manifest.recv() else {
        return Ok(writer);
    };
    writer.begin(&manifest)?;
    drop(manifest);
    for mut batch in full {
        for record in batch.drain(..) {
            writer.record(record)?;
        }
        // The producer may have finished and gone: a lost empty batch is harmless.
        let _ = empty.try_send(batch);
    }
    writer.finish()?;
    Ok(writer)
}

/// The time loop's side: hands the manifest over, fills a batch and sends it when full;
/// `finish` sends the rest.
struct Handoff {
    manifest: Option<SyncSender<Box<RunManifest>>>,
    batch: Vec<Record>,
    full: Option<SyncSender<Vec<Record>>>,
    empty: Receiver<Vec<Record>>,
}

impl Handoff {
    fn send(&mut self) -> Result<()> {
        let next = match self.empty.try_recv() {
            Ok(batch) => batch,
            Err(TryRecvError::Empty | TryRecvError::Disconnected) => {
                Vec::with_capacity(BATCH_RECORDS)
            }
        };
        let full = std::mem::replace(&mut self.batch, next);
        let stopped = || Error::Output {
            path: "writer thread".into(),
            reason: "stopped early".into(),
        };
        self.full
            .as_ref()
            .ok_or_else(stopped)?
            .send(full)
            .map_err(|_| stopped())
    }
}

impl Recorder for Handoff {
    fn begin(&mut self, manifest: &RunManifest) -> Result<()> {
        let stopped = || Error::Output {
            path: "writer thread".into(),
            reason: "stopped before the run began".into(),
        };
        let sender = self.manifest.take().ok_or_else(stopped)?;
        sender
            .send(Box::new(manifest.clone()))
            .map_err(|_| stopped())
    }

    fn record(&mut self, record: Record) -> Result<()> {
        if self.manifest.is_some() {
            return Err(Error::Output {
                path: "writer thread".into(),
                reason: "a record arrived before the run manifest (Recorder::begin)".into(),
            });
        }
        self.batch.push(record);
        if self.batch.len() >= BATCH_RECORDS {
            self.send()?;
        }
        Ok(())
    }

    /// Sends the last batch and closes the channel; the writer then finishes.
    fn finish(&mut self) -> Result<()> {
        if !self.batch.is_empty() {
            self.send()?;
        }
        self.full = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{EventLevel, VecRecorder};

    fn event(t_ns: u64) -> Record {
        Record::Event {
            t_ns,
            level: EventLevel::Info,
            text: String::new(),
        }
    }

    #[test]
    fn records_arrive_in_order_and_complete() {
        let n = 3 * BATCH_RECORDS as u64 + 17;
        let ((), got) = record_in_background(VecRecorder::default(), |r| {
            r.begin(&RunManifest::minimal())?;
            for t in 0..n {
                r.record(event(t))?;
            }
            r.finish()
        })
        .unwrap();
        let times: Vec<u64> = got.records.iter().map(Record::t_ns).collect();
        assert_eq!(times, (0..n).collect::<Vec<_>>());
    }

    /// A writer failing at its 10th record.
    struct Failing(usize);
    impl Recorder for Failing {
        fn record(&mut self, _: Record) -> Result<()> {
            self.0 += 1;
            match self.0 {
                10 => Err(Error::Output {
                    path: "disk".into(),
                    reason: "full".into(),
                }),
                _ => Ok(()),
            }
        }
    }

    #[test]
    fn the_writer_error_is_returned_and_stops_the_producer() {
        let mut produced = 0u64;
        let outcome = record_in_background(Failing(0), |r| {
            r.begin(&RunManifest::minimal())?;
            for t in 0..1_000_000 {
                r.record(event(t))?;
                produced += 1;
            }
            r.finish()
        });
        let message = outcome.err().expect("must fail").to_string();
        assert!(
            message.contains("disk") && message.contains("full"),
            "{message}"
        );
        // The producer stopped once the channel was full, far before the end.
        assert!(produced < 100 * BATCH_RECORDS as u64, "{produced}");
    }
}
