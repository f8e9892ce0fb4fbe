//! A private runtime directory for the graphics driver when the environment has none.
//!
//! On a machine without a display session (a server, CI, an SSH login) `XDG_RUNTIME_DIR` is
//! unset, and the Vulkan loader's window-system probe (libwayland) prints "error:
//! XDG_RUNTIME_DIR is invalid or not set in the environment" once per instance, twice per
//! bench run, although nothing is wrong and aograph opens no window there. Giving the process
//! a private directory (mode 0700, as the XDG spec asks) before any device is created keeps
//! that line away from the user without filtering anything the driver says: a real error
//! still reaches stderr. Invariant: an existing, valid `XDG_RUNTIME_DIR` is never changed.

use std::path::{Path, PathBuf};

/// The directory used when the environment has none: per user, under the system temp dir.
fn private_dir() -> PathBuf {
    let user = std::env::var("USER").unwrap_or_else(|_| "user".into());
    std::env::temp_dir().join(format!("aograph-runtime-{user}"))
}

/// Sets `XDG_RUNTIME_DIR` to a private 0700 directory when it is unset or not a directory.
/// Must run before any thread starts (it changes the process environment). Leaves the
/// environment as it is when the directory cannot be made.
pub fn ensure_runtime_dir() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| Path::new(&d).is_dir()) {
        return;
    }
    let dir = private_dir();
    let mut builder = std::fs::DirBuilder::new();
    builder.recursive(true);
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    if builder.create(&dir).is_err() || !dir.is_dir() {
        return;
    }
    // SAFETY: called first thing in `main`, before the program starts any thread, so no
    // other thread reads or writes the environment concurrently.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
}
