//! The documentation's links and the README's length. Every relative link of README.md and
//! docs/*.md must point to a file or folder of the repository, and a `#anchor` to a heading
//! of its Markdown target, so that a chapter moved or renamed breaks the build instead of
//! the reader's click. The README is the five-minute tour: at most 300 lines, the rest
//! belongs in the book under docs/.

use std::path::Path;

use super::markdown::{anchors, book_files, links, shown};

/// The README's most lines: what a newcomer reads in five minutes.
const README_MAX_LINES: usize = 300;

/// Whether `target` leaves the repository's files (a URL or an e-mail address).
fn is_external(target: &str) -> bool {
    target.contains("://") || target.starts_with("mailto:")
}

/// The broken links of the Markdown `text` of the file `file`, one message each naming the
/// file, the line and the target.
fn broken_links(file: &Path, text: &str) -> Vec<String> {
    let dir = file.parent().expect("a file has a folder");
    let mut broken = Vec::new();
    for (line, target) in links(text) {
        if target.is_empty() {
            broken.push(format!("{}:{line}: a link with no target", shown(file)));
            continue;
        }
        if is_external(&target) {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((path, anchor)) => (path, Some(anchor)),
            None => (target.as_str(), None),
        };
        let resolved = if path.is_empty() {
            file.to_path_buf()
        } else {
            dir.join(path)
        };
        if !resolved.exists() {
            broken.push(format!(
                "{}:{line}: {target}: no such file ({})",
                shown(file),
                shown(&resolved)
            ));
            continue;
        }
        if let Some(anchor) = anchor {
            if resolved.extension().is_some_and(|ext| ext == "md") {
                let target_text = if path.is_empty() {
                    text.to_string()
                } else {
                    std::fs::read_to_string(&resolved).expect("a Markdown target is readable")
                };
                if !anchors(&target_text).iter().any(|a| a == anchor) {
                    broken.push(format!(
                        "{}:{line}: {target}: {} has no heading with the anchor #{anchor}",
                        shown(file),
                        shown(&resolved)
                    ));
                }
            }
        }
    }
    broken
}

#[test]
fn every_relative_link_of_the_readme_and_the_book_resolves() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in book_files() {
        let text = std::fs::read_to_string(&file).expect("a book file is readable");
        checked += links(&text).len();
        broken.extend(broken_links(&file, &text));
    }
    // The README and the book link to each other: a count near zero means the link
    // parser stopped finding them, not that all is well.
    assert!(
        checked > 50,
        "only {checked} links found in README.md and docs/*.md"
    );
    assert!(
        broken.is_empty(),
        "{} broken links:\n{}",
        broken.len(),
        broken.join("\n")
    );
}

#[test]
fn the_readme_is_at_most_300_lines() {
    let readme = super::markdown::repo().join("README.md");
    let lines = std::fs::read_to_string(&readme)
        .expect("README.md is readable")
        .lines()
        .count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: move detail into a chapter of docs/ (docs/README.md lists them)"
    );
}

/// The checker itself: a missing file, a missing anchor and a link inside code.
#[test]
fn a_broken_link_and_a_missing_anchor_are_named() {
    let file = super::markdown::repo().join("docs").join("README.md");
    let text = "# Title\n\
                [ok](physics.md) [here](#title) [web](https://example.org)\n\
                [gone](no_such_chapter.md)\n\
                [anchor](physics.md#no-such-section)\n\
                `[code](not_checked.md)`\n";
    let broken = broken_links(&file, text);
    assert_eq!(broken.len(), 2, "{broken:?}");
    assert!(broken[0].starts_with("docs/README.md:3: no_such_chapter.md: no such file"));
    assert!(broken[1].contains("docs/README.md:4: physics.md#no-such-section"));
    assert!(broken[1].contains("no heading with the anchor #no-such-section"));
}
