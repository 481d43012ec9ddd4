//! Columns of one topic: what a reader or an in-memory run hands to numpy and pandas, one
//! typed vector per field (no per-message object), built row group by row group.

use std::collections::HashMap;

/// The values of one column, one entry per row (lists: one list per row).
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    F64(Vec<f64>),
    I64(Vec<i64>),
    U32(Vec<u32>),
    I32(Vec<i32>),
    Bool(Vec<bool>),
    /// Strings as codes into `categories` (a pandas Categorical): sensor ids repeat on every
    /// row, and a code costs 4 bytes where a Python string object costs 50.
    Str {
        codes: Vec<u32>,
        categories: Vec<String>,
    },
    /// Row `i` is `values[offsets[i]..offsets[i + 1]]` (`offsets` has rows + 1 entries).
    F64List {
        offsets: Vec<usize>,
        values: Vec<f64>,
    },
    U32List {
        offsets: Vec<usize>,
        values: Vec<u32>,
    },
    StrList {
        offsets: Vec<usize>,
        values: Vec<String>,
    },
}

impl Values {
    /// Rows held.
    pub fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::U32(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::Bool(v) => v.len(),
            Values::Str { codes, .. } => codes.len(),
            Values::F64List { offsets, .. }
            | Values::U32List { offsets, .. }
            | Values::StrList { offsets, .. } => offsets.len().saturating_sub(1),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// An empty column of the same type.
    fn empty_like(&self) -> Values {
        match self {
            Values::F64(_) => Values::F64(Vec::new()),
            Values::I64(_) => Values::I64(Vec::new()),
            Values::U32(_) => Values::U32(Vec::new()),
            Values::I32(_) => Values::I32(Vec::new()),
            Values::Bool(_) => Values::Bool(Vec::new()),
            Values::Str { .. } => Values::Str {
                codes: Vec::new(),
                categories: Vec::new(),
            },
            Values::F64List { .. } => Values::F64List {
                offsets: vec![0],
                values: Vec::new(),
            },
            Values::U32List { .. } => Values::U32List {
                offsets: vec![0],
                values: Vec::new(),
            },
            Values::StrList { .. } => Values::StrList {
                offsets: vec![0],
                values: Vec::new(),
            },
        }
    }

    /// Appends `n` placeholder rows (NaN, 0, false, "", empty lists).
    fn pad(&mut self, n: usize) {
        if n == 0 {
            // No row: no "" category either.
            return;
        }
        match self {
            Values::F64(v) => v.resize(v.len() + n, f64::NAN),
            Values::I64(v) => v.resize(v.len() + n, 0),
            Values::U32(v) => v.resize(v.len() + n, 0),
            Values::I32(v) => v.resize(v.len() + n, 0),
            Values::Bool(v) => v.resize(v.len() + n, false),
            Values::Str { codes, categories } => {
                let code = match categories.iter().position(|c| c.is_empty()) {
                    Some(i) => i,
                    None => {
                        categories.push(String::new());
                        categories.len() - 1
                    }
                };
                codes.resize(codes.len() + n, code as u32);
            }
            Values::F64List { offsets, values } => offsets.resize(offsets.len() + n, values.len()),
            Values::U32List { offsets, values } => offsets.resize(offsets.len() + n, values.len()),
            Values::StrList { offsets, values } => offsets.resize(offsets.len() + n, values.len()),
        }
    }
}

/// One named column; `missing[i]` marks a row without a value (a map key one message
/// lacks, an unset time), `None` when every row has one.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub name: String,
    pub values: Values,
    pub missing: Option<Vec<bool>>,
}

/// The columns of one topic, all of the same length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    pub rows: usize,
    pub columns: Vec<Column>,
}

impl Table {
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The `f64` column `name`, if there is one.
    pub fn f64s(&self, name: &str) -> Option<&[f64]> {
        match &self.column(name)?.values {
            Values::F64(v) => Some(v),
            _ => None,
        }
    }

    /// The `i64` column `name`, if there is one.
    pub fn i64s(&self, name: &str) -> Option<&[i64]> {
        match &self.column(name)?.values {
            Values::I64(v) => Some(v),
            _ => None,
        }
    }

    /// The same columns without rows.
    pub fn empty_like(&self) -> Table {
        Table {
            rows: 0,
            columns: self
                .columns
                .iter()
                .map(|c| Column {
                    name: c.name.clone(),
                    values: c.values.empty_like(),
                    missing: None,
                })
                .collect(),
        }
    }

    /// Adds `time_s`, seconds since `start_ns`, after `log_time_ns`, and spreads list
    /// columns whose rows all have the same length `n > 0` into `n` columns `name.0`, ...
    /// (the deflected shape at the nodes), as `tools/read_run.py` made 2-D arrays of them.
    pub fn finish(&mut self, start_ns: u64) {
        if let Some(Values::I64(log)) = self.column("log_time_ns").map(|c| &c.values) {
            let time_s = log
                .iter()
                .map(|&t| (t as i128 - start_ns as i128) as f64 * 1e-9)
                .collect();
            let at = self
                .columns
                .iter()
                .position(|c| c.name == "log_time_ns")
                .map_or(0, |i| i + 1);
            self.columns.insert(
                at,
                Column {
                    name: "time_s".into(),
                    values: Values::F64(time_s),
                    missing: None,
                },
            );
        }
        let columns = std::mem::take(&mut self.columns);
        for column in columns {
            match spread(&column, self.rows) {
                Some(spread) => self.columns.extend(spread),
                None => self.columns.push(column),
            }
        }
    }
}

/// `name.0`, `name.1`, ... of a number-list column whose rows all hold `n > 0` values.
fn spread(column: &Column, rows: usize) -> Option<Vec<Column>> {
    let Values::F64List { offsets, values } = &column.values else {
        return None;
    };
    let width = offsets.get(1)? - offsets[0];
    let uniform = rows > 0 && width > 0 && offsets.windows(2).all(|w| w[1] - w[0] == width);
    if !uniform || column.missing.is_some() {
        return None;
    }
    Some(
        (0..width)
            .map(|k| Column {
                name: format!("{}.{k}", column.name),
                values: Values::F64(values.iter().skip(k).step_by(width).copied().collect()),
                missing: None,
            })
            .collect(),
    )
}

/// Builds a [`Table`] a group of rows at a time: `rows(n)`, then each field's `n` values
/// (a field set in no row of a group gets `n` missing rows; a field first seen late gets
/// missing rows before), then the next group.
#[derive(Debug, Default)]
pub struct TableBuilder {
    table: Table,
    /// Rows of the current group.
    group: usize,
    /// Whether each column received the current group.
    filled: Vec<bool>,
    /// Code of each string per string column (by column index).
    codes: HashMap<usize, HashMap<String, u32>>,
    /// Where the last column was found: fields come in the same order in every group.
    cursor: usize,
}

impl TableBuilder {
    pub fn rows_so_far(&self) -> usize {
        self.table.rows
    }

    /// Starts a group of `n` rows (closing the previous group).
    pub fn rows(&mut self, n: usize) {
        self.close_group();
        self.group = n;
    }

    /// Closes the last group and returns the table.
    pub fn build(mut self) -> Table {
        self.close_group();
        self.table
    }

    fn close_group(&mut self) {
        let n = self.group;
        for (i, column) in self.table.columns.iter_mut().enumerate() {
            if !self.filled[i] {
                column.values.pad(n);
                let rows = self.table.rows;
                let missing = column.missing.get_or_insert_with(|| vec![false; rows]);
                missing.resize(rows + n, true);
            } else if let Some(missing) = column.missing.as_mut() {
                missing.resize(self.table.rows + n, false);
            }
            self.filled[i] = false;
        }
        self.table.rows += n;
        self.group = 0;
    }

    /// The column `name`, created with `prototype`'s type (and missing earlier rows) when
    /// new; marked as filled for this group.
    fn column(&mut self, name: &str, prototype: fn() -> Values) -> (usize, &mut Values) {
        let columns = &self.table.columns;
        let index = match columns.get(self.cursor).filter(|c| c.name == name) {
            Some(_) => self.cursor,
            None => match columns.iter().position(|c| c.name == name) {
                Some(i) => i,
                None => {
                    let mut values = prototype().empty_like();
                    let rows = self.table.rows;
                    values.pad(rows);
                    self.table.columns.push(Column {
                        name: name.to_string(),
                        values,
                        missing: (rows > 0).then(|| vec![true; rows]),
                    });
                    self.filled.push(false);
                    self.table.columns.len() - 1
                }
            },
        };
        self.cursor = index + 1;
        self.filled[index] = true;
        (index, &mut self.table.columns[index].values)
    }

    /// The current group's values of an `f64` field.
    pub fn f64s(&mut self, name: &str, values: impl IntoIterator<Item = f64>) {
        if let (_, Values::F64(v)) = self.column(name, || Values::F64(Vec::new())) {
            v.extend(values);
        }
    }

    pub fn f64(&mut self, name: &str, value: f64) {
        self.f64s(name, [value]);
    }

    pub fn i64s(&mut self, name: &str, values: impl IntoIterator<Item = i64>) {
        if let (_, Values::I64(v)) = self.column(name, || Values::I64(Vec::new())) {
            v.extend(values);
        }
    }

    pub fn i64(&mut self, name: &str, value: i64) {
        self.i64s(name, [value]);
    }

    /// An `i64` value that may be absent in this row (an unset time): missing then.
    pub fn i64_or_missing(&mut self, name: &str, value: Option<i64>) {
        match value {
            Some(v) => self.i64(name, v),
            None => {
                // Leaving the column unfilled makes the row missing at the group's close.
                let (index, _) = self.column(name, || Values::I64(Vec::new()));
                self.filled[index] = false;
            }
        }
    }

    pub fn u32s(&mut self, name: &str, values: impl IntoIterator<Item = u32>) {
        if let (_, Values::U32(v)) = self.column(name, || Values::U32(Vec::new())) {
            v.extend(values);
        }
    }

    pub fn u32(&mut self, name: &str, value: u32) {
        self.u32s(name, [value]);
    }

    pub fn i32(&mut self, name: &str, value: i32) {
        if let (_, Values::I32(v)) = self.column(name, || Values::I32(Vec::new())) {
            v.push(value);
        }
    }

    pub fn bools(&mut self, name: &str, values: impl IntoIterator<Item = bool>) {
        if let (_, Values::Bool(v)) = self.column(name, || Values::Bool(Vec::new())) {
            v.extend(values);
        }
    }

    pub fn bool(&mut self, name: &str, value: bool) {
        self.bools(name, [value]);
    }

    /// The same string on all `n` rows of the current group.
    pub fn str_repeated(&mut self, name: &str, value: &str, n: usize) {
        let (index, _) = self.column(name, || Values::Str {
            codes: Vec::new(),
            categories: Vec::new(),
        });
        let Values::Str { codes, categories } = &mut self.table.columns[index].values else {
            return;
        };
        let known = self.codes.entry(index).or_default();
        let code = match known.get(value) {
            Some(&code) => code,
            None => {
                // Padding may have added "" as a category before any row held it.
                let code = match categories.iter().position(|c| c == value) {
                    Some(i) => i as u32,
                    None => {
                        categories.push(value.to_string());
                        (categories.len() - 1) as u32
                    }
                };
                known.insert(value.to_string(), code);
                code
            }
        };
        codes.resize(codes.len() + n, code);
    }

    pub fn str(&mut self, name: &str, value: &str) {
        self.str_repeated(name, value, 1);
    }

    /// One list of numbers (one row).
    pub fn f64_list(&mut self, name: &str, list: &[f64]) {
        let prototype = || Values::F64List {
            offsets: vec![0],
            values: Vec::new(),
        };
        if let (_, Values::F64List { offsets, values }) = self.column(name, prototype) {
            values.extend_from_slice(list);
            offsets.push(values.len());
        }
    }

    pub fn u32_list(&mut self, name: &str, list: &[u32]) {
        let prototype = || Values::U32List {
            offsets: vec![0],
            values: Vec::new(),
        };
        if let (_, Values::U32List { offsets, values }) = self.column(name, prototype) {
            values.extend_from_slice(list);
            offsets.push(values.len());
        }
    }

    pub fn str_list(&mut self, name: &str, list: &[String]) {
        let prototype = || Values::StrList {
            offsets: vec![0],
            values: Vec::new(),
        };
        if let (_, Values::StrList { offsets, values }) = self.column(name, prototype) {
            values.extend(list.iter().cloned());
            offsets.push(values.len());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_absent_from_some_rows_is_missing_there() {
        let mut b = TableBuilder::default();
        b.rows(1);
        b.i64("log_time_ns", 10);
        b.f64("parameters.mass_kg", 1.0);
        b.rows(1);
        b.i64("log_time_ns", 20);
        b.f64("parameters.stiffness_n_m", 2.0);
        b.rows(1);
        b.i64("log_time_ns", 30);
        b.i64_or_missing("exit_time_ns", None);
        let mut t = b.build();
        t.finish(10);
        assert_eq!(t.rows, 3);
        assert_eq!(t.f64s("time_s").unwrap(), &[0.0, 10e-9, 20e-9]);
        let mass = t.column("parameters.mass_kg").unwrap();
        assert_eq!(mass.missing.as_deref(), Some(&[false, true, true][..]));
        let stiffness = t.column("parameters.stiffness_n_m").unwrap();
        assert_eq!(stiffness.missing.as_deref(), Some(&[true, false, true][..]));
        let exit = t.column("exit_time_ns").unwrap();
        assert_eq!(exit.missing.as_deref(), Some(&[true, true, true][..]));
        assert!(t.columns.iter().all(|c| c.values.len() == 3));
    }

    #[test]
    fn uniform_lists_spread_into_columns_and_ragged_ones_stay_lists() {
        let mut b = TableBuilder::default();
        for k in 0..3 {
            b.rows(1);
            b.f64_list("deflection_m", &[k as f64, 10.0 + k as f64]);
            b.f64_list("natural_frequency_hz", &vec![3.8; k]);
        }
        let mut t = b.build();
        t.finish(0);
        assert_eq!(t.f64s("deflection_m.0").unwrap(), &[0.0, 1.0, 2.0]);
        assert_eq!(t.f64s("deflection_m.1").unwrap(), &[10.0, 11.0, 12.0]);
        assert!(matches!(
            t.column("natural_frequency_hz").unwrap().values,
            Values::F64List { .. }
        ));
    }

    #[test]
    fn repeated_strings_share_one_code() {
        let mut b = TableBuilder::default();
        b.rows(100);
        b.str_repeated("sensor_id", "A1", 100);
        b.rows(2);
        b.str_repeated("sensor_id", "A1", 2);
        let t = b.build();
        let Values::Str { codes, categories } = &t.column("sensor_id").unwrap().values else {
            panic!("a string column");
        };
        assert_eq!(
            (codes.len(), categories.as_slice()),
            (102, &["A1".to_string()][..])
        );
    }
}
