//! Records the version of the IPOPT library that `ipopt-sys` linked, so that every result file
//! can state which solver produced it (`env!("CODESIGN_IPOPT_VERSION")`), and builds the shim
//! through which IPOPT reaches the crate's LDLᵀ (`src/ldl/shim.c`, see `src/ldl/loader.rs`).

use std::path::PathBuf;

fn main() {
    // ipopt-sys declares `links = "ipopt"` and prints `cargo:version=...`, which cargo hands to
    // this script as DEP_IPOPT_VERSION.
    let version = std::env::var("DEP_IPOPT_VERSION").unwrap_or_else(|_| "unknown".to_owned());
    println!("cargo:rustc-env=CODESIGN_IPOPT_VERSION={version}");
    println!("cargo:rerun-if-env-changed=DEP_IPOPT_VERSION");
    build_shim();
}

/// Compiles `src/ldl/shim.c` into `$OUT_DIR/libpardiso.so`, a shared object whose SONAME is the
/// name IPOPT's Pardiso loader asks for; the crate embeds its bytes.
fn build_shim() {
    let source = "src/ldl/shim.c";
    println!("cargo:rerun-if-changed={source}");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let target = out.join("libpardiso.so");
    let compiler = cc::Build::new().opt_level(2).pic(true).get_compiler();
    let mut command = compiler.to_command();
    command
        .args([
            "-shared",
            "-Wall",
            "-Werror",
            "-Wl,-soname,libpardiso.so",
            "-o",
        ])
        .arg(&target)
        .arg(source);
    match command.status() {
        Ok(status) if status.success() => {}
        Ok(status) => fail(&format!("{command:?} failed ({status})")),
        Err(error) => fail(&format!(
            "could not run the C compiler {command:?}: {error}"
        )),
    }
}

/// Stops the build with one clear message.
fn fail(message: &str) -> ! {
    eprintln!("\nerror: building the LDL shim: {message}\n");
    std::process::exit(1);
}
