//! Records the version of the IPOPT library that `ipopt-sys` linked, so that every result file
//! can state which solver produced it (`env!("CODESIGN_IPOPT_VERSION")`).

fn main() {
    // ipopt-sys declares `links = "ipopt"` and prints `cargo:version=...`, which cargo hands to
    // this script as DEP_IPOPT_VERSION.
    let version = std::env::var("DEP_IPOPT_VERSION").unwrap_or_else(|_| "unknown".to_owned());
    println!("cargo:rustc-env=CODESIGN_IPOPT_VERSION={version}");
    println!("cargo:rerun-if-env-changed=DEP_IPOPT_VERSION");
}
