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

/// Creates the directory of `path` if needed.
///
/// # Errors
/// [`Error::Io`] if it cannot be created.
pub fn ensure_parent(path: &Path) -> Result<()> {
    Ok(hycont_sample::study::ensure_parent(path)?)
}

/// Writes the file `path` through `write`, which receives a temporary path in the same
/// directory; the temporary file replaces `path` only if `write` succeeds (and is removed
/// otherwise): [`hycont_sample::study::write_with`].
///
/// # Errors
/// The error of `write`, or [`Error::Io`] if the directory cannot be created or the rename
/// fails.
pub fn write_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    hycont_sample::study::write_with(path, write)
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

/// The file formats of a picture.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Default,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// SVG only (scalable; what plotters draws).
    #[default]
    Svg,
    /// PNG only (the SVG rendered with the bundled font, one pixel per SVG unit).
    Png,
    /// Both, side by side (`figN.svg` and `figN.png`).
    Both,
}

impl Format {
    /// Whether an SVG file is written.
    #[must_use]
    pub fn svg(self) -> bool {
        matches!(self, Format::Svg | Format::Both)
    }

    /// Whether a PNG file is written.
    #[must_use]
    pub fn png(self) -> bool {
        matches!(self, Format::Png | Format::Both)
    }
}

/// Writes a picture drawn by `draw` (which writes an SVG file at the path it receives) as SVG at
/// `svg` and as PNG at `png`, each when given, atomically (see [`write_with`]); returns the
/// files written.
///
/// # Errors
/// The error of `draw`; [`Error::Plot`] if the SVG cannot be rendered; [`Error::Io`].
pub fn write_picture(
    svg: Option<&Path>,
    png: Option<&Path>,
    draw: impl FnOnce(&Path) -> Result<()>,
) -> Result<Vec<PathBuf>> {
    let Some(first) = svg.or(png) else {
        return Ok(Vec::new());
    };
    // The SVG is drawn next to the first target, under a temporary name.
    let drawn = hycont_sample::study::temp_path(&first.with_extension("svg"));
    ensure_parent(first)?;
    let result = draw(&drawn).and_then(|()| {
        if let Some(png) = png {
            let text = std::fs::read_to_string(&drawn).map_err(io_error(&drawn))?;
            write_atomic(png, crate::plot::svg_to_png(&text, png)?)?;
        }
        match svg {
            Some(svg) if is_special(svg) => {
                let text = std::fs::read(&drawn).map_err(io_error(&drawn))?;
                std::fs::write(svg, text).map_err(io_error(svg))
            }
            Some(svg) => std::fs::rename(&drawn, svg).map_err(io_error(svg)),
            None => Ok(()),
        }
    });
    let _ = std::fs::remove_file(&drawn);
    result?;
    Ok(svg.into_iter().chain(png).map(Path::to_path_buf).collect())
}

/// An output directory and the format of the pictures written into it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutDir {
    /// The directory.
    pub dir: PathBuf,
    /// The pictures' format.
    pub format: Format,
}

impl OutDir {
    /// `dir`, pictures as SVG.
    #[must_use]
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        OutDir {
            dir: dir.into(),
            format: Format::default(),
        }
    }

    /// The same directory, pictures in `format`.
    #[must_use]
    pub fn with_format(self, format: Format) -> Self {
        OutDir { format, ..self }
    }

    /// The path of the file `name` in the directory.
    #[must_use]
    pub fn join(&self, name: impl AsRef<Path>) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes the picture `stem.svg` and/or `stem.png` (as the format says) drawn by `draw` (see
    /// [`write_picture`]); returns the files written.
    ///
    /// # Errors
    /// As [`write_picture`].
    pub fn picture(
        &self,
        stem: &str,
        draw: impl FnOnce(&Path) -> Result<()>,
    ) -> Result<Vec<PathBuf>> {
        let svg = self.join(format!("{stem}.svg"));
        let png = self.join(format!("{stem}.png"));
        write_picture(
            self.format.svg().then_some(svg.as_path()),
            self.format.png().then_some(png.as_path()),
            draw,
        )
    }
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

/// Whether `path` exists and is neither a regular file nor a directory (a device, a pipe, a
/// socket): outputs are written through such files, not replaced.
#[must_use]
pub fn is_special(path: &Path) -> bool {
    hycont_sample::study::is_special(path)
}

/// The file `path` names: its canonical path where it exists, else its directory's canonical
/// path joined with its name (the file it would create), else the absolute path.
fn identity(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let parent = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    match (std::fs::canonicalize(parent), path.file_name()) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
    }
}

/// Whether two paths name the same file (an output that would replace an input), also when
/// neither exists yet.
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    identity(a) == identity(b)
}

/// Checks a command's files before any work: every output can be written (its directory takes
/// new files; an existing one is not a directory), none is one of the `inputs`, and no two
/// outputs (named by their flags) are the same file. Devices and pipes (e.g. `/dev/null`) are
/// written through, so several outputs may share one.
///
/// # Errors
/// [`Error::InvalidArgument`] naming the output's flag and path; [`Error::Io`] for an
/// unwritable directory.
pub fn check_outputs(inputs: &[&Path], outputs: &[(&'static str, &Path)]) -> Result<()> {
    for (i, &(flag, path)) in outputs.iter().enumerate() {
        let bad = |reason| {
            Err(Error::InvalidArgument {
                name: flag,
                value: path.display().to_string(),
                reason,
            })
        };
        if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
            return bad("is a directory; name a file to write");
        }
        if is_special(path) {
            continue;
        }
        if inputs.iter().any(|input| same_file(input, path)) {
            return bad("is an input file of this command; write to another file");
        }
        if outputs[..i].iter().any(|(_, other)| same_file(other, path)) {
            return bad("names the same file as another output of this command");
        }
        check_file(path)?;
    }
    Ok(())
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
