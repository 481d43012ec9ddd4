//! A sweep plan: a base scenario plus a grid and/or random draws over scenario fields
//! named by dotted paths (`vehicles.0.speed_m_s`, `road.profile.class`, `seed`).
//!
//! ```toml
//! base = "base.toml"            # optional; default: the embedded default scenario
//! seed = 1                      # seed of the random draws (not of the runs)
//! [grid]                        # cartesian product over the keys in sorted order
//! "vehicles.0.speed_m_s" = [10.0, 20.0, 30.0]
//! "road.profile.class" = ["A", "B"]
//! [random]
//! draws = 4                     # runs per grid point
//! "bridge.damping_ratio" = { uniform = [0.01, 0.03] }
//! "seed" = { integer = [0, 1000000] }
//! ```
//!
//! The runs are numbered in a fixed order and every random value is drawn from a stream
//! seeded by the plan seed and the run number, so every node of a cluster expands the
//! same plan into the same runs.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use toml::Value;

use crate::base::random::child_rng;
use crate::error::{Error, Result};
use crate::scenario::Scenario;

/// A distribution of one randomly drawn field.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Draw {
    /// Uniform real in [low, high).
    Uniform([f64; 2]),
    /// Normal with [mean, standard deviation].
    Normal([f64; 2]),
    /// Uniform integer in [low, high].
    Integer([i64; 2]),
    /// One of the values, equally likely.
    Choice(Vec<Value>),
}

/// The `[random]` table: draws per grid point and the fields' distributions.
#[derive(Debug, Clone, Default, Deserialize)]
pub struct RandomSection {
    #[serde(default)]
    pub draws: usize,
    #[serde(flatten)]
    pub fields: BTreeMap<String, Draw>,
}

/// The plan file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Base scenario, relative to the plan file.
    pub base: Option<PathBuf>,
    #[serde(default)]
    pub seed: u64,
    #[serde(default)]
    pub grid: BTreeMap<String, Vec<Value>>,
    #[serde(default)]
    pub random: RandomSection,
}

/// One run of the sweep: its id, the values set, and the scenario.
#[derive(Debug, Clone)]
pub struct RunSpec {
    pub index: usize,
    pub id: String,
    /// (dotted path, value as TOML text), in plan order.
    pub parameters: Vec<(String, String)>,
    pub scenario: Scenario,
    /// The scenario as TOML (what a run attaches as `scenario.toml`).
    pub toml: String,
}

/// A plan expanded into its runs, with the base scenario as a TOML table.
#[derive(Debug)]
pub struct Expanded {
    pub runs: Vec<RunSpec>,
    /// Every swept path, grid first (the manifest's parameter columns).
    pub paths: Vec<String>,
}

impl Plan {
    /// Reads a plan file; errors name the file.
    pub fn from_file(path: &Path) -> Result<(Plan, Value)> {
        let label = path.display().to_string();
        let file_error = |reason: String| Error::File {
            path: label.clone(),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(|e| file_error(e.to_string()))?;
        let plan: Plan =
            toml::from_str(&text).map_err(|e| file_error(e.to_string().replace('\n', " ")))?;
        let base = match &plan.base {
            None => Scenario::default_scenario(),
            Some(base) => {
                let base = path.parent().unwrap_or(Path::new("")).join(base);
                Scenario::from_file(&base)?.0
            }
        };
        let table = Value::try_from(&base).map_err(|e| file_error(e.to_string()))?;
        Ok((plan, table))
    }

    /// Every run of the plan, checked: each scenario parses and resolves. Errors name the
    /// plan field (`grid."vehicles.0.speed_m_s"`) and the value.
    pub fn expand(&self, base: &Value) -> Result<Expanded> {
        let grid_points = self.grid.values().try_fold(1usize, |n, values| {
            (!values.is_empty())
                .then(|| n.checked_mul(values.len()))
                .flatten()
        });
        let Some(grid_points) = grid_points else {
            return Err(Error::invalid(
                "grid",
                format!("{:?}", self.grid.keys().collect::<Vec<_>>()),
                "every grid field needs at least one value (and fewer than 2^64 runs in all)",
            ));
        };
        let draws = self.random.draws.max(1);
        if !self.random.fields.is_empty() && self.random.draws == 0 {
            return Err(Error::invalid(
                "random.draws",
                0,
                "must be at least 1 when random fields are given",
            ));
        }
        let total = grid_points.saturating_mul(draws);
        if total > 1_000_000 {
            return Err(Error::invalid("plan", total, "more than 10^6 runs"));
        }
        let runs = (0..total)
            .map(|index| self.run(base, index, draws))
            .collect::<Result<Vec<_>>>()?;
        let paths = self
            .grid
            .keys()
            .chain(self.random.fields.keys())
            .cloned()
            .collect();
        Ok(Expanded { runs, paths })
    }

    /// Run `index`: grid point `index / draws` (keys in sorted order, the first varying
    /// slowest), draw `index % draws`.
    fn run(&self, base: &Value, index: usize, draws: usize) -> Result<RunSpec> {
        let mut table = base.clone();
        let mut parameters = Vec::new();
        let mut rest = index / draws;
        let sizes: Vec<usize> = self.grid.values().map(Vec::len).collect();
        let mut picks = vec![0; sizes.len()];
        for (k, &size) in sizes.iter().enumerate().rev() {
            picks[k] = rest % size;
            rest /= size;
        }
        for ((path, values), pick) in self.grid.iter().zip(picks) {
            let field = format!("grid.\"{path}\"");
            set_path(&mut table, path, values[pick].clone(), &field)?;
            parameters.push((path.clone(), value_text(&values[pick])));
        }
        let mut rng: ChaCha8Rng = child_rng(self.seed, &format!("sweep/run/{index}"));
        for (path, draw) in &self.random.fields {
            let field = format!("random.\"{path}\"");
            let value = sample(draw, &mut rng, &field)?;
            parameters.push((path.clone(), value_text(&value)));
            set_path(&mut table, path, value, &field)?;
        }
        let id = format!("run-{index:06}");
        let toml = toml::to_string(&table)
            .map_err(|e| Error::invalid(id.as_str(), "scenario", e.to_string()))?;
        let scenario = Scenario::from_toml(&toml, &format!("{id} (plan fields {parameters:?})"))?;
        scenario
            .resolve()
            .map_err(|e| in_run(&id, &parameters, e))?;
        Ok(RunSpec {
            index,
            id,
            parameters,
            scenario,
            toml,
        })
    }
}

/// A value as the manifest shows it: strings bare (`A`), everything else as TOML.
fn value_text(value: &Value) -> String {
    match value {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Prefixes an error with the run and the values that produced it.
fn in_run(id: &str, parameters: &[(String, String)], e: Error) -> Error {
    let values: Vec<String> = parameters
        .iter()
        .map(|(p, v)| format!("{p} = {v}"))
        .collect();
    Error::invalid(
        format!("{id} ({})", values.join(", ")),
        "scenario",
        e.to_string(),
    )
}

fn sample(draw: &Draw, rng: &mut ChaCha8Rng, field: &str) -> Result<Value> {
    let bad = |reason: &str| Error::invalid(field, format!("{draw:?}"), reason.to_string());
    Ok(match draw {
        Draw::Uniform([lo, hi]) => {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(bad("needs finite low < high"));
            }
            Value::Float(rng.random_range(*lo..*hi))
        }
        Draw::Normal([mean, sd]) => {
            if !(mean.is_finite() && sd.is_finite() && *sd >= 0.0) {
                return Err(bad("needs a finite mean and a standard deviation >= 0"));
            }
            let z: f64 = rng.sample(rand_distr::StandardNormal);
            Value::Float(mean + sd * z)
        }
        Draw::Integer([lo, hi]) => {
            if lo > hi {
                return Err(bad("needs low <= high"));
            }
            Value::Integer(rng.random_range(*lo..=*hi))
        }
        Draw::Choice(values) => {
            if values.is_empty() {
                return Err(bad("needs at least one value"));
            }
            values[rng.random_range(0..values.len())].clone()
        }
    })
}

/// Sets `path` (`a.b.0.c`: table keys and array indices) in `root` to `value`. The last
/// key may be new (an optional field left at its default); every step before it must
/// exist, so a typo is caught here or by the scenario's unknown-field check.
pub fn set_path(root: &mut Value, path: &str, value: Value, field: &str) -> Result<()> {
    let missing = |what: String| Error::invalid(field, path, what);
    let keys: Vec<&str> = path.split('.').collect();
    let (last, parents) = keys
        .split_last()
        .ok_or_else(|| missing("empty path".into()))?;
    let mut node = root;
    for (depth, key) in parents.iter().enumerate() {
        let at = keys[..=depth].join(".");
        node = match node {
            Value::Table(t) => t
                .get_mut(*key)
                .ok_or_else(|| missing(format!("the scenario has no `{at}`")))?,
            Value::Array(a) => {
                let i: usize = key
                    .parse()
                    .map_err(|_| missing(format!("`{at}`: an array needs an index")))?;
                let len = a.len();
                a.get_mut(i)
                    .ok_or_else(|| missing(format!("`{at}`: index {i} of {len} elements")))?
            }
            _ => return Err(missing(format!("`{at}` is a value, not a table"))),
        };
    }
    match node {
        Value::Table(t) => {
            t.insert((*last).to_string(), value);
        }
        Value::Array(a) => {
            let i: usize = last
                .parse()
                .map_err(|_| missing(format!("`{path}`: an array needs an index")))?;
            let len = a.len();
            *a.get_mut(i)
                .ok_or_else(|| missing(format!("`{path}`: index {i} of {len} elements")))? = value;
        }
        _ => return Err(missing(format!("the parent of `{path}` is a value"))),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(text: &str) -> Plan {
        toml::from_str(text).unwrap()
    }

    fn base() -> Value {
        Value::try_from(Scenario::default_scenario()).unwrap()
    }

    #[test]
    fn grid_is_a_cartesian_product_with_the_first_key_slowest() {
        let p = plan(
            r#"
            [grid]
            "seed" = [1, 2]
            "vehicles.0.speed_m_s" = [10.0, 20.0, 30.0]
            "#,
        );
        let e = p.expand(&base()).unwrap();
        assert_eq!(e.runs.len(), 6);
        assert_eq!(e.runs[4].scenario.seed, 2);
        assert_eq!(e.runs[4].scenario.vehicles[0].speed_m_s, 20.0);
        assert_eq!(e.runs[5].id, "run-000005");
        assert_eq!(e.paths, ["seed", "vehicles.0.speed_m_s"]);
    }

    #[test]
    fn random_draws_are_reproducible_and_in_range() {
        let text = r#"
            seed = 9
            [random]
            draws = 50
            "bridge.damping_ratio" = { uniform = [0.01, 0.03] }
            "seed" = { integer = [0, 5] }
            "road.profile.class" = { choice = ["A", "B"] }
        "#;
        let a = plan(text).expand(&base()).unwrap();
        let b = plan(text).expand(&base()).unwrap();
        for (x, y) in a.runs.iter().zip(&b.runs) {
            assert_eq!(x.toml, y.toml);
            let z = x.scenario.bridge.damping_ratio;
            assert!((0.01..0.03).contains(&z));
            assert!(x.scenario.seed <= 5);
        }
        let distinct: std::collections::BTreeSet<u64> =
            a.runs.iter().map(|r| r.scenario.seed).collect();
        assert!(distinct.len() > 3, "{distinct:?}");
    }

    #[test]
    fn bad_paths_and_types_name_the_plan_field() {
        let cases = [
            (
                r#"[grid]
"vehicles.3.speed_m_s" = [1.0]"#,
                "index 3 of 1",
            ),
            (
                r#"[grid]
"bridge.spann_m" = [1.0]"#,
                "spann_m",
            ),
            (
                r#"[grid]
"nowhere.x" = [1.0]"#,
                "the scenario has no `nowhere`",
            ),
            (
                r#"[grid]
"vehicles.0.speed_m_s" = ["fast"]"#,
                "speed_m_s",
            ),
            (
                r#"[grid]
"bridge.span_m" = [-1.0]"#,
                "bridge.span_m",
            ),
            (
                r#"[grid]
"seed" = []"#,
                "grid",
            ),
        ];
        for (text, needle) in cases {
            let err = plan(text).expand(&base()).unwrap_err().to_string();
            assert!(err.contains(needle), "{text}: {err}");
        }
    }
}
