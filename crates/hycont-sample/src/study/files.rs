//! Count files on disk: written atomically, read and checked before use.

use crate::Error;
use std::path::{Path, PathBuf};

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |e| Error::Io {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

/// The temporary name of `path` while it is written: a hidden file in the same directory (so
/// that the rename is atomic), unique to this process.
#[must_use]
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Whether `path` is a device or a pipe (e.g. `/dev/null`, `/dev/stdout`): written through,
/// never replaced.
#[must_use]
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Creates the directory of `path` if needed.
///
/// # Errors
/// [`Error::Io`] naming the directory.
pub fn ensure_parent(path: &Path) -> Result<(), Error> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => std::fs::create_dir_all(dir).map_err(io(dir)),
        _ => Ok(()),
    }
}

/// Writes the file `path` through `write`, which receives a temporary path in the same
/// directory; the temporary file replaces `path` only if `write` succeeds (and is removed
/// otherwise), so that a failing or interrupted writer never leaves a half-written file or
/// replaces a good one. A device or a pipe is written through.
///
/// # Errors
/// The error of `write`, or [`Error::Io`] if the directory cannot be created or the rename
/// fails.
pub fn write_with<E: From<Error>>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), E> {
    if is_special(path) {
        return write(path);
    }
    ensure_parent(path)?;
    let tmp = temp_path(path);
    match write(&tmp) {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            E::from(io(path)(e))
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to `path` atomically (see [`write_with`]).
///
/// ```
/// let dir = std::env::temp_dir().join(format!("hycont-doc-{}", std::process::id()));
/// let path = dir.join("counts.json");
/// hycont_sample::study::write_atomic(&path, b"{}").unwrap();
/// assert_eq!(std::fs::read(&path).unwrap(), b"{}");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn write_atomic(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), Error> {
    write_with(path, |tmp| {
        std::fs::write(tmp, bytes.as_ref()).map_err(io(path))
    })
}

/// Reads a JSON count file written by `what` (named in the message) and checks it with
/// `check`.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::InvalidFile`] naming the file and
/// what is wrong with it.
pub fn read_checked<F: serde::de::DeserializeOwned>(
    path: &Path,
    what: &str,
    check: impl FnOnce(&F) -> Result<(), String>,
) -> Result<F, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let file: F = serde_json::from_str(&text).map_err(|e| Error::InvalidFile {
        path: path.to_path_buf(),
        reason: format!("not a file written by `{what}` ({e})"),
    })?;
    check(&file).map_err(|reason| Error::InvalidFile {
        path: path.to_path_buf(),
        reason,
    })?;
    Ok(file)
}
