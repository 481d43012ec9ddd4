//! What the documentation tests read from Markdown: the files of the book, fenced code
//! blocks with their line numbers, links outside code, and headings as GitHub anchors.
//! Written for this repository's Markdown (CommonMark fences of three backticks, inline
//! links), not as a general parser.

use std::path::{Path, PathBuf};

/// The repository's root (the folder of `Cargo.toml`).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every `docs/*.md`, sorted.
pub fn book_files() -> Vec<PathBuf> {
    let root = repo();
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ is readable")
        .map(|entry| entry.expect("a docs/ entry").path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The file's path relative to the repository, for messages.
pub fn shown(path: &Path) -> String {
    path.strip_prefix(repo())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// A fenced code block: its info string (`sh`, `python`, ...), the 1-based line of its
/// opening fence, and its lines with their 1-based line numbers.
#[derive(Debug)]
pub struct Block {
    pub info: String,
    pub fence_line: usize,
    pub lines: Vec<(usize, String)>,
}

/// Every fenced block of `text` (fences of three or more backticks at the line start).
pub fn blocks(text: &str) -> Vec<Block> {
    let mut found = Vec::new();
    let mut open: Option<Block> = None;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let trimmed = line.trim_start();
        match open.take() {
            None => {
                if let Some(info) = trimmed.strip_prefix("```") {
                    open = Some(Block {
                        info: info.trim().to_string(),
                        fence_line: number,
                        lines: Vec::new(),
                    });
                }
            }
            Some(mut block) => {
                if trimmed.starts_with("```") {
                    found.push(block);
                } else {
                    block.lines.push((number, line.to_string()));
                    open = Some(block);
                }
            }
        }
    }
    found
}

/// Whether each line of `text` lies inside a fenced block (fences included).
pub fn in_fence(text: &str) -> Vec<bool> {
    let mut inside = false;
    text.lines()
        .map(|line| {
            if line.trim_start().starts_with("```") {
                inside = !inside;
                true
            } else {
                inside
            }
        })
        .collect()
}

/// `line` with its inline code spans (`...`) blanked, so that links quoted as code are not
/// taken for links.
fn without_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut in_code = false;
    for c in line.chars() {
        if c == '`' {
            in_code = !in_code;
            out.push(' ');
        } else if in_code {
            out.push(' ');
        } else {
            out.push(c);
        }
    }
    out
}

/// The targets of the inline links and images of `text` outside code, with their 1-based
/// line numbers: what stands between `](` and the closing `)`, without a title.
pub fn links(text: &str) -> Vec<(usize, String)> {
    let fenced = in_fence(text);
    let mut found = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        if fenced[index] {
            continue;
        }
        let line = without_code_spans(raw);
        let mut rest = line.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let end = after.find(')').unwrap_or(after.len());
            let target = after[..end].split_whitespace().next().unwrap_or("");
            found.push((index + 1, target.to_string()));
            rest = &after[end..];
        }
        // Reference definitions: `[name]: target`.
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            if let Some(at) = trimmed.find("]: ") {
                let target = trimmed[at + 3..].split_whitespace().next().unwrap_or("");
                found.push((index + 1, target.to_string()));
            }
        }
    }
    found
}

/// GitHub's anchor of a heading's text: lower case, letters, digits, `-` and `_` kept,
/// spaces made hyphens, everything else dropped.
pub fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of every heading of `text` outside code, a repeated one numbered `-1`, `-2`,
/// ... as GitHub numbers them.
pub fn anchors(text: &str) -> Vec<String> {
    let fenced = in_fence(text);
    let mut seen: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let mut found = Vec::new();
    for (index, line) in text.lines().enumerate() {
        if fenced[index] || !line.starts_with('#') {
            continue;
        }
        let heading = line.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        let base = slug(heading);
        let repeats = seen.entry(base.clone()).or_insert(0);
        found.push(if *repeats == 0 {
            base
        } else {
            format!("{base}-{repeats}")
        });
        *repeats += 1;
    }
    found
}

#[test]
fn the_parser_finds_links_blocks_and_anchors() {
    let text = "# The `bridgetwin` book: 3. Part\n\
                See [a](a.md#x) and ![b](figures/b.svg \"title\"), not `[c](c.md)`.\n\
                ```sh\n[d](d.md)\ncargo run\n```\n\
                [e]: e.md\n## Two\n## Two\n";
    let found: Vec<String> = links(text).into_iter().map(|(_, t)| t).collect();
    assert_eq!(found, ["a.md#x", "figures/b.svg", "e.md"]);
    let fenced = blocks(text);
    assert_eq!(fenced.len(), 1);
    assert_eq!(fenced[0].info, "sh");
    assert_eq!(fenced[0].fence_line, 3);
    assert_eq!(fenced[0].lines[1], (5, "cargo run".to_string()));
    assert_eq!(
        anchors(text),
        ["the-bridgetwin-book-3-part", "two", "two-1"]
    );
}
