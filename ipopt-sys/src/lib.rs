//! Raw bindings to IPOPT's C interface (`IpStdCInterface.h`) and its Pardiso loader
//! (`PardisoLoader.h`), generated at build time by bindgen
//! against the library that pkg-config finds (Debian: `coinor-libipopt-dev`).
//!
//! Everything here is `unsafe` and mirrors the C header one to one; the `codesign` crate wraps it
//! in a safe API. The version of the library found is passed to dependants' build scripts as
//! `DEP_IPOPT_VERSION`.

#![allow(non_upper_case_globals, non_camel_case_types, non_snake_case)]

include!(concat!(env!("OUT_DIR"), "/bindings.rs"));
