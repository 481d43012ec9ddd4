//! Reading and writing road profiles as CSV: header, then `x_m,elevation_m` rows.
//!
//! Strict: the header must name both columns (other columns are ignored, in any order),
//! every row must have a finite number in both, x must increase strictly, and there must
//! be at least two rows. Blank lines and lines starting with `#` are skipped. Errors are
//! `Error::File` naming the source and the 1-based line.

use crate::error::{Error, Result};

/// The knots read from a CSV profile.
#[derive(Debug, Clone)]
pub(crate) struct CsvProfile {
    pub x_m: Vec<f64>,
    pub elevation_m: Vec<f64>,
}

fn file_error(source: &str, line: usize, reason: impl std::fmt::Display) -> Error {
    Error::File {
        path: source.to_string(),
        reason: format!("line {line}: {reason}"),
    }
}

fn parse_field(source: &str, line: usize, name: &str, text: &str) -> Result<f64> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| file_error(source, line, format!("{name} = `{text}` is not a number")))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(file_error(
            source,
            line,
            format!("{name} = {value} is not finite"),
        ))
    }
}

/// Parses CSV `text`; `source` names it in errors (the file path).
pub(crate) fn parse(text: &str, source: &str) -> Result<CsvProfile> {
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = rows
        .next()
        .ok_or_else(|| file_error(source, 1, "empty file: expected a header x_m,elevation_m"))?;
    let columns: Vec<&str> = header.split(',').map(str::trim).collect();
    let column = |name: &str| {
        columns.iter().position(|c| *c == name).ok_or_else(|| {
            file_error(
                source,
                header_line,
                format!(
                    "header has no column `{name}` (found: {}); expected x_m,elevation_m",
                    columns.join(", ")
                ),
            )
        })
    };
    let (ix, iz) = (column("x_m")?, column("elevation_m")?);
    let mut profile = CsvProfile {
        x_m: Vec::new(),
        elevation_m: Vec::new(),
    };
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').collect();
        if fields.len() != columns.len() {
            return Err(file_error(
                source,
                line,
                format!(
                    "expected {} fields as in the header, found {}",
                    columns.len(),
                    fields.len()
                ),
            ));
        }
        let x = parse_field(source, line, "x_m", fields[ix])?;
        let z = parse_field(source, line, "elevation_m", fields[iz])?;
        if let Some(&prev) = profile.x_m.last() {
            if x <= prev {
                return Err(file_error(
                    source,
                    line,
                    format!(
                        "x_m = {x} is not greater than the previous x_m = {prev} \
                         (x must increase strictly)"
                    ),
                ));
            }
        }
        profile.x_m.push(x);
        profile.elevation_m.push(z);
    }
    if profile.x_m.len() < 2 {
        return Err(Error::File {
            path: source.to_string(),
            reason: format!(
                "{} data row(s); a profile needs at least 2",
                profile.x_m.len()
            ),
        });
    }
    Ok(profile)
}

/// Reads and parses the CSV file at `path`.
pub(crate) fn read(path: &str) -> Result<CsvProfile> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::File {
        path: path.to_string(),
        reason: format!("cannot read road profile: {e}"),
    })?;
    parse(&text, path)
}

/// Writes `x_m,elevation_m` rows; `{}` prints the shortest decimal that reads back to the
/// same f64, so a round trip is exact.
pub(crate) fn write(points: impl Iterator<Item = (f64, f64)>) -> String {
    use std::fmt::Write;
    let mut out = String::from("x_m,elevation_m\n");
    for (x, z) in points {
        // Writing to a String cannot fail.
        let _ = writeln!(out, "{x},{z}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_in_any_order_comments_and_crlf() {
        let text = "# measured\r\nelevation_m, lane, x_m\r\n0.001,1,0\r\n\r\n-0.002,1,0.5\r\n";
        let p = parse(text, "m.csv").unwrap();
        assert_eq!(p.x_m, vec![0.0, 0.5]);
        assert_eq!(p.elevation_m, vec![0.001, -0.002]);
    }

    #[test]
    fn errors_name_source_and_line() {
        let e = parse("x_m,elevation_m\n0,0\n1,abc\n", "p.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "p.csv: line 3: elevation_m = `abc` is not a number"
        );
        let e = parse("x_m,elevation_m\n0,0\n1,2,3\n", "p.csv").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("p.csv: line 3: expected 2 fields"),
            "{e}"
        );
        let e = parse("x_m,elevation_m\n0,0\n", "p.csv").unwrap_err();
        assert!(e.to_string().contains("at least 2"), "{e}");
        let e = parse("", "p.csv").unwrap_err();
        assert!(
            e.to_string().starts_with("p.csv: line 1: empty file"),
            "{e}"
        );
    }
}
