//! Figures the README and the book state that the code determines, compared with the code:
//! the size of the verification ladder ("N rows in M groups", "groups `girder_*`: N rows")
//! against `bridgetwin verify --json`, and the default run's message count and size ("the
//! default run writes N messages in X MiB") against a fresh run read by `inspect --json`.
//! A stale figure fails naming the file, the line, what it says and what the code gives.
//! Every kind of statement must appear at least once, so that rewording one away cannot
//! leave this test checking nothing.

use std::collections::BTreeMap;
use std::process::Command;

use super::common::BIN;
use super::markdown::{book_files, shown};

/// One file's text with its line breaks made spaces (statements wrap across lines), and
/// where each line starts, to name a statement's line.
struct Flat {
    name: String,
    text: String,
    line_starts: Vec<usize>,
}

impl Flat {
    fn new(name: String, raw: &str) -> Flat {
        let mut line_starts = vec![0];
        line_starts.extend(raw.match_indices('\n').map(|(at, _)| at + 1));
        Flat {
            name,
            text: raw.replace('\n', " "),
            line_starts,
        }
    }

    fn line_of(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= offset)
    }
}

fn flat_book() -> Vec<Flat> {
    book_files()
        .into_iter()
        .map(|path| {
            let raw = std::fs::read_to_string(&path).expect("a book file is readable");
            Flat::new(shown(&path), &raw)
        })
        .collect()
}

/// The number written just before `end` in `text` (digits, thousands separated by single
/// spaces as the book writes them: "37 216"), if any.
fn number_before(text: &str, end: usize) -> Option<u64> {
    let head = text[..end].trim_end();
    let digits: String = head
        .chars()
        .rev()
        .take_while(|c| c.is_ascii_digit() || *c == ' ')
        .collect::<String>()
        .chars()
        .rev()
        .collect();
    let digits = digits.trim_start();
    // A group after a space must have three digits ("37 216"), else the space ends it.
    let mut groups: Vec<&str> = digits.split(' ').collect();
    while groups.len() > 1 && groups[1..].iter().any(|g| g.len() != 3) {
        groups.remove(0);
    }
    groups.concat().parse().ok()
}

/// The number that starts `text` (after spaces), and the rest.
fn number_after(text: &str) -> Option<(u64, &str)> {
    let text = text.trim_start();
    let end = text
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(text.len());
    Some((text[..end].parse().ok()?, &text[end..]))
}

/// What the book states, with where.
#[derive(Debug)]
struct Statement {
    place: String,
    said: String,
}

/// "N rows in M groups": (N, M) and where.
fn ladder_totals(book: &[Flat]) -> Vec<(Statement, u64, u64)> {
    let mut found = Vec::new();
    for file in book {
        for (at, marker) in file.text.match_indices(" rows in ") {
            let (Some(rows), Some((groups, rest))) = (
                number_before(&file.text, at),
                number_after(&file.text[at + marker.len()..]),
            ) else {
                continue;
            };
            if !rest.starts_with(" groups") {
                continue;
            }
            found.push((
                Statement {
                    place: format!("{}:{}", file.name, file.line_of(at)),
                    said: format!("{rows} rows in {groups} groups"),
                },
                rows,
                groups,
            ));
        }
    }
    found
}

/// "groups `PREFIX*`: N rows": (PREFIX, N) and where.
fn ladder_subsets(book: &[Flat]) -> Vec<(Statement, String, u64)> {
    let mut found = Vec::new();
    for file in book {
        let lower = file.text.to_lowercase();
        for (at, marker) in lower.match_indices("groups `") {
            let after = &file.text[at + marker.len()..];
            let Some(close) = after.find('`') else {
                continue;
            };
            let Some(prefix) = after[..close].strip_suffix('*') else {
                continue;
            };
            let Some(tail) = after[close + 1..]
                .strip_prefix(':')
                .or_else(|| after[close + 1..].strip_prefix(';'))
            else {
                continue;
            };
            let Some((rows, rest)) = number_after(tail) else {
                continue;
            };
            if !rest.starts_with(" rows") {
                continue;
            }
            found.push((
                Statement {
                    place: format!("{}:{}", file.name, file.line_of(at)),
                    said: format!("groups `{prefix}*`: {rows} rows"),
                },
                prefix.to_string(),
                rows,
            ));
        }
    }
    found
}

/// "the default run writes N messages in X MiB": (N, X as written) and where.
fn default_run_size(book: &[Flat]) -> Vec<(Statement, u64, String)> {
    let mut found = Vec::new();
    for file in book {
        let lower = file.text.to_lowercase();
        for (at, marker) in lower.match_indices("the default run writes ") {
            let after = &file.text[at + marker.len()..];
            let Some(end) = after.find(" messages in ") else {
                continue;
            };
            let Some(messages) = number_before(after, end) else {
                continue;
            };
            let size: String = after[end + " messages in ".len()..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            found.push((
                Statement {
                    place: format!("{}:{}", file.name, file.line_of(at)),
                    said: format!("{messages} messages in {size} MiB"),
                },
                messages,
                size,
            ));
        }
    }
    found
}

/// The row count of every group of `bridgetwin verify --json`.
fn ladder_rows() -> BTreeMap<String, u64> {
    let output = Command::new(BIN)
        .args(["verify", "--json"])
        .output()
        .expect("bridgetwin verify runs");
    assert!(
        output.status.success(),
        "bridgetwin verify --json failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let rows: Vec<serde_json::Value> =
        serde_json::from_slice(&output.stdout).expect("verify --json is a JSON array");
    let mut groups = BTreeMap::new();
    for row in rows {
        let group = row["group"].as_str().expect("a row names its group");
        *groups.entry(group.to_string()).or_insert(0) += 1;
    }
    groups
}

/// The stale statements among `totals` and `subsets`, against the ladder `groups`.
fn ladder_mismatches(
    totals: &[(Statement, u64, u64)],
    subsets: &[(Statement, String, u64)],
    groups: &BTreeMap<String, u64>,
) -> Vec<String> {
    let rows: u64 = groups.values().sum();
    let mut wrong = Vec::new();
    for (statement, said_rows, said_groups) in totals {
        if (*said_rows, *said_groups) != (rows, groups.len() as u64) {
            wrong.push(format!(
                "{} says {}; `bridgetwin verify --json` has {rows} rows in {} groups",
                statement.place,
                statement.said,
                groups.len()
            ));
        }
    }
    for (statement, prefix, said_rows) in subsets {
        let actual: u64 = groups
            .iter()
            .filter(|(name, _)| name.starts_with(prefix.as_str()))
            .map(|(_, n)| n)
            .sum();
        if *said_rows != actual {
            wrong.push(format!(
                "{} says {}; `bridgetwin verify --json` has {actual} rows in the groups `{prefix}*`",
                statement.place, statement.said
            ));
        }
    }
    wrong
}

#[test]
fn the_stated_size_of_the_verification_ladder_is_the_ladders() {
    let book = flat_book();
    let totals = ladder_totals(&book);
    let subsets = ladder_subsets(&book);
    assert!(
        !totals.is_empty() && !subsets.is_empty(),
        "no statement of the form \"N rows in M groups\" ({}) or \"groups `girder_*`: N rows\" ({}) left in README.md and docs/*.md: reword this test with them",
        totals.len(),
        subsets.len()
    );
    let wrong = ladder_mismatches(&totals, &subsets, &ladder_rows());
    assert!(wrong.is_empty(), "stale figures:\n{}", wrong.join("\n"));
}

#[test]
fn the_stated_size_of_the_default_run_is_a_fresh_runs() {
    let book = flat_book();
    let statements = default_run_size(&book);
    assert!(
        !statements.is_empty(),
        "no statement \"the default run writes N messages in X MiB\" in README.md and docs/*.md"
    );
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("default.mcap");
    let run = Command::new(BIN)
        .args(["simulate", "--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("bridgetwin simulate runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let inspect = Command::new(BIN)
        .args(["inspect", "--json"])
        .arg(&out)
        .output()
        .expect("bridgetwin inspect runs");
    assert!(
        inspect.status.success(),
        "{}",
        String::from_utf8_lossy(&inspect.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&inspect.stdout).expect("inspect --json is JSON");
    let messages = summary["message_count"].as_u64().expect("message_count");
    let bytes = summary["file_size_bytes"]
        .as_u64()
        .expect("file_size_bytes");
    let wrong: Vec<String> = statements
        .iter()
        .filter_map(|(statement, said_messages, said_mib)| {
            // The size as stated, to the digits it is given with.
            let decimals = said_mib.split_once('.').map_or(0, |(_, d)| d.len());
            let mib = format!("{:.*}", decimals, bytes as f64 / 1_048_576.0);
            (*said_messages != messages || *said_mib != mib).then(|| {
                format!(
                    "{} says {}; the default run writes {messages} messages in {mib} MiB ({bytes} B)",
                    statement.place, statement.said
                )
            })
        })
        .collect();
    assert!(wrong.is_empty(), "stale figures:\n{}", wrong.join("\n"));
}

/// The parsers and the comparison on made-up text: a stale count is named with its line.
#[test]
fn a_stale_count_is_named_with_its_line() {
    let book = vec![Flat::new(
        "made-up.md".to_string(),
        "intro text\n(244 rows\nin 18 groups) and groups `girder_*`: 86 rows.\n\
         the default run writes 37 117 messages in 1.4 MiB\n",
    )];
    let totals = ladder_totals(&book);
    let subsets = ladder_subsets(&book);
    assert_eq!((totals[0].1, totals[0].2), (244, 18));
    assert_eq!(totals[0].0.place, "made-up.md:2");
    assert_eq!((subsets[0].1.as_str(), subsets[0].2), ("girder_", 86));
    let sizes = default_run_size(&book);
    assert_eq!((sizes[0].1, sizes[0].2.as_str()), (37_117, "1.4"));
    let groups = BTreeMap::from([
        ("girder_frequencies".to_string(), 80),
        ("girder_statics".to_string(), 6),
        ("frequencies".to_string(), 200),
    ]);
    let wrong = ladder_mismatches(&totals, &subsets, &groups);
    assert_eq!(
        wrong,
        ["made-up.md:2 says 244 rows in 18 groups; `bridgetwin verify --json` has 286 rows in 3 groups"]
    );
}
