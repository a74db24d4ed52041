//! What a run folder was made with, so a re-run reuses finished stages only when nothing
//! that decides them has changed.
//!
//! A [`Provenance`] is a sorted list of named values: input paths, content hashes of the
//! input files, config texts' hashes and options. `xylem run` records it in `RUN/run.toml`
//! on its first call; a later call with the same folder compares its own record with the
//! stored one and refuses, naming every difference, instead of silently keeping results
//! that came from other photos, faces or configs. Hashes are FNV-1a 64 of the bytes: they
//! guard against mistakes, not against an adversary.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::atomic::write_bytes_atomic;
use crate::error::{Result, XylemError};

#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// Name -> value, e.g. "faces" -> "A,B,C,D,E".
    pub inputs: BTreeMap<String, String>,
}

impl Provenance {
    pub fn with(mut self, key: &str, value: impl Into<String>) -> Self {
        self.inputs.insert(key.to_string(), value.into());
        self
    }

    /// Records `path` and the hash of its bytes under `key` (and `key_hash`).
    pub(crate) fn with_file(self, key: &str, path: &Path) -> Result<Self> {
        let bytes = super::read::read_bytes(path, "a file to record")?;
        Ok(self
            .with(key, absolute(path))
            .with(&format!("{key}_hash"), hex(fnv1a(&bytes, FNV_OFFSET))))
    }

    /// Records `dir` and one hash over the names and bytes of its regular files and those
    /// of its `truth/` subfolder (a sample folder: photos, ring images, knot markers).
    pub(crate) fn with_folder(self, key: &str, dir: &Path) -> Result<Self> {
        // A mistyped folder would otherwise be recorded with the hash of nothing.
        if !dir.is_dir() {
            return Err(XylemError::input(
                dir.display().to_string(),
                format!("{key} folder not found"),
            ));
        }
        let mut hash = FNV_OFFSET;
        for sub in [dir.to_path_buf(), dir.join("truth")] {
            for path in sorted_files(&sub)? {
                let bytes = fs::read(&path).map_err(|e| XylemError::io(&path, e))?;
                let name = path
                    .strip_prefix(dir)
                    .unwrap_or(&path)
                    .display()
                    .to_string();
                hash = fnv1a(name.as_bytes(), hash);
                hash = fnv1a(&bytes, hash);
            }
        }
        Ok(self
            .with(key, absolute(dir))
            .with(&format!("{key}_hash"), hex(hash)))
    }

    /// Records the hash of `text` under `key` (a built-in config).
    pub(crate) fn with_text(self, key: &str, text: &str) -> Self {
        self.with(key, hex(fnv1a(text.as_bytes(), FNV_OFFSET)))
    }

    /// Records `path` while the folder holds no results yet (`started` false: a record
    /// left by a call that failed before producing anything describes nothing, and is
    /// replaced); once it holds results, compares and fails on any difference, naming
    /// each key with its recorded and its new value (and a missing record is an error
    /// too: the results were made by an older xylem and nothing says what from).
    pub fn check_or_record(&self, path: &Path, started: bool) -> Result<()> {
        if !started || !path.is_file() {
            if started {
                return Err(XylemError::input(
                    path.display().to_string(),
                    "missing: this run folder holds results but no record of what made them \
                     (an older xylem?); use another $out, or delete the folder to start over",
                ));
            }
            let text = toml::to_string(self).map_err(|e| {
                XylemError::input(path.display().to_string(), format!("cannot encode: {e}"))
            })?;
            return write_bytes_atomic(path, text.as_bytes());
        }
        let text = super::read::read_text(path, "a run record (TOML)")?;
        let old: Provenance = toml::from_str(&text).map_err(|e| {
            XylemError::input(
                path.display().to_string(),
                format!("not a run record ([inputs] of names and strings): {e}"),
            )
        })?;
        let changes = self.differences(&old);
        if changes.is_empty() {
            return Ok(());
        }
        Err(XylemError::input(
            path.display().to_string(),
            format!(
                "this run folder was made with other inputs ({}); its results would not match \
                 this call: use another $out, or delete the folder to start over",
                crate::error::literal(&changes.join("; "))
            ),
        ))
    }

    /// "key: was A, now B" for every key whose values differ (or exist on one side only).
    pub fn differences(&self, old: &Provenance) -> Vec<String> {
        let none = String::from("(none)");
        let keys: std::collections::BTreeSet<&String> =
            self.inputs.keys().chain(old.inputs.keys()).collect();
        keys.into_iter()
            .filter_map(|k| {
                let (a, b) = (old.inputs.get(k), self.inputs.get(k));
                (a != b).then(|| {
                    format!(
                        "{k}: was {}, now {}",
                        a.unwrap_or(&none),
                        b.unwrap_or(&none)
                    )
                })
            })
            .collect()
    }
}

/// The FNV-1a 64 hash of `bytes` as 16 hex digits (what the records store).
pub fn content_hash(bytes: &[u8]) -> String {
    hex(fnv1a(bytes, FNV_OFFSET))
}

/// The canonical path (so `./S` and `/home/me/S` are the same input).
fn absolute(path: &Path) -> String {
    fs::canonicalize(path)
        .unwrap_or_else(|_| path.to_path_buf())
        .display()
        .to_string()
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

fn fnv1a(bytes: &[u8], mut hash: u64) -> u64 {
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash
}

fn hex(hash: u64) -> String {
    format!("{hash:016x}")
}

/// Regular files directly in `dir`, sorted by name; none when `dir` does not exist.
fn sorted_files(dir: &Path) -> Result<Vec<std::path::PathBuf>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let entries = fs::read_dir(dir).map_err(|e| XylemError::io(dir, e))?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| XylemError::io(dir, e))?.path();
        if path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}
