//! Writing study outputs (with errors that name the path).

use std::path::Path;

use crate::error::{Error, Result};

/// Writes a text file, creating parent directories.
pub fn write_file(path: &Path, text: &str) -> Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| Error::Output {
            path: parent.display().to_string(),
            reason: e.to_string(),
        })?;
    }
    std::fs::write(path, text).map_err(|e| Error::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Writes an SVG document.
pub fn write_svg_file(path: &Path, svg: &str) -> Result<()> {
    write_file(path, svg)
}
