//! Any bytes given as a run file: every reader of untrusted runs (`inspect`, the Python
//! package's `read_run`, `simulate --from`) must report the damage or an error, never
//! panic, abort or allocate beyond what the file can hold (libFuzzer's -rss_limit_mb).
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use bridgetwin::cli::{from_mcap, inspect_cmd};
use bridgetwin::input::{read_run, ReadOptions};
use libfuzzer_sys::fuzz_target;

/// The readers take paths: each input goes to one file per process, in memory-backed
/// /dev/shm when there is one.
fn scratch() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = PathBuf::from("/dev/shm");
        let dir = if dir.is_dir() { dir } else { std::env::temp_dir() };
        dir.join(format!("bridgetwin-fuzz-{}.mcap", std::process::id()))
    })
}

fuzz_target!(|data: &[u8]| {
    let path = scratch();
    std::fs::write(path, data).expect("the scratch file is writable");
    let _ = inspect_cmd::inspect(path);
    let _ = read_run(std::slice::from_ref(path), &ReadOptions::default());
    let _ = from_mcap::scenario_from_mcap(path);
});
