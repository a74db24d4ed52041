//! Output folders. xylem writes only into folders it created (or empty ones), marked by a
//! `.xylem-output` file, so a mistyped `--out` never scatters files into a folder the user
//! cares about; inside its own folders files are replaced atomically.

use std::fs;
use std::path::{Path, PathBuf};

use crate::error::{Result, XylemError};

const MARKER: &str = ".xylem-output";

/// An output folder that xylem may write into.
#[derive(Clone, Debug)]
pub struct OutputDir {
    root: PathBuf,
}

impl OutputDir {
    /// Creates `root` (or adopts it if it is empty or already a xylem output folder).
    pub fn prepare(root: &Path) -> Result<Self> {
        if root.exists() {
            if !root.is_dir() {
                return Err(XylemError::input(
                    root.display().to_string(),
                    "$out must be a folder, and this is an existing file",
                ));
            }
            let marked = root.join(MARKER).exists();
            let empty = fs::read_dir(root)
                .map_err(|e| XylemError::io(root, e))?
                .next()
                .is_none();
            if !marked && !empty {
                return Err(XylemError::input(
                    root.display().to_string(),
                    "folder exists, is not empty and was not written by xylem; \
                     choose a new $out folder so nothing there is overwritten",
                ));
            }
        } else {
            fs::create_dir_all(root).map_err(|e| XylemError::io(root, e))?;
        }
        remove_stale_temps(root, 2);
        let marker = root.join(MARKER);
        if !marker.exists() {
            fs::write(&marker, b"written by xylem\n").map_err(|e| XylemError::io(&marker, e))?;
        }
        Ok(Self {
            root: root.to_path_buf(),
        })
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    /// A path inside the folder (sub-folders are created when files are written).
    pub fn path(&self, relative: impl AsRef<Path>) -> PathBuf {
        self.root.join(relative)
    }
}

/// Refuses to replace an existing single output file unless `force` is set.
pub fn check_new_file(path: &Path, force: bool) -> Result<()> {
    if path.exists() && !force {
        return Err(XylemError::input(
            path.display().to_string(),
            "file exists; pass $force to replace it",
        ));
    }
    Ok(())
}

/// Removes the temporary files of atomic writes (`.NAME.PID.tmp`) that a killed xylem left
/// in `dir` and its subfolders down to `depth`; a file whose process still runs is kept.
/// Best effort: where running processes cannot be listed (no `/proc`), nothing is removed.
fn remove_stale_temps(dir: &Path, depth: usize) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            if depth > 0 {
                remove_stale_temps(&path, depth - 1);
            }
            continue;
        }
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some(pid) = temp_owner(&name)
            && !Path::new(&format!("/proc/{pid}")).exists()
        {
            let _ = fs::remove_file(&path);
        }
    }
}

/// The process id in a temporary name `.NAME.PID.tmp`.
fn temp_owner(name: &str) -> Option<u32> {
    let inner = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, pid) = inner.rsplit_once('.')?;
    pid.parse().ok()
}
