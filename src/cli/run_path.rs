//! The file a user names on the command line for an existing run: the file itself, or,
//! for a split run (`[output] split_every_s`), the base name given to `--out`, whose
//! parts are `name-0000.mcap`, `name-0001.mcap`, ...

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use crate::output::existing_parts;

/// What a path on the command line names.
#[derive(Debug)]
pub enum RunPath {
    /// A file that exists.
    File(PathBuf),
    /// The base name of a split run, and its parts in order (at least one).
    Split { base: PathBuf, parts: Vec<PathBuf> },
}

impl RunPath {
    /// Finds what `path` names; the error says what was looked for.
    pub fn find(path: &Path) -> Result<Self> {
        if path.exists() {
            return Ok(Self::File(path.to_path_buf()));
        }
        let parts = existing_parts(path);
        if !parts.is_empty() {
            return Ok(Self::Split {
                base: path.to_path_buf(),
                parts,
            });
        }
        let mut partial = path.as_os_str().to_os_string();
        partial.push(".partial");
        if Path::new(&partial).is_file() {
            bail!(
                "no such file: {} (an unfinished run is kept as {}: pass that name)",
                path.display(),
                Path::new(&partial).display()
            );
        }
        bail!(
            "no such file: {} (nor the parts of a split run, {})",
            path.display(),
            crate::output::part_path(path, 0).display()
        )
    }

    /// The file to read from: the file, or a split run's first part.
    pub fn first(&self) -> &Path {
        match self {
            Self::File(path) => path,
            Self::Split { parts, .. } => &parts[0],
        }
    }

    /// For a split run, the line that says which parts exist and which one is read.
    pub fn note(&self) -> Option<String> {
        let Self::Split { base, parts } = self else {
            return None;
        };
        let list = match parts.as_slice() {
            [one] => one.display().to_string(),
            [first, .., last] => format!("{} .. {}", first.display(), last.display()),
            [] => String::new(),
        };
        Some(format!(
            "{} is a split run: {} part{} ({list}); reading {}",
            base.display(),
            parts.len(),
            if parts.len() == 1 { "" } else { "s" },
            parts[0].display()
        ))
    }
}
