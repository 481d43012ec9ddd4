//! A measured air temperature record (`time_s,temperature_c`), linearly interpolated.

use std::path::Path;

use crate::error::{Error, Result};

/// The header the file must start with; a required header catches a file with the columns
/// swapped or a first data row that would otherwise be taken as a header.
pub const CSV_HEADER: &str = "time_s,temperature_c";

/// Temperature samples at strictly increasing times, read with a moving cursor so a
/// monotone stream costs O(1) per call.
#[derive(Debug, Clone, PartialEq)]
pub struct TemperatureTable {
    times_s: Vec<f64>,
    temperatures_c: Vec<f64>,
    /// Index of the segment [i, i + 1] used last.
    cursor: usize,
}

impl TemperatureTable {
    /// Reads and parses `path`; errors name the file and the line.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::File {
            path: path.display().to_string(),
            reason: format!("cannot read the temperature CSV (environment.temperature.path): {e}"),
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses CSV text; `origin` (the file name) prefixes errors. Blank lines and lines
    /// starting with `#` are skipped.
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let error = |line: usize, reason: String| Error::File {
            path: origin.to_string(),
            reason: format!("line {line}: {reason}"),
        };
        let mut rows = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        match rows.next() {
            Some((_, header)) if header.replace(' ', "") == CSV_HEADER => {}
            Some((line, header)) => {
                return Err(error(
                    line,
                    format!("header `{header}` must be `{CSV_HEADER}`"),
                ))
            }
            None => {
                return Err(whole_file_error(
                    origin,
                    format!("empty; expected `{CSV_HEADER}`"),
                ))
            }
        }
        let (mut times_s, mut temperatures_c) = (Vec::new(), Vec::new());
        for (line, row) in rows {
            let (t_s, value_c) = parse_row(row).map_err(|reason| error(line, reason))?;
            if let Some(&previous_s) = times_s.last() {
                if t_s <= previous_s {
                    return Err(error(
                        line,
                        format!("time_s = {t_s} must exceed the previous {previous_s}"),
                    ));
                }
            }
            times_s.push(t_s);
            temperatures_c.push(value_c);
        }
        if times_s.is_empty() {
            return Err(whole_file_error(
                origin,
                "no data rows after the header".into(),
            ));
        }
        Ok(Self {
            times_s,
            temperatures_c,
            cursor: 0,
        })
    }

    /// First and last time of the record (s).
    pub fn time_range_s(&self) -> (f64, f64) {
        (self.times_s[0], self.times_s[self.times_s.len() - 1])
    }

    /// Linear interpolation at `t_s`; the first and last values hold outside the record.
    pub fn at(&mut self, t_s: f64) -> f64 {
        let n = self.times_s.len();
        if n == 1 || t_s <= self.times_s[0] {
            return self.temperatures_c[0];
        }
        if t_s >= self.times_s[n - 1] {
            return self.temperatures_c[n - 1];
        }
        if t_s < self.times_s[self.cursor] {
            // A step back in time: search once, then stream forward again.
            self.cursor = self.times_s.partition_point(|&x| x <= t_s) - 1;
        }
        while self.times_s[self.cursor + 1] <= t_s {
            self.cursor += 1;
        }
        let i = self.cursor;
        let (t0, t1) = (self.times_s[i], self.times_s[i + 1]);
        let (v0, v1) = (self.temperatures_c[i], self.temperatures_c[i + 1]);
        v0 + (v1 - v0) * (t_s - t0) / (t1 - t0)
    }
}

/// One `time_s,temperature_c` row; the reason names the column.
fn parse_row(row: &str) -> std::result::Result<(f64, f64), String> {
    let fields: Vec<&str> = row.split(',').map(str::trim).collect();
    let [t, v] = fields.as_slice() else {
        return Err(format!(
            "`{row}` must have 2 columns (time_s,temperature_c), found {}",
            fields.len()
        ));
    };
    Ok((number("time_s", t)?, number("temperature_c", v)?))
}

fn number(column: &str, text: &str) -> std::result::Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) => Err(format!("{column} = {x} must be a finite number")),
        Err(_) => Err(format!("{column} = `{text}` is not a number")),
    }
}

fn whole_file_error(origin: &str, reason: String) -> Error {
    Error::File {
        path: origin.to_string(),
        reason,
    }
}
