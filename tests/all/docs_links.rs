//! The documentation's relative links resolve: every `[text](target)` of README.md,
//! CHANGELOG.md, results/README.md, robots/README.md and docs/**/*.md names a file or folder
//! that exists, and its `#anchor`, where it has one into a Markdown page, a heading of that page
//! (as GitHub derives anchors from headings).

use crate::support::root;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// The Markdown pages whose links are checked, relative to the repository.
fn pages() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = [
        "README.md",
        "CHANGELOG.md",
        "results/README.md",
        "robots/README.md",
    ]
    .iter()
    .map(|page| root().join(page))
    .collect();
    let mut folders = vec![root().join("docs")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    pages.sort();
    pages
}

/// The page's lines outside fenced code blocks, each as written and with the text of its inline
/// code spans blanked byte for byte (so that a bracket or parenthesis inside code is never read
/// as a link, and the two have the same byte offsets).
fn prose_lines(text: &str) -> Vec<(String, &str)> {
    let mut fenced = false;
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut in_code = false;
        let mut blanked = String::with_capacity(line.len());
        for c in line.chars() {
            if c == '`' {
                in_code = !in_code;
                blanked.push(c);
            } else if in_code {
                blanked.extend(std::iter::repeat_n('x', c.len_utf8()));
            } else {
                blanked.push(c);
            }
        }
        lines.push((blanked, line));
    }
    lines
}

/// The targets of the inline links on one line (`[text](target)`, images included), as written.
fn link_targets(line: &str, original: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut from = 0;
    while let Some(found) = line[from..].find("](") {
        let start = from + found + 2;
        let Some(length) = line[start..].find(')') else {
            break;
        };
        // The target is read from the original line: code spans in a target are blanked above.
        targets.push(original[start..start + length].trim().to_owned());
        from = start + length;
    }
    targets
}

/// GitHub's anchor of a heading: lower case, every character but letters, digits, `-`, `_`
/// and spaces dropped, spaces as `-`.
fn anchor_of(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown page's headings (outside code blocks), with GitHub's `-1`, `-2`
/// suffixes for repeated ones.
fn anchors(page: &Path) -> HashSet<String> {
    let text = std::fs::read_to_string(page).unwrap();
    let mut seen = HashSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let heading = line.trim_start_matches('#');
        if fenced || heading.len() == line.len() || !heading.starts_with(' ') {
            continue;
        }
        let anchor = anchor_of(heading);
        let mut unique = anchor.clone();
        let mut n = 0;
        while !seen.insert(unique.clone()) {
            n += 1;
            unique = format!("{anchor}-{n}");
        }
    }
    seen
}

/// What is wrong with one link of `page`, if anything.
fn broken(page: &Path, target: &str) -> Option<String> {
    let external = ["http://", "https://", "mailto:"];
    if external.iter().any(|scheme| target.starts_with(scheme)) {
        return None;
    }
    let (path, anchor) = match target.split_once('#') {
        Some((path, anchor)) => (path, Some(anchor)),
        None => (target, None),
    };
    let file = if path.is_empty() {
        page.to_path_buf()
    } else {
        page.parent().unwrap().join(path)
    };
    if !file.exists() {
        return Some(format!("{} does not exist", file.display()));
    }
    match anchor {
        Some(anchor) if file.extension().is_some_and(|e| e == "md") => {
            (!anchors(&file).contains(anchor)).then(|| format!("no heading gives #{anchor}"))
        }
        _ => None,
    }
}

#[test]
fn every_relative_link_of_the_documentation_resolves() {
    let mut problems = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        for (line, original) in prose_lines(&text) {
            for target in link_targets(&line, original) {
                checked += 1;
                if let Some(problem) = broken(&page, &target) {
                    let name = page.strip_prefix(root()).unwrap().display().to_string();
                    problems.push(format!("{name}: ({target}): {problem}"));
                }
            }
        }
    }
    assert!(
        checked > 100,
        "only {checked} links found: is the scanner reading the pages?"
    );
    assert!(
        problems.is_empty(),
        "broken links:\n{}",
        problems.join("\n")
    );
}

#[test]
fn anchors_are_derived_as_github_derives_them() {
    assert_eq!(
        anchor_of(" 17. Transmissions whose ratio changes with the pose"),
        "17-transmissions-whose-ratio-changes-with-the-pose"
    );
    assert_eq!(anchor_of(" `codesign/solve`"), "codesignsolve");
    assert_eq!(
        anchor_of(" 2026-12-04: The paper's formulation again (issue 33)"),
        "2026-12-04-the-papers-formulation-again-issue-33"
    );
    let lines = prose_lines("a [`x(y)ᵀ`](b.md#c) and ![d](e.svg)\n```\n[f](g)\n```");
    assert_eq!(lines.len(), 1);
    let (line, original) = &lines[0];
    assert_eq!(link_targets(line, original), ["b.md#c", "e.svg"]);
    assert_eq!(
        broken(&root().join("README.md"), "docs/model.md#no-such-heading"),
        Some("no heading gives #no-such-heading".to_owned())
    );
    assert_eq!(broken(&root().join("README.md"), "docs/model.md"), None);
    assert!(broken(&root().join("README.md"), "docs/none.md").is_some());
}
