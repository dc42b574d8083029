//! Hands this crate's LDLᵀ to IPOPT as its run-time loaded Pardiso library.
//!
//! build.rs compiles `shim.c` into a small shared object (SONAME `libpardiso.so`) that exports the
//! Pardiso entry points and forwards them to function pointers. Its bytes are embedded in the
//! binary; [`install`] writes them to an anonymous file (`memfd_create`), loads it with `dlopen`,
//! binds the pointers to [`pardisoinit`](super::pardiso::pardisoinit) and
//! [`pardiso`](super::pardiso::pardiso), and asks IPOPT's loader to take that very object. No
//! file is written to disk and no search path is involved, so the binary works wherever it is
//! copied, and a real Pardiso on the system is never picked up instead.

use super::pardiso::{pardiso, pardisoinit};
use ipopt_sys as sys;
use std::ffi::{c_char, c_void, CStr, CString};
use std::fmt;
use std::io::Write;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::sync::OnceLock;

/// The shim, built by build.rs.
static SHIM: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/libpardiso.so"));

/// Outcome of the one installation per process.
static INSTALLED: OnceLock<Result<(), InstallError>> = OnceLock::new();

/// Why the LDLᵀ could not be handed to IPOPT; each variant carries the system's message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum InstallError {
    /// Another Pardiso library was loaded into IPOPT first.
    OtherPardiso,
    /// The anonymous file for the shim could not be made or written.
    AnonymousFile(String),
    /// `dlopen` or `dlsym` of the shim failed.
    Dl(String),
    /// IPOPT's loader refused the shim.
    Refused(String),
}

impl fmt::Display for InstallError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InstallError::OtherPardiso => {
                f.write_str("another Pardiso library was loaded into IPOPT before codesign's")
            }
            InstallError::AnonymousFile(why) | InstallError::Dl(why) => f.write_str(why),
            InstallError::Refused(why) => write!(f, "IPOPT did not take the LDL shim: {why}"),
        }
    }
}

impl std::error::Error for InstallError {}

/// Signature of the shim's `codesign_ldl_bind`.
type Bind = unsafe extern "C" fn(
    init: unsafe extern "C" fn(
        *mut *mut c_void,
        *const i32,
        *const i32,
        *mut i32,
        *mut f64,
        *mut i32,
    ),
    solve: unsafe extern "C" fn(
        *mut *mut c_void,
        *const i32,
        *const i32,
        *const i32,
        *const i32,
        *const i32,
        *const f64,
        *const i32,
        *const i32,
        *const i32,
        *const i32,
        *mut i32,
        *const i32,
        *mut f64,
        *mut f64,
        *mut i32,
        *mut f64,
    ),
);

/// Makes IPOPT's `linear_solver = pardiso` use this crate's LDLᵀ. Idempotent and thread-safe;
/// the error says what failed (it is the same on every later call).
pub fn install() -> Result<(), InstallError> {
    INSTALLED.get_or_init(load).clone()
}

fn load() -> Result<(), InstallError> {
    // SAFETY: LSL_isPardisoLoaded only reads IPOPT's loader state.
    if unsafe { sys::LSL_isPardisoLoaded() } != 0 {
        return Err(InstallError::OtherPardiso);
    }
    let file = anonymous_file()?;
    let path = CString::new(format!("/proc/self/fd/{}", file.as_raw_fd()))
        .map_err(|_| InstallError::Dl("the shim's path holds a NUL byte".to_owned()))?;
    // SAFETY: the path names a complete shared object written above; loading runs no code of
    // ours but the shim's (which has no initialisers).
    let library = unsafe { libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
    if library.is_null() {
        return Err(InstallError::Dl(format!(
            "dlopen of the LDL shim failed: {}",
            dl_error()
        )));
    }
    // SAFETY: the shim exports codesign_ldl_bind with the `Bind` signature (shim.c).
    unsafe {
        let symbol = libc::dlsym(library, c"codesign_ldl_bind".as_ptr());
        if symbol.is_null() {
            return Err(InstallError::Dl(format!(
                "the LDL shim has no binder: {}",
                dl_error()
            )));
        }
        let bind: Bind = std::mem::transmute::<*mut c_void, Bind>(symbol);
        bind(pardisoinit, pardiso);
    }
    let mut message = [0 as c_char; 256];
    // SAFETY: the buffer's length is passed; IPOPT's loader dlopens the same path, which resolves
    // to the object loaded above, and keeps it loaded for the life of the process.
    let failed = unsafe {
        sys::LSL_loadPardisoLib(path.as_ptr(), message.as_mut_ptr(), message.len() as i32)
    };
    if failed != 0 {
        // SAFETY: IPOPT writes a NUL-terminated message into the buffer.
        let text = unsafe { CStr::from_ptr(message.as_ptr()) };
        return Err(InstallError::Refused(text.to_string_lossy().into_owned()));
    }
    Ok(())
}

/// An anonymous file holding the shim's bytes.
fn anonymous_file() -> Result<OwnedFd, InstallError> {
    // SAFETY: a NUL-terminated name and valid flags; the descriptor is owned below.
    let fd = unsafe { libc::memfd_create(c"libpardiso.so".as_ptr(), libc::MFD_CLOEXEC) };
    if fd < 0 {
        return Err(InstallError::AnonymousFile(format!(
            "memfd_create failed: {}",
            std::io::Error::last_os_error()
        )));
    }
    // SAFETY: fd is a fresh descriptor that nothing else owns.
    let owned = unsafe { OwnedFd::from_raw_fd(fd) };
    let mut file = std::fs::File::from(owned);
    file.write_all(SHIM).map_err(|e| {
        InstallError::AnonymousFile(format!(
            "cannot write the LDL shim to an anonymous file: {e}"
        ))
    })?;
    Ok(OwnedFd::from(file))
}

fn dl_error() -> String {
    // SAFETY: dlerror returns null or a NUL-terminated string valid until the next dl call.
    unsafe {
        let text = libc::dlerror();
        if text.is_null() {
            "unknown error".to_owned()
        } else {
            CStr::from_ptr(text).to_string_lossy().into_owned()
        }
    }
}
