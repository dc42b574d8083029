//! Finds the system IPOPT with pkg-config and generates bindings of its C interface with bindgen.
//!
//! Bound: the functions, callback types and return-status enum of the plain C API
//! (`IpStdCInterface.h`), and the two functions of the run-time Pardiso loader
//! (`PardisoLoader.h`) that let a program supply its own linear solver. The version found is exported to dependants as `DEP_IPOPT_VERSION`.

use std::env;
use std::path::PathBuf;

const INSTALL_HINT: &str = "On Debian or Ubuntu install them with:\n    \
     apt-get update && apt-get install -y coinor-libipopt-dev pkg-config libclang-dev";

fn main() {
    println!("cargo:rerun-if-changed=wrapper.h");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");

    // Link libipopt alone: it is a shared library that already records its own dependencies
    // (MUMPS, LAPACK, BLAS). The .pc file also lists -llapack -lblas for static links, which
    // would need the unversioned .so links of liblapack-dev and libblas-dev for nothing.
    let library = match pkg_config::Config::new()
        .atleast_version("3.11")
        .cargo_metadata(false)
        .probe("ipopt")
    {
        Ok(library) => library,
        Err(error) => fail(&format!(
            "IPOPT (3.11 or newer, with its C interface) was not found by pkg-config: {error}\n{INSTALL_HINT}"
        )),
    };
    for path in &library.link_paths {
        println!("cargo:rustc-link-search=native={}", path.display());
    }
    println!("cargo:rustc-link-lib=dylib=ipopt");
    println!("cargo:version={}", library.version);

    let mut builder = bindgen::Builder::default()
        .header("wrapper.h")
        .allowlist_function("CreateIpoptProblem|FreeIpoptProblem|AddIpopt(Str|Num|Int)Option")
        .allowlist_function("OpenIpoptOutputFile|SetIpoptProblemScaling|SetIntermediateCallback")
        .allowlist_function("IpoptSolve")
        .allowlist_function("LSL_loadPardisoLib|LSL_isPardisoLoaded")
        .allowlist_type("Eval_.*_CB|Intermediate_CB|IpoptProblem|UserDataPtr|Number|Index|Int|Bool")
        .allowlist_type("ApplicationReturnStatus|AlgorithmMode")
        // C enums arrive as plain integers: constants, so an unknown code can never be UB.
        .constified_enum_module("ApplicationReturnStatus|AlgorithmMode")
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    for path in &library.include_paths {
        builder = builder.clang_arg(format!("-I{}", path.display()));
    }
    for (name, value) in &library.defines {
        builder = builder.clang_arg(match value {
            Some(value) => format!("-D{name}={value}"),
            None => format!("-D{name}"),
        });
    }

    // bindgen panics when it cannot load libclang; turn that into the same clear message.
    let generated =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    let bindings = match generated {
        Ok(Ok(bindings)) => bindings,
        Ok(Err(error)) => fail(&format!(
            "bindgen could not parse IPOPT's C interface header IpStdCInterface.h: {error}\n{INSTALL_HINT}"
        )),
        Err(_) => fail(&format!(
            "bindgen could not run libclang to read IPOPT's header.\n{INSTALL_HINT}"
        )),
    };
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(error) = bindings.write_to_file(out.join("bindings.rs")) {
        fail(&format!("could not write the generated bindings: {error}"));
    }
}

/// Stops the build with one message that says what is missing and how to install it.
fn fail(message: &str) -> ! {
    eprintln!("\nerror: {message}\n");
    println!(
        "cargo:warning={}",
        message.lines().next().unwrap_or(message)
    );
    std::process::exit(1);
}
