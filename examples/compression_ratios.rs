//! Measures how well each message type compresses in bridgetwin runs: the figures behind
//! `output::estimate`'s compression table (`docs/output.md`, "The estimate before a run").
//!
//!     cargo run --release --example compression_ratios -- run1.mcap run2.mcap ...
//!
//! For every schema, the messages of the given files are laid out as the writer lays
//! them out in a chunk (the 31-byte message record header, then the payload, in file
//! order), cut into 1 MiB pieces and compressed with zstd at the writer's level (3);
//! the ratio is compressed / uncompressed bytes. Each file's own ratio (its chunks'
//! compressed over uncompressed sizes, from the summary) is printed beside the mix the
//! per-schema ratios predict for it, to show how far the per-type model is from the
//! interleaved chunks the writer really makes.

use std::collections::BTreeMap;

use anyhow::{Context, Result};

/// The writer's chunk size (the `mcap` crate's default).
const CHUNK_BYTES: usize = 1 << 20;
/// zstd level of the `mcap` crate's writer (0: zstd's default, 3).
const ZSTD_LEVEL: i32 = 3;
/// Opcode, record length, channel id, sequence, log time, publish time.
const MESSAGE_RECORD_HEADER_BYTES: usize = 1 + 8 + 2 + 4 + 8 + 8;

/// Uncompressed record bytes of one schema, in file order, and its message count.
#[derive(Default)]
struct Stream {
    bytes: Vec<u8>,
    messages: u64,
    compressed: u64,
    uncompressed: u64,
}

impl Stream {
    fn push(&mut self, message: &mcap::Message<'_>) -> Result<()> {
        let channel_id = message.channel.id;
        let length = (MESSAGE_RECORD_HEADER_BYTES - 9 + message.data.len()) as u64;
        self.bytes.push(0x05);
        self.bytes.extend_from_slice(&length.to_le_bytes());
        self.bytes.extend_from_slice(&channel_id.to_le_bytes());
        self.bytes
            .extend_from_slice(&message.sequence.to_le_bytes());
        self.bytes
            .extend_from_slice(&message.log_time.to_le_bytes());
        self.bytes
            .extend_from_slice(&message.publish_time.to_le_bytes());
        self.bytes.extend_from_slice(&message.data);
        self.messages += 1;
        if self.bytes.len() >= CHUNK_BYTES {
            self.compress()?;
        }
        Ok(())
    }

    fn compress(&mut self) -> Result<()> {
        if self.bytes.is_empty() {
            return Ok(());
        }
        let compressed = zstd::bulk::compress(&self.bytes, ZSTD_LEVEL)?;
        self.compressed += compressed.len() as u64;
        self.uncompressed += self.bytes.len() as u64;
        self.bytes.clear();
        Ok(())
    }

    fn ratio(&self) -> f64 {
        self.compressed as f64 / self.uncompressed.max(1) as f64
    }
}

/// One file: its schemas' uncompressed bytes and ratios, and its chunks' ratio.
struct FileFigures {
    path: String,
    schemas: BTreeMap<String, (u64, f64)>,
    actual: f64,
}

fn main() -> Result<()> {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        anyhow::bail!("usage: compression_ratios RUN.mcap [RUN.mcap ...]");
    }
    let mut all: BTreeMap<String, Stream> = BTreeMap::new();
    let mut files = Vec::new();
    for path in &paths {
        let bytes = std::fs::read(path).with_context(|| format!("reading {path}"))?;
        let mut streams: BTreeMap<String, Stream> = BTreeMap::new();
        for message in mcap::MessageStream::new(&bytes)? {
            let message = message?;
            let schema = message
                .channel
                .schema
                .as_ref()
                .map_or_else(String::new, |s| s.name.clone());
            streams.entry(schema.clone()).or_default().push(&message)?;
            all.entry(schema).or_default().push(&message)?;
        }
        let summary = mcap::Summary::read(&bytes)?.context("no summary")?;
        let (compressed, uncompressed) = summary
            .chunk_indexes
            .iter()
            .fold((0u64, 0u64), |(c, u), i| {
                (c + i.compressed_size, u + i.uncompressed_size)
            });
        let mut schemas = BTreeMap::new();
        for (schema, stream) in &mut streams {
            stream.compress()?;
            schemas.insert(schema.clone(), (stream.uncompressed, stream.ratio()));
        }
        files.push(FileFigures {
            path: path.clone(),
            schemas,
            actual: compressed as f64 / uncompressed.max(1) as f64,
        });
    }
    for stream in all.values_mut() {
        stream.compress()?;
    }
    println!("| file | chunks: compressed / uncompressed | the schemas' ratios over all files predict | error |");
    println!("|---|---|---|---|");
    for file in &files {
        let (predicted_bytes, total) =
            file.schemas
                .iter()
                .fold((0.0, 0u64), |(p, t), (schema, (uncompressed, _))| {
                    (
                        p + all[schema].ratio() * *uncompressed as f64,
                        t + uncompressed,
                    )
                });
        let predicted = predicted_bytes / total.max(1) as f64;
        println!(
            "| {} | {:.3} | {predicted:.3} | {:+.1} % |",
            file.path,
            file.actual,
            100.0 * (predicted / file.actual - 1.0)
        );
    }
    if std::env::var_os("COMPRESSION_RATIOS_PER_FILE").is_some() {
        println!();
        println!("| file | schema | uncompressed bytes | ratio |");
        println!("|---|---|---|---|");
        for file in &files {
            for (schema, (uncompressed, ratio)) in &file.schemas {
                println!("| {} | {schema} | {uncompressed} | {ratio:.3} |", file.path);
            }
        }
    }
    println!();
    println!("| schema | messages | uncompressed bytes | ratio over all files | lowest and highest in one file |");
    println!("|---|---|---|---|---|");
    for (schema, stream) in &all {
        let ratios = files
            .iter()
            .filter_map(|f| f.schemas.get(schema).map(|s| s.1));
        let (low, high) = ratios.fold((f64::MAX, 0.0f64), |(l, h), r| (l.min(r), h.max(r)));
        println!(
            "| {schema} | {} | {} | {:.3} | {low:.3} .. {high:.3} |",
            stream.messages,
            stream.uncompressed,
            stream.ratio()
        );
    }
    Ok(())
}
