//! `codesign table`: the paper's table rebuilt from result files (e.g. runs split across machines).

use super::store_hints::check_output;
use crate::report::table::{build_table, check_results, read_result_file};
use crate::store::document::write_document;
use crate::store::files::write_atomic;
use std::path::{Path, PathBuf};

/// Flags of `codesign table`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Result files of `solve`, `optimize` and `capacity` (JSON).
    #[arg(required = true, value_name = "FILES")]
    files: Vec<PathBuf>,
    /// Write the Markdown table here and its JSON beside it (`T.md` gives `T.json`, any other
    /// name `NAME.json` appended); default: print it. Symbolic links are followed; an input
    /// file, a folder, a special file or a file the user may not write is refused.
    #[arg(long, value_name = "FILE.md")]
    out: Option<PathBuf>,
}

/// Reads the files, builds the table, writes or prints it.
pub fn run(args: &Args) -> Result<(), String> {
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
