//! `simulate --from FILE.mcap`: the scenario a run was made from, read back from the run.
//! The `scenario` metadata record holds the resolved scenario (overrides applied); the
//! `scenario.toml` attachment holds the text the user wrote, re-attached as it was so
//! that the re-run's file is byte-identical.

use std::path::Path;

use anyhow::{bail, Context, Result};
use mcap::records::Record;

use crate::scenario::Scenario;

/// The resolved scenario and the original scenario text stored in a bridgetwin run.
/// Reads records from the start, so a `.partial` file without a summary works too.
pub fn scenario_from_mcap(path: &Path) -> Result<(Scenario, String)> {
    let label = path.display().to_string();
    let bytes = std::fs::read(path).with_context(|| format!("reading {label}"))?;
    let reader = mcap::read::LinearReader::new(&bytes)
        .with_context(|| format!("{label}: not an MCAP file"))?;
    let (mut resolved, mut original) = (None, None);
    for record in reader {
        let record = record.with_context(|| format!("{label}: damaged MCAP record"))?;
        match record {
            Record::Metadata(m) if m.name == "scenario" => {
                resolved = m.metadata.get("toml").cloned();
            }
            Record::Attachment { header, data, .. } if header.name == "scenario.toml" => {
                original = Some(
                    String::from_utf8(data.into_owned())
                        .with_context(|| format!("{label}: scenario.toml is not UTF-8"))?,
                );
            }
            // Both records precede the first message: no need to read on.
            Record::Message { .. } | Record::Chunk { .. } => break,
            _ => {}
        }
    }
    let Some(resolved) = resolved else {
        bail!("{label}: no `scenario` metadata record (not a bridgetwin run?)");
    };
    let scenario = Scenario::from_toml(&resolved, &format!("{label} (scenario metadata)"))?;
    Ok((scenario, original.unwrap_or(resolved)))
}
