//! `bridgetwin verify`.

use anyhow::Result;

use super::VerifyArgs;
use crate::studies::verify::{ladder, CheckRow};

/// Runs the ladder; Ok(false) when a check fails.
pub fn run(args: &VerifyArgs) -> Result<bool> {
    let mut rows: Vec<CheckRow> = Vec::new();
    for group in ladder() {
        if let Some(only) = &args.only {
            if !group.name.contains(only.as_str()) {
                continue;
            }
        }
        rows.extend((group.run)()?);
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        print_table(&rows);
    }
    let failed = rows.iter().filter(|r| !r.pass).count();
    eprintln!("{} passed, {} failed", rows.len() - failed, failed);
    Ok(failed == 0)
}

fn print_table(rows: &[CheckRow]) {
    let width = rows.iter().map(|r| r.check.len()).max().unwrap_or(5).max(5);
    let ref_width = rows
        .iter()
        .map(|r| r.reference.len())
        .max()
        .unwrap_or(9)
        .max(9);
    println!(
        "{:<12} {:<width$} {:<ref_width$} {:>14} {:>14} {:>10} {:>10}  pass",
        "group", "check", "reference", "ref value", "value", "error", "tolerance"
    );
    for r in rows {
        println!(
            "{:<12} {:<width$} {:<ref_width$} {:>14.6e} {:>14.6e} {:>10.2e} {:>10.2e}  {}",
            r.group,
            r.check,
            r.reference,
            r.reference_value,
            r.value,
            r.error,
            r.tolerance,
            if r.pass { "ok" } else { "FAIL" }
        );
    }
}
