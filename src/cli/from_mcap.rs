//! `simulate --from FILE.mcap`: the scenario a run was made from, read back from the run.
//! The `scenario` metadata record holds the resolved scenario (overrides applied); the
//! `scenario.toml` attachment holds the text the user wrote, re-attached as it was so
//! that the re-run's file is byte-identical.

use std::path::Path;

use anyhow::{bail, Result};
use mcap::records::Record;

use crate::input::{read_records, Flow};
use crate::scenario::Scenario;

/// The resolved scenario and the original scenario text stored in a bridgetwin run.
/// Reads records from the start, so a `.partial` file without a summary works too.
pub fn scenario_from_mcap(path: &Path) -> Result<(Scenario, String)> {
    let label = path.display().to_string();
    let (mut resolved, mut original) = (None, None);
    let mut bad_text = None;
    // The input layer's guarded pass: no length in a damaged file can make it allocate
    // more than the file holds, and damage ends the pass instead of aborting it.
    let pass = read_records(path, |record| {
        match record {
            Record::Metadata(m) if m.name == "scenario" => {
                resolved = m.metadata.get("toml").cloned();
            }
            Record::Attachment { header, data, .. } if header.name == "scenario.toml" => {
                match String::from_utf8(data.into_owned()) {
                    Ok(text) => original = Some(text),
                    Err(_) => bad_text = Some("scenario.toml is not UTF-8"),
                }
            }
            // Both records precede the first message: no need to read on.
            Record::Message { .. } => return Ok(Flow::Stop),
            _ => {}
        }
        Ok(Flow::Continue)
    })?;
    if let Some(why) = bad_text {
        bail!("{label}: {why}");
    }
    let Some(resolved) = resolved else {
        if let Some(damage) = pass.damage() {
            bail!("{label}: damaged before its scenario could be read: {damage}");
        }
        bail!("{label}: no `scenario` metadata record (not a bridgetwin run?)");
    };
    if original.is_none() {
        if let Some(damage) = pass.damage() {
            bail!("{label}: damaged before its scenario.toml attachment: {damage}");
        }
    }
    let scenario = Scenario::from_toml(&resolved, &format!("{label} (scenario metadata)"))?;
    Ok((scenario, original.unwrap_or(resolved)))
}
