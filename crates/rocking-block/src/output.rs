//! How results reach the disk: every file is written to a temporary file in its directory and
//! renamed over the target only when complete, so a failing or interrupted run never leaves a
//! half-written file or replaces a good one; output locations are checked before any work.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The temporary name of `path` while it is written: a hidden file in the same directory (so
/// that the rename is atomic), unique to this process.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Creates the directory of `path` if needed.
///
/// # Errors
/// [`Error::Io`] if it cannot be created.
pub fn ensure_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(io_error(dir))
        }
        _ => Ok(()),
    }
}

/// Writes the file `path` through `write`, which receives a temporary path in the same
/// directory; the temporary file replaces `path` only if `write` succeeds (and is removed
/// otherwise).
///
/// # Errors
/// The error of `write`, or [`Error::Io`] if the directory cannot be created or the rename
/// fails.
pub fn write_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    ensure_parent(path)?;
    let tmp = temp_path(path);
    match write(&tmp) {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|source| {
            let _ = std::fs::remove_file(&tmp);
            Error::Io {
                path: path.to_path_buf(),
                source,
            }
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to `path` atomically (see [`write_with`]).
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn write_atomic(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_with(path, |tmp| {
        std::fs::write(tmp, bytes.as_ref()).map_err(io_error(path))
    })
}

/// Checks that files can be created in `dir` (creating it if needed), before any work.
///
/// # Errors
/// [`Error::Io`] naming the directory.
pub fn check_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    let probe = dir.join(format!(".rocking-block-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(io_error(dir))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Checks that the file `path` can be written (its directory exists or can be created, and
/// takes new files), before any work.
///
/// # Errors
/// [`Error::Io`] naming the directory.
pub fn check_file(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => check_dir(dir),
        _ => check_dir(Path::new(".")),
    }
}

/// Whether two paths name the same file (an output that would replace an input).
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failing_writer_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("rb-output-{}", std::process::id()));
        let path = dir.join("a.json");
        write_atomic(&path, "old").unwrap();
        let err = write_with(&path, |tmp| {
            std::fs::write(tmp, "half").unwrap();
            Err(Error::NoOrbit("failed".into()))
        });
        assert!(err.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
        assert_eq!(names.len(), 1, "{names:?}");
        write_atomic(&path, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert!(same_file(&path, &dir.join(".").join("a.json")));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn an_unwritable_directory_is_found_before_work() {
        assert!(check_dir(Path::new("/proc/rocking-block")).is_err());
        assert!(check_file(Path::new("/proc/x/y.json")).is_err());
    }
}
