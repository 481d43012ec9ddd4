//! Chunks decompressed and checked on worker threads while the reading thread goes on:
//! decompression is most of the time of a pass over a run (1 s of 1.5 s for the hour
//! example), and chunks are independent. Each chunk's records come back in file order;
//! a chunk is handed on only whole and with its CRC checked, as before.

use std::io::Read;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::{Arc, Mutex};
use std::thread::{Scope, ScopedJoinHandle};

use mcap::records::ChunkHeader;

/// What a chunk gives: its decompressed records, or why it is damaged.
pub type ChunkRecords = Result<Vec<u8>, String>;

/// A chunk to decompress: its header, compressed records and where the reply goes.
struct Job {
    compression: String,
    uncompressed_size: u64,
    uncompressed_crc: u32,
    compressed: Vec<u8>,
    limit_bytes: usize,
    reply: SyncSender<ChunkRecords>,
}

/// Worker threads that decompress chunks. [`ChunkPool::finish`] (or dropping it) stops
/// them: jobs not started are skipped, and the threads are joined to their end.
pub struct ChunkPool<'scope> {
    jobs: Option<SyncSender<Job>>,
    threads: Vec<ScopedJoinHandle<'scope, ()>>,
    cancelled: Arc<AtomicBool>,
}

impl<'scope> ChunkPool<'scope> {
    /// Starts `workers` threads in `scope` (at least one).
    pub fn start(scope: &'scope Scope<'scope, '_>, workers: usize) -> ChunkPool<'scope> {
        let workers = workers.max(1);
        let (jobs, queue) = sync_channel::<Job>(workers * 2);
        let queue = Arc::new(Mutex::new(queue));
        let cancelled = Arc::new(AtomicBool::new(false));
        let threads = (0..workers)
            .map(|_| {
                let queue = Arc::clone(&queue);
                let cancelled = Arc::clone(&cancelled);
                scope.spawn(move || work(&queue, &cancelled))
            })
            .collect();
        ChunkPool {
            jobs: Some(jobs),
            threads,
            cancelled,
        }
    }

    pub fn workers(&self) -> usize {
        self.threads.len()
    }

    /// Queues a chunk; its records (or why it is damaged) arrive on the receiver.
    pub fn submit(
        &self,
        header: &ChunkHeader,
        compressed: &[u8],
        limit_bytes: usize,
    ) -> Receiver<ChunkRecords> {
        let (reply, records) = sync_channel(1);
        let job = Job {
            compression: header.compression.clone(),
            uncompressed_size: header.uncompressed_size,
            uncompressed_crc: header.uncompressed_crc,
            compressed: compressed.to_vec(),
            limit_bytes,
            reply,
        };
        let sent = match &self.jobs {
            Some(jobs) => jobs.send(job).map_err(|failed| failed.0),
            None => Err(job),
        };
        if let Err(job) = sent {
            // No worker takes jobs any more (it cannot happen while the pool lives).
            let reply = job.reply.clone();
            let _ = reply.send(guarded(job));
        }
        records
    }

    /// Stops the workers (jobs not yet started are dropped) and waits until every thread
    /// has ended, its thread-local state freed with it.
    pub fn finish(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.cancelled.store(true, Ordering::Relaxed);
        self.jobs = None;
        for thread in self.threads.drain(..) {
            // A worker's panic was already turned into a damaged chunk.
            let _ = thread.join();
        }
    }
}

impl Drop for ChunkPool<'_> {
    fn drop(&mut self) {
        self.stop();
    }
}

/// A worker: takes jobs until the pool is finished, skipping them once it is cancelled.
fn work(queue: &Mutex<Receiver<Job>>, cancelled: &AtomicBool) {
    loop {
        // The lock is held only to take the next job.
        let job = match queue.lock() {
            Ok(queue) => queue.recv(),
            Err(_) => return,
        };
        let Ok(job) = job else { return };
        if cancelled.load(Ordering::Relaxed) {
            continue;
        }
        let reply = job.reply.clone();
        // The reader may have stopped and dropped the receiver: nothing to do.
        let _ = reply.send(guarded(job));
    }
}

/// [`decompress`], with a panic in a codec reported as damage instead of crossing threads.
fn guarded(job: Job) -> ChunkRecords {
    catch_unwind(AssertUnwindSafe(|| decompress(job)))
        .unwrap_or_else(|_| Err("decompressing a chunk failed (the codec panicked)".into()))
}

/// The threads to decompress with: the cores there are, at most 8 (more do not help a
/// pass that also reads and decodes on one thread).
pub fn default_workers() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().clamp(1, 8))
}

/// A chunk's records, decompressed and checked against its stated size and CRC. The
/// output grows only with bytes really decompressed, never beyond the stated size (which
/// the reader also counts against its budget of queued bytes).
fn decompress(job: Job) -> ChunkRecords {
    let size = usize::try_from(job.uncompressed_size)
        .ok()
        .filter(|&s| s <= job.limit_bytes)
        .ok_or_else(|| {
            format!(
                "a chunk claims {} bytes uncompressed, more than the file can hold (corrupted length)",
                job.uncompressed_size
            )
        })?;
    let records = match job.compression.as_str() {
        "" => job.compressed,
        "zstd" => read_at_most(
            zstd::stream::read::Decoder::with_buffer(&job.compressed[..])
                .map_err(|e| format!("a zstd chunk does not decompress: {e}"))?,
            size,
        )?,
        "lz4" => read_at_most(
            lz4::Decoder::new(&job.compressed[..])
                .map_err(|e| format!("an lz4 chunk does not decompress: {e}"))?,
            size,
        )?,
        other => return Err(format!("chunk compression {other:?} is not supported")),
    };
    if records.len() != size {
        return Err(format!(
            "a chunk decompresses to {} bytes where its header says {size}",
            records.len()
        ));
    }
    let crc = crc32fast::hash(&records);
    if job.uncompressed_crc != 0 && crc != job.uncompressed_crc {
        return Err(format!(
            "chunk CRC mismatch: its records hash to {crc:#010x}, the chunk says {:#010x}",
            job.uncompressed_crc
        ));
    }
    Ok(records)
}

/// Reads at most `size + 1` bytes (one more shows a chunk longer than it says).
fn read_at_most(source: impl Read, size: usize) -> Result<Vec<u8>, String> {
    const FIRST_RESERVE_BYTES: usize = 16 << 20;
    let mut out = Vec::with_capacity(size.min(FIRST_RESERVE_BYTES));
    source
        .take(size as u64 + 1)
        .read_to_end(&mut out)
        .map_err(|e| format!("a chunk does not decompress: {e}"))?;
    Ok(out)
}

/// The records of a decompressed chunk, in order: `(opcode, body)`, or why the next one
/// cannot be read (a length past the chunk's end).
pub fn chunk_records(records: &[u8]) -> impl Iterator<Item = Result<(u8, &[u8]), String>> {
    let mut at = 0usize;
    std::iter::from_fn(move || {
        if at >= records.len() {
            return None;
        }
        let left = records.len() - at;
        if left < 9 {
            at = records.len();
            return Some(Err(format!(
                "a record in a chunk is cut short ({left} bytes where 9 are its opcode and length)"
            )));
        }
        let opcode = records[at];
        let mut le = [0u8; 8];
        le.copy_from_slice(&records[at + 1..at + 9]);
        let len = u64::from_le_bytes(le);
        let body_start = at + 9;
        let fits = usize::try_from(len)
            .ok()
            .filter(|&n| n <= records.len() - body_start);
        let Some(len) = fits else {
            at = records.len();
            return Some(Err(format!(
                "a record in a chunk (opcode {opcode:#04x}) claims {len} bytes, more than the chunk holds (corrupted length)"
            )));
        };
        at = body_start + len;
        Some(Ok((opcode, &records[body_start..at])))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(compression: &str, data: Vec<u8>, size: u64, crc: u32) -> Job {
        Job {
            compression: compression.into(),
            uncompressed_size: size,
            uncompressed_crc: crc,
            compressed: data,
            limit_bytes: 1 << 20,
            reply: sync_channel(1).0,
        }
    }

    #[test]
    fn chunks_decompress_and_are_checked() {
        let records: Vec<u8> = (0..5000u32)
            .flat_map(|i| (i % 251) as u8..=(i % 251) as u8)
            .collect();
        let crc = crc32fast::hash(&records);
        let n = records.len() as u64;
        let zstd = zstd::bulk::compress(&records, 3).unwrap();
        assert_eq!(
            decompress(job("zstd", zstd.clone(), n, crc)),
            Ok(records.clone())
        );
        assert_eq!(
            decompress(job("", records.clone(), n, 0)),
            Ok(records.clone())
        );
        let e = decompress(job("zstd", zstd.clone(), n, crc ^ 1)).unwrap_err();
        assert!(e.contains("CRC mismatch"), "{e}");
        let e = decompress(job("zstd", zstd.clone(), n - 1, 0)).unwrap_err();
        assert!(e.contains("header says"), "{e}");
        let e = decompress(job("zstd", zstd, 1 << 40, 0)).unwrap_err();
        assert!(e.contains("corrupted length"), "{e}");
        let e = decompress(job("brotli", vec![], 0, 0)).unwrap_err();
        assert!(e.contains("not supported"), "{e}");
        let mut garbage = zstd::bulk::compress(&records, 3).unwrap();
        garbage[10] ^= 0xFF;
        assert!(decompress(job("zstd", garbage, n, crc)).is_err());
    }

    #[test]
    fn records_of_a_chunk_are_split_by_their_lengths() {
        let mut chunk = vec![0x05];
        chunk.extend(3u64.to_le_bytes());
        chunk.extend([1, 2, 3, 0x0C]);
        chunk.extend(0u64.to_le_bytes());
        let got: Vec<_> = chunk_records(&chunk).collect();
        assert_eq!(got, vec![Ok((0x05, &[1u8, 2, 3][..])), Ok((0x0C, &[][..]))]);
        chunk.extend([0x05, 0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0]);
        let last = chunk_records(&chunk).last().unwrap();
        assert!(last.unwrap_err().contains("corrupted length"));
        let cut = chunk_records(&[0x05, 1, 0]).next().unwrap();
        assert!(cut.unwrap_err().contains("cut short"));
    }
}
