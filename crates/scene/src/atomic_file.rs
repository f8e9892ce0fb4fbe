//! Writes a file all at once: into a temporary file beside it, then renamed over it.
//!
//! Invariant: a reader never sees a partial file at `path`, and a failed write leaves no
//! temporary file behind and any previous file at `path` untouched.

use crate::error::SceneError;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A temporary path in the directory of `path`, unique within this process.
fn temporary_path(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

/// Writes `bytes` to `path` atomically (temporary file in the same directory + rename).
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    let temporary = temporary_path(path);
    let result = std::fs::File::create(&temporary)
        .and_then(|mut file| {
            file.write_all(bytes)?;
            file.sync_all()
        })
        .and_then(|()| std::fs::rename(&temporary, path));
    result.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        SceneError::io("write", path, e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_leaves_no_file() {
        let dir = std::env::temp_dir().join(format!("aograph-atomic-{}", std::process::id()));
        let missing_dir = dir.join("does-not-exist").join("out.bin");
        let err = write_atomically(&missing_dir, b"x").unwrap_err();
        assert!(err.to_string().contains("out.bin"), "{err}");
        assert!(!missing_dir.exists());
    }
}
