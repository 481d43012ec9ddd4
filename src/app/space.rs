//! The free space of the file system an output goes to, and the check that refuses a
//! run whose estimate does not fit in it (before anything is written).

use std::path::{Path, PathBuf};

use crate::base::units::bytes_text;
use crate::error::{Error, Result};

/// The environment variable that, when set to a whole number of bytes, replaces the
/// free space every output file system reports: for tests of the refusal, which cannot
/// fill or mount a file system. Read by [`free_space_bytes`] and nowhere else.
pub const FREE_SPACE_OVERRIDE_VAR: &str = "BRIDGETWIN_FREE_SPACE_BYTES";

/// Reports the free bytes of the file system holding a folder; `None`: not known.
pub type FreeSpaceQuery = fn(&Path) -> std::io::Result<Option<u64>>;

/// How a run into files checks the space its output needs.
#[derive(Debug, Clone, Copy)]
pub enum SpaceCheck {
    /// Refuse the run when its estimated bytes exceed what the query reports for the
    /// output's folder (the usual check: [`free_space_bytes`]).
    Refuse(FreeSpaceQuery),
    /// No check (`simulate --skip-space-check`).
    Skip,
}

impl Default for SpaceCheck {
    fn default() -> Self {
        SpaceCheck::Refuse(free_space_bytes)
    }
}

/// Bytes an unprivileged process may still write on the file system holding `folder`
/// (statvfs: available blocks times the fragment size), or [`FREE_SPACE_OVERRIDE_VAR`]
/// when it is set. `None` for a file system that reports no size at all (sysfs, procfs:
/// their free space means nothing; writing there fails on its own terms).
pub fn free_space_bytes(folder: &Path) -> std::io::Result<Option<u64>> {
    if let Ok(text) = std::env::var(FREE_SPACE_OVERRIDE_VAR) {
        return text.trim().parse().map(Some).map_err(|_| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{FREE_SPACE_OVERRIDE_VAR} = {text:?} is not a whole number of bytes"),
            )
        });
    }
    statvfs_free_bytes(folder)
}

/// The statvfs part of [`free_space_bytes`], without the override.
pub fn statvfs_free_bytes(folder: &Path) -> std::io::Result<Option<u64>> {
    let stats = rustix::fs::statvfs(folder)?;
    if stats.f_blocks == 0 {
        return Ok(None);
    }
    Ok(Some(stats.f_bavail.saturating_mul(stats.f_frsize)))
}

/// The folder an output file goes to: its parent, or `.` for a bare file name.
pub fn output_folder(out: &Path) -> PathBuf {
    match out.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Refuses a run of `estimated_bytes` into `out` when `check` says its folder has less
/// free space. A folder the query cannot read is not refused here: creating the file
/// will fail with the reason (a missing folder, a permission).
pub fn check_space(out: &Path, estimated_bytes: u64, check: SpaceCheck) -> Result<()> {
    let SpaceCheck::Refuse(query) = check else {
        return Ok(());
    };
    let folder = output_folder(out);
    let free_bytes = match query(&folder) {
        Ok(Some(free)) => free,
        Ok(None) => return Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::InvalidInput => {
            return Err(Error::Output {
                path: out.display().to_string(),
                reason: e.to_string(),
            })
        }
        Err(_) => return Ok(()),
    };
    if estimated_bytes <= free_bytes {
        return Ok(());
    }
    Err(Error::InsufficientSpace {
        out: out.display().to_string(),
        folder: folder.display().to_string(),
        estimated: bytes_text(estimated_bytes),
        free: bytes_text(free_bytes),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny(_: &Path) -> std::io::Result<Option<u64>> {
        Ok(Some(1000))
    }

    fn unknown(_: &Path) -> std::io::Result<Option<u64>> {
        Ok(None)
    }

    #[test]
    fn a_run_larger_than_the_free_space_is_refused_with_both_figures_and_the_flag() {
        let out = Path::new("some/folder/run.mcap");
        let e = check_space(out, 5_000_000, SpaceCheck::Refuse(tiny)).unwrap_err();
        let text = e.to_string();
        for part in [
            "4.8 MiB",
            "1000 B",
            "some/folder ",
            "--skip-space-check",
            "run.mcap",
        ] {
            assert!(text.contains(part), "{part:?} not in {text}");
        }
        check_space(out, 1000, SpaceCheck::Refuse(tiny)).unwrap();
        check_space(out, u64::MAX, SpaceCheck::Skip).unwrap();
        check_space(out, u64::MAX, SpaceCheck::Refuse(unknown)).unwrap();
    }

    #[test]
    fn a_bare_file_name_is_in_the_current_folder() {
        assert_eq!(output_folder(Path::new("run.mcap")), PathBuf::from("."));
        assert_eq!(
            output_folder(Path::new("/tmp/run.mcap")),
            PathBuf::from("/tmp")
        );
    }

    #[test]
    fn statvfs_of_the_temp_folder_reports_some_free_space_below_its_size() {
        // The real query (the override variable is not set in the test environment;
        // if it is, this checks the override instead, which is what the process uses).
        let dir = std::env::temp_dir();
        let free = statvfs_free_bytes(&dir)
            .unwrap()
            .expect("a sized file system");
        let stats = rustix::fs::statvfs(&dir).unwrap();
        let size = stats.f_blocks * stats.f_frsize;
        assert!(free > 0 && free <= size, "free {free} of {size}");
        // A folder that does not exist is an error, not a figure.
        assert!(statvfs_free_bytes(&dir.join("no/such/folder")).is_err());
        // sysfs reports no size: no figure to refuse a run by.
        if Path::new("/sys/kernel").is_dir() {
            assert_eq!(statvfs_free_bytes(Path::new("/sys/kernel")).unwrap(), None);
        }
    }
}
