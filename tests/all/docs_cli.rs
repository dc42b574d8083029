//! The documentation's commands against the command line's own parser (`codesign::cli::Cli`,
//! the one `codesign` parses its arguments with): the reference page docs/guide/cli.md names
//! every flag of every command and no flag a command lacks, and every `codesign` command shown
//! in a `sh` or `console` block of README.md and docs/guide/ parses; the README's solve prints
//! what the README shows.

use crate::support::{codesign_in, root, scratch};
use clap::error::ErrorKind;
use clap::{CommandFactory, Parser};
use codesign::cli::Cli;

/// The text of `## \`codesign NAME\`` in the reference page, up to the next section.
fn section<'a>(page: &'a str, name: &str) -> Option<&'a str> {
    let heading = format!("\n## `codesign {name}`\n");
    let start = page.find(&heading)? + heading.len();
    let end = page[start..]
        .find("\n## ")
        .map_or(page.len(), |end| start + end);
    Some(&page[start..end])
}

/// The long flags (`--name`) a text names, in order.
fn flags(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (at, _) in text.match_indices("--") {
        let name: String = text[at + 2..]
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-')
            .collect();
        let after_word = at == 0 || !text[..at].ends_with(|c: char| c.is_alphanumeric());
        if !name.is_empty() && after_word {
            found.push(name);
        }
    }
    found
}

#[test]
fn the_reference_page_lists_every_flag_of_every_command_and_no_other() {
    let page = std::fs::read_to_string(root().join("docs/guide/cli.md")).unwrap();
    let mut cli = Cli::command();
    cli.build();
    let mut problems = Vec::new();
    let mut commands = 0;
    for command in cli.get_subcommands() {
        let name = command.get_name();
        if command.is_hide_set() || name == "help" {
            continue;
        }
        commands += 1;
        let Some(text) = section(&page, name) else {
            problems.push(format!("no section `codesign {name}`"));
            continue;
        };
        let known: Vec<&str> = command
            .get_arguments()
            .filter(|arg| !arg.is_hide_set())
            .filter_map(|arg| arg.get_long())
            .filter(|long| *long != "help")
            .collect();
        let listed = flags(text);
        for long in &known {
            if !listed.iter().any(|flag| flag == long) {
                problems.push(format!("codesign {name}: --{long} is not listed"));
            }
        }
        // What the section's flag table names must exist (the prose may name other commands').
        let rows: String = text.lines().filter(|l| l.starts_with("| `")).collect();
        for flag in flags(&rows) {
            if !known.contains(&flag.as_str()) {
                problems.push(format!("codesign {name}: --{flag} is listed but no flag"));
            }
        }
    }
    assert!(commands >= 9, "only {commands} commands found");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Splits a shell line into words: whitespace outside quotes separates, quotes group.
fn words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quote, mut any) = (Vec::new(), String::new(), None, false);
    for c in line.chars() {
        match (quote, c) {
            (None, '\'' | '"') => (quote, any) = (Some(c), true),
            (Some(q), _) if c == q => quote = None,
            (None, _) if c.is_whitespace() => {
                if any {
                    words.push(std::mem::take(&mut word));
                }
                any = false;
            }
            _ => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        words.push(word);
    }
    words
}

/// The `codesign` commands of a page's `sh` and `console` blocks, as argument lists (the
/// program's name first): lines joined at a trailing `\`, comments dropped, split at `&&`, `;`
/// and `|`, redirections dropped; `cargo run --release -- ARGS` counts as `codesign ARGS`.
fn shown_commands(page: &str) -> Vec<Vec<String>> {
    let mut commands = Vec::new();
    let mut block: Option<&str> = None;
    let mut pending = String::new();
    for line in page.lines() {
        if let Some(tag) = line.trim_start().strip_prefix("```") {
            block = if block.is_some() {
                None
            } else {
                Some(tag.trim())
            };
            continue;
        }
        let line = match block {
            Some("sh") => line,
            Some("console") => match line.strip_prefix("$ ") {
                Some(command) => command,
                None => continue,
            },
            _ => continue,
        };
        let line = line.split(" #").next().unwrap_or("");
        if let Some(open) = line.trim_end().strip_suffix('\\') {
            pending.push_str(open);
            continue;
        }
        let whole = std::mem::take(&mut pending) + line;
        for part in whole
            .split("&&")
            .flat_map(|p| p.split(';'))
            .flat_map(|p| p.split(" | "))
        {
            let mut args = words(part);
            if let Some(redirect) = args.iter().position(|w| w.starts_with(['>', '<'])) {
                args.truncate(redirect);
            }
            if args.starts_with(&[
                "cargo".into(),
                "run".into(),
                "--release".into(),
                "--".into(),
            ]) {
                args.splice(0..4, ["codesign".to_owned()]);
            }
            if args.first().is_some_and(|program| program == "codesign") {
                commands.push(args);
            }
        }
    }
    commands
}

#[test]
fn every_command_the_readme_and_the_guide_show_parses() {
    let mut pages = vec![root().join("README.md")];
    for entry in std::fs::read_dir(root().join("docs/guide")).unwrap() {
        pages.push(entry.unwrap().path());
    }
    let mut problems = Vec::new();
    let mut checked = 0;
    for page in pages {
        let text = std::fs::read_to_string(&page).unwrap();
        for args in shown_commands(&text) {
            checked += 1;
            if let Err(error) = Cli::try_parse_from(&args) {
                if !matches!(
                    error.kind(),
                    ErrorKind::DisplayHelp | ErrorKind::DisplayVersion
                ) {
                    let name = page.strip_prefix(root()).unwrap().display();
                    problems.push(format!("{name}: {}:\n{error}", args.join(" ")));
                }
            }
        }
    }
    assert!(
        checked >= 15,
        "only {checked} commands found in the pages' sh blocks"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// A printed line without its wall times, which no two runs share.
fn timeless(line: &str) -> &str {
    if line.trim_start().starts_with("solve ") && line.ends_with(" ms)") {
        "solve (times)"
    } else {
        line
    }
}

#[test]
fn the_readme_solve_prints_what_the_readme_shows() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let commands = shown_commands(&readme);
    let solve = commands
        .iter()
        .find(|args| args[1] == "solve")
        .expect("the README shows a solve");
    let start = readme
        .find("```text\n")
        .expect("the README shows its output")
        + 8;
    let shown = &readme[start..start + readme[start..].find("```").unwrap()];
    let dir = scratch("readme-solve");
    let args: Vec<&str> = solve[1..].iter().map(String::as_str).collect();
    let output = codesign_in(&dir, &args);
    assert!(output.status.success(), "{output:?}");
    let printed = String::from_utf8(output.stdout).unwrap();
    let printed: Vec<&str> = printed.lines().map(timeless).collect();
    let shown: Vec<&str> = shown.lines().map(timeless).collect();
    assert_eq!(printed, shown);
    assert!(dir.join("first/poses.svg").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_command_scanner_reads_shell_as_written() {
    let page = "```sh\ncodesign solve --payload 1 \\\n    --out a.json > log  # note\n\
                cargo run --release -- task && codesign task --urdf | head\n\
                echo codesign\n```\n```console\n$ codesign check\noutput\n```\n";
    let shown: Vec<String> = shown_commands(page).iter().map(|c| c.join(" ")).collect();
    assert_eq!(
        shown,
        [
            "codesign solve --payload 1 --out a.json",
            "codesign task",
            "codesign task --urdf",
            "codesign check"
        ]
    );
    assert_eq!(words(r#"a "b c" 'd'"#), ["a", "b c", "d"]);
    assert_eq!(
        flags("`--ratios R1,R2` and --out, not a--b"),
        ["ratios", "out"]
    );
    // The parser refuses what the page could get wrong.
    assert!(Cli::try_parse_from(["codesign", "solve", "--no-such-flag"]).is_err());
    assert!(Cli::try_parse_from(["codesign", "solve", "--ratios", "R1,R2"]).is_err());
}
