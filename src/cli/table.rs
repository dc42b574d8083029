//! `codesign table`: the paper's table rebuilt from result files (e.g. runs split across machines),
//! or a reproduction folder's page written again from its table and the plots it holds.

use super::store_hints::check_output;
use crate::experiment::{write_index, Layout};
use crate::report::table::{build_table, check_results, read_result_file, read_table_file};
use crate::store::document::write_document;
use crate::store::files::write_atomic;
use std::path::{Path, PathBuf};

/// Flags of `codesign table`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Result files of `solve`, `optimize` and `capacity` (JSON).
    #[arg(required_unless_present = "page", value_name = "FILES")]
    files: Vec<PathBuf>,
    /// Write the Markdown table here and its JSON beside it (`T.md` gives `T.json`, any other
    /// name `NAME.json` appended); default: print it. Symbolic links are followed; an input
    /// file, a folder, a special file or a file the user may not write is refused.
    #[arg(long, value_name = "FILE.md", conflicts_with = "page")]
    out: Option<PathBuf>,
    /// Instead: write the page `FOLDER/index.html` of a reproduction folder (as `reproduce
    /// --out-dir FOLDER` lays it out) again, from its `paper_table.json` and the plots it
    /// holds, e.g. after this build changed the page; nothing else in it is touched.
    #[arg(long, value_name = "FOLDER", conflicts_with = "files")]
    page: Option<PathBuf>,
}

/// Reads the files, builds the table, writes or prints it.
pub fn run(args: &Args) -> Result<(), String> {
    if let Some(folder) = &args.page {
        return write_page(folder);
    }
    let outputs = match &args.out {
        Some(markdown) => {
            let json = json_beside(markdown);
            let inputs: Vec<(&str, &Path)> =
                args.files.iter().map(|f| ("input", f.as_path())).collect();
            check_output("--out", markdown, &inputs)?;
            check_output("--out (its JSON)", &json, &inputs)?;
            Some((markdown, json))
        }
        None => None,
    };
    let files = args
        .files
        .iter()
        .map(|path| read_result_file(path))
        .collect::<Result<Vec<_>, _>>()?;
    check_results(&args.files, &files)?;
    let table = build_table(&files, Vec::new());
    match outputs {
        Some((markdown, json)) => {
            write_atomic(markdown, table.to_markdown().as_bytes()).map_err(|e| e.to_string())?;
            write_document(&json, &table).map_err(|e| e.to_string())?;
            say!(
                "table written to {} and {}",
                markdown.display(),
                json.display()
            );
        }
        None => say_raw!("{}", table.to_markdown()),
    }
    Ok(())
}

/// Writes the page of the reproduction folder `folder` from its table.
fn write_page(folder: &Path) -> Result<(), String> {
    if !folder.is_dir() {
        return Err(format!("--page {}: no such folder", folder.display()));
    }
    let layout = Layout::new(folder);
    let table = read_table_file(&layout.table_json()).map_err(|e| e.to_string())?;
    write_index(&layout, &table).map_err(|e| e.to_string())?;
    say!("page written to {}", layout.index().display());
    Ok(())
}

/// The JSON file of the table written to `markdown`: `T.md` -> `T.json`, any other name
/// `NAME` -> `NAME.json`, so that the two never coincide.
fn json_beside(markdown: &Path) -> PathBuf {
    if markdown.extension().is_some_and(|e| e == "md") {
        markdown.with_extension("json")
    } else {
        let mut name = markdown.as_os_str().to_owned();
        name.push(".json");
        PathBuf::from(name)
    }
}

#[cfg(test)]
mod tests {
    use super::json_beside;
    use std::path::Path;

    #[test]
    fn the_json_is_named_apart_from_the_markdown() {
        assert_eq!(json_beside(Path::new("a/t.md")), Path::new("a/t.json"));
        assert_eq!(json_beside(Path::new("t.json")), Path::new("t.json.json"));
        assert_eq!(json_beside(Path::new("t")), Path::new("t.json"));
    }
}
