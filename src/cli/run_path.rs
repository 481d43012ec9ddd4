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
        // A `.partial` name is no split run's base: `day.mcap.partial` of a split run is
        // `day-0000.mcap.partial`, not the part name built from it (`day.mcap-0000.partial`).
        if let Some(base) = path.to_str().and_then(|p| p.strip_suffix(".partial")) {
            match existing_parts(Path::new(base)).last() {
                Some(last) => bail!(
                    "no such file: {} ({base} is a split run: pass {base} or a part's name, \
                     such as {})",
                    path.display(),
                    last.display()
                ),
                None => bail!("no such file: {}", path.display()),
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A split run's unfinished part is `day-0000.mcap.partial`: asked for
    /// `day.mcap.partial`, the error names that file, not `day.mcap-0000.partial` (the part
    /// name built from `day.mcap.partial` as if `.partial` were the extension).
    #[test]
    fn a_split_runs_partial_is_named_by_its_part() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("day-0000.mcap.partial"), b"x").unwrap();
        let asked = dir.path().join("day.mcap.partial");
        let e = RunPath::find(&asked).unwrap_err().to_string();
        assert!(e.contains("day-0000.mcap.partial"), "{e}");
        assert!(!e.contains("day.mcap-0000"), "{e}");
        // The base name itself finds the part.
        let found = RunPath::find(&dir.path().join("day.mcap")).unwrap();
        assert_eq!(found.first(), dir.path().join("day-0000.mcap.partial"));
        // A missing `.partial` of no run gets no invented part name.
        let e = RunPath::find(&dir.path().join("other.mcap.partial"))
            .unwrap_err()
            .to_string();
        assert!(!e.contains("-0000"), "{e}");
    }
}
