//! Scenario text (family 2 of `properties`): random byte strings, random TOML-like text
//! and mutations of the default scenario: `Scenario::from_toml` and `resolve` return Ok
//! or Err, never panic.

use proptest::prelude::*;

use bridgetwin::scenario::{Scenario, DEFAULT_SCENARIO_TOML};

use super::config;

/// Tokens that replace values in the mutated scenario text.
const TOKENS: [&str; 22] = [
    "-1",
    "0",
    "-0.0",
    "nan",
    "inf",
    "-inf",
    "1e400",
    "1e-300",
    "1e9",
    "5001",
    "18446744073709551616",
    "-9223372036854775809",
    "\"\"",
    "\"x\"",
    "[]",
    "[1, 2]",
    "{}",
    "{ kind = \"modal\", modes = 0 }",
    "true",
    "0.0001",
    "1e-9",
    "3.0e8",
];

/// Byte ranges of the numbers in `line` (a digit or sign followed by number characters).
fn number_spans(line: &str) -> Vec<(usize, usize)> {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_word = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts && !after_word {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_digit() || b".eE+-_".contains(&bytes[j])) {
                j += 1;
            }
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Duplicate(usize),
    Swap(usize, usize),
    /// Replace the n-th number of the line (or the value after `=`) by a token.
    Number(usize, usize, usize),
    Insert(usize, String),
    Truncate(usize),
}

fn mutation_strategy() -> impl Strategy<Value = Mutation> {
    let any_line = any::<usize>();
    prop_oneof![
        1 => any_line.prop_map(Mutation::Delete),
        1 => any_line.prop_map(Mutation::Duplicate),
        1 => (any_line, any_line).prop_map(|(a, b)| Mutation::Swap(a, b)),
        3 => (any_line, any::<usize>(), 0..TOKENS.len())
            .prop_map(|(l, n, t)| Mutation::Number(l, n, t)),
        1 => (any_line, toml_line_strategy()).prop_map(|(l, s)| Mutation::Insert(l, s)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, mutations: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for m in mutations {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let n = lines.len();
        match m {
            Mutation::Delete(i) => {
                lines.remove(i % n);
            }
            Mutation::Duplicate(i) => {
                let line = lines[i % n].clone();
                lines.insert(i % n, line);
            }
            Mutation::Swap(a, b) => lines.swap(a % n, b % n),
            Mutation::Number(i, k, t) => {
                // Prefer lines that hold numbers: scan from line i.
                let Some(l) = (0..n)
                    .map(|d| (i % n + d) % n)
                    .find(|&l| !number_spans(&lines[l]).is_empty() || lines[l].contains('='))
                else {
                    continue;
                };
                let spans = number_spans(&lines[l]);
                let token = TOKENS[*t];
                lines[l] = if spans.is_empty() {
                    let eq = lines[l].find('=').unwrap();
                    format!("{}= {token}", &lines[l][..eq])
                } else {
                    let (a, b) = spans[k % spans.len()];
                    format!("{}{token}{}", &lines[l][..a], &lines[l][b..])
                };
            }
            Mutation::Insert(i, s) => lines.insert(i % (n + 1), s.clone()),
            Mutation::Truncate(at) => {
                let mut joined = lines.join("\n");
                let mut cut = at % (joined.len() + 1);
                while !joined.is_char_boundary(cut) {
                    cut -= 1;
                }
                joined.truncate(cut);
                lines = joined.lines().map(str::to_string).collect();
            }
        }
    }
    lines.join("\n")
}

const SECTIONS: [&str; 9] = [
    "[bridge]",
    "[solver]",
    "[road]",
    "[output]",
    "[[vehicles]]",
    "[[sensors]]",
    "[[wim_stations]]",
    "[bridge.model]",
    "[[bridge.stiffness_regions]]",
];

const KEYS: [&str; 30] = [
    "seed",
    "start_time",
    "duration_s",
    "span_m",
    "flexural_rigidity_n_m2",
    "mass_per_length_kg_m",
    "damping_ratio",
    "model",
    "kind",
    "nodes",
    "elements",
    "modes",
    "dt_s",
    "contact",
    "profile",
    "approach_m",
    "exit_m",
    "id",
    "speed_m_s",
    "entry_time_s",
    "position_m",
    "rate_hz",
    "noise_density",
    "gauge_depth_m",
    "layout",
    "block_samples",
    "axle_load_rate_hz",
    "bridge_state_rate_hz",
    "start_m",
    "ei_factor",
];

fn value_strategy() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(TOKENS.to_vec()).prop_map(str::to_string),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        any::<i64>().prop_map(|v| v.to_string()),
        prop::sample::select(vec![
            "\"finite_element\"",
            "\"lumped_mass\"",
            "\"modal\"",
            "\"full\"",
            "\"unilateral\"",
            "\"accelerometer\"",
            "\"strain\"",
            "\"block\"",
            "\"1969-12-31T23:59:59Z\"",
            "\"2026-01-01T00:00:00Z\"",
            "{ kind = \"iso8608\", class = \"H\" }",
            "{ kind = \"csv\", path = \"/nonexistent.csv\" }",
            "{ kind = \"lumped_mass\", nodes = 1 }",
            "{ kind = \"half_car\", preset = \"nope\" }",
            "{ kind = \"moving_force\", axle_loads_n = [] }",
        ])
        .prop_map(str::to_string),
        "[a-z0-9\"\\[\\]{}=., -]{0,12}",
    ]
}

fn toml_line_strategy() -> impl Strategy<Value = String> {
    prop_oneof![
        1 => prop::sample::select(SECTIONS.to_vec()).prop_map(str::to_string),
        3 => (prop::sample::select(KEYS.to_vec()), value_strategy())
            .prop_map(|(k, v)| format!("{k} = {v}")),
        1 => "[ -~]{0,30}",
    ]
}

/// Parsing and resolving must not panic; whatever they return is fine.
fn parse_and_resolve(text: &str) {
    if let Ok(s) = Scenario::from_toml(text, "fuzz") {
        let _ = s.resolve();
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn random_bytes_as_scenario_text_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        parse_and_resolve(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn random_toml_like_text_never_panics(lines in prop::collection::vec(toml_line_strategy(), 0..40)) {
        parse_and_resolve(&lines.join("\n"));
    }

    #[test]
    fn mutations_of_the_default_scenario_never_panic(
        mutations in prop::collection::vec(mutation_strategy(), 1..5)
    ) {
        parse_and_resolve(&apply(DEFAULT_SCENARIO_TOML, &mutations));
    }
}

#[test]
fn mutation_helpers_change_what_they_should() {
    let text = "span_m = 30.0\nmodel = { kind = \"finite_element\", elements = 30 }";
    assert_eq!(number_spans("position_m = -20.0"), vec![(13, 18)]);
    assert_eq!(number_spans("a2 = 1e-3"), vec![(5, 9)]);
    let m = apply(text, &[Mutation::Number(1, 0, 0)]);
    assert_eq!(
        m,
        "span_m = 30.0\nmodel = { kind = \"finite_element\", elements = -1 }"
    );
    assert_eq!(apply(text, &[Mutation::Delete(0)]).lines().count(), 1);
}
