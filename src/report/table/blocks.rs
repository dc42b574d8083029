//! The table's text as blocks (headings, paragraphs, notes, lists, tables), built once and
//! rendered as Markdown (`paper_table.md`) or HTML (`index.html`). Text may hold Markdown's
//! inline `code` and **bold**, which the HTML renders as such.

use codesign_core::text::markup_safe;

/// One block of the table's text.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    /// A heading of level 1 or 2.
    Heading(usize, String),
    /// A paragraph.
    Paragraph(String),
    /// A note set apart (a quote in Markdown).
    Note(String),
    /// A bulleted list, one item a line.
    List(Vec<String>),
    /// A table: its header, then its rows of cells.
    Grid(Vec<String>, Vec<Vec<String>>),
}

impl Block {
    /// A table whose header is `header`.
    pub(super) fn grid(header: &[&str], rows: Vec<Vec<String>>) -> Block {
        Block::Grid(header.iter().map(|&h| h.to_owned()).collect(), rows)
    }

    /// The block in Markdown, without the blank line that separates it from the next.
    fn markdown(&self) -> String {
        match self {
            Block::Heading(level, text) => format!("{} {}", "#".repeat(*level), one_line(text)),
            Block::Paragraph(text) => text.clone(),
            Block::Note(text) => format!("> {text}"),
            Block::List(items) => {
                let lines: Vec<String> = items.iter().map(|item| format!("- {item}")).collect();
                lines.join("\n")
            }
            Block::Grid(header, rows) => {
                let line = |cells: &[String]| {
                    let cells: Vec<String> = cells.iter().map(|c| one_line(c)).collect();
                    format!("| {} |", cells.join(" | "))
                };
                let mut lines = vec![line(header), format!("|{}", "---|".repeat(header.len()))];
                lines.extend(rows.iter().map(|row| line(row)));
                lines.join("\n")
            }
        }
    }

    /// The block in HTML, all text escaped.
    fn html(&self) -> String {
        match self {
            Block::Heading(level, text) => format!("<h{level}>{}</h{level}>", inline(text)),
            Block::Paragraph(text) => format!("<p>{}</p>", inline(text)),
            Block::Note(text) => format!("<blockquote>{}</blockquote>", inline(text)),
            Block::List(items) => {
                let items: Vec<String> = items
                    .iter()
                    .map(|item| format!("<li>{}</li>", inline(item)))
                    .collect();
                format!("<ul>\n{}\n</ul>", items.join("\n"))
            }
            Block::Grid(header, rows) => {
                let row = |cells: &[String], tag: &str| {
                    let cells: Vec<String> = cells
                        .iter()
                        .map(|c| format!("<{tag}>{}</{tag}>", inline(c)))
                        .collect();
                    format!("<tr>{}</tr>", cells.concat())
                };
                let body: Vec<String> = rows.iter().map(|r| row(r, "td")).collect();
                format!(
                    "<table>\n<thead>{}</thead>\n<tbody>\n{}\n</tbody>\n</table>",
                    row(header, "th"),
                    body.join("\n")
                )
            }
        }
    }
}

/// The blocks as Markdown: each separated from the next by a blank line.
pub fn to_markdown(blocks: &[Block]) -> String {
    let parts: Vec<String> = blocks.iter().map(Block::markdown).collect();
    parts.join("\n\n") + "\n"
}

/// The blocks as HTML, one element each.
pub fn to_html(blocks: &[Block]) -> String {
    let parts: Vec<String> = blocks.iter().map(Block::html).collect();
    parts.join("\n") + "\n"
}

/// `text` with the characters HTML reserves escaped, for an element's text or an attribute's
/// value in double quotes, and the control characters written as their escapes
/// ([`markup_safe`]: an escape in a task file's name, `\u{1b}`).
pub fn escape_html(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in markup_safe(text).chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&#39;"),
            c => escaped.push(c),
        }
    }
    escaped
}

/// `text` as HTML: escaped, its `code` spans and **bold** runs marked up as such (a delimiter
/// without its pair is left as it is).
fn inline(text: &str) -> String {
    spans(text, "`", "code", &|plain| {
        spans(plain, "**", "strong", &|plain| escape_html(plain))
    })
}

/// `text` split at `delimiter`: the runs between pairs of it wrapped in `tag` (their text
/// escaped), the rest through `outside`.
fn spans(text: &str, delimiter: &str, tag: &str, outside: &dyn Fn(&str) -> String) -> String {
    let parts: Vec<&str> = text.split(delimiter).collect();
    if parts.len().is_multiple_of(2) {
        return outside(text);
    }
    let marked: Vec<String> = parts
        .iter()
        .enumerate()
        .map(|(i, part)| match i % 2 {
            1 => format!("<{tag}>{}</{tag}>", escape_html(part)),
            _ => outside(part),
        })
        .collect();
    marked.concat()
}

/// `text` kept on one line of Markdown (a heading, a table cell): each control character (a
/// newline in a file's name) written as its escape, `\n`, `\t`, `\u{7}`; a `|` escaped so that
/// it splits no cell.
fn one_line(text: &str) -> String {
    let mut line = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '|' => line.push_str("\\|"),
            c if c.is_control() => line.extend(c.escape_default()),
            c => line.push(c),
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::{escape_html, inline, one_line, to_html, to_markdown, Block};

    fn blocks() -> Vec<Block> {
        vec![
            Block::Heading(1, "Table of a|b".to_owned()),
            Block::Note("With `--ends hold`.".to_owned()),
            Block::grid(
                &["payload", "space"],
                vec![vec!["1 kg".to_owned(), "joint <x> | y".to_owned()]],
            ),
            Block::List(vec!["one.".to_owned(), "two.".to_owned()]),
        ]
    }

    #[test]
    fn markdown_separates_blocks_by_a_blank_line() {
        assert_eq!(
            to_markdown(&blocks()),
            "# Table of a\\|b\n\n> With `--ends hold`.\n\n| payload | space |\n|---|---|\n\
             | 1 kg | joint <x> \\| y |\n\n- one.\n- two.\n"
        );
    }

    #[test]
    fn html_escapes_every_text() {
        let html = to_html(&blocks());
        assert!(html.starts_with("<h1>Table of a|b</h1>\n"), "{html}");
        assert!(html.contains("<blockquote>With <code>--ends hold</code>.</blockquote>"));
        assert!(html.contains("<tr><td>1 kg</td><td>joint &lt;x&gt; | y</td></tr>"));
        assert!(html.contains("<ul>\n<li>one.</li>\n<li>two.</li>\n</ul>"));
    }

    #[test]
    fn inline_marks_up_only_paired_delimiters() {
        assert_eq!(
            inline("**Bold.** `a<b>` & \"c\""),
            "<strong>Bold.</strong> <code>a&lt;b&gt;</code> &amp; &quot;c&quot;"
        );
        assert_eq!(inline("a ` b **c"), "a ` b **c");
        assert_eq!(
            inline("<script>alert('x')</script>"),
            "&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;"
        );
        assert_eq!(escape_html("a&b"), "a&amp;b");
        assert_eq!(escape_html("task\u{1b}[2J.json"), "task\\u{1b}[2J.json");
    }

    #[test]
    fn a_name_or_reason_stays_on_its_line() {
        // Issue 38, item 16: a task file named with a newline broke the table's title.
        assert_eq!(one_line("tasks/a\nb.json"), "tasks/a\\nb.json");
        assert_eq!(one_line("a|b\tc\u{7}"), "a\\|b\\tc\\u{7}");
        assert_eq!(one_line("pick_place é.json"), "pick_place é.json");
        let grid = Block::grid(
            &["why"],
            vec![vec!["line one\n| forged | row |".to_owned()]],
        );
        let text = to_markdown(&[grid]);
        assert_eq!(text.lines().count(), 3, "{text}");
        assert!(!text.contains(" | forged"), "{text}");
    }
}
