//! `codesign table`: the paper's table rebuilt from result files (e.g. runs split across machines).

use crate::report::files::{write_atomic, write_json};
use crate::report::table::{build_table, read_result_file};
use std::path::PathBuf;

/// Flags of `codesign table`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Result files of `solve`, `optimize` and `capacity` (JSON).
    #[arg(required = true, value_name = "FILES")]
    files: Vec<PathBuf>,
    /// Write the Markdown table here (and its JSON beside it, .json); default: print it.
    #[arg(long, value_name = "FILE.md")]
    out: Option<PathBuf>,
}

/// Reads the files, builds the table, writes or prints it.
pub fn run(args: &Args) -> Result<(), String> {
    let files = args
        .files
        .iter()
        .map(|path| read_result_file(path))
        .collect::<Result<Vec<_>, _>>()?;
    let table = build_table(&files, Vec::new());
    match &args.out {
        Some(path) => {
            write_atomic(path, table.to_markdown().as_bytes())?;
            write_json(&path.with_extension("json"), &table)?;
            say!(
                "table written to {} and {}",
                path.display(),
                path.with_extension("json").display()
            );
        }
        None => say_raw!("{}", table.to_markdown()),
    }
    Ok(())
}
