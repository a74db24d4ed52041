//! Config files: TOML documents deserialised into plain serde structs (unknown keys are
//! errors), range-checked with messages that name the file and the key, and copied next to
//! every output they produced.

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::error::{Result, XylemError};
use crate::io::write_bytes_atomic;

/// Reads and parses a TOML file into `T`. Parse errors (syntax, unknown key, wrong type)
/// carry the parser's message, which names the key and the line.
pub(crate) fn load_toml<T: DeserializeOwned + Serialize>(path: &Path) -> Result<T> {
    let text = crate::io::read_text(path, "a TOML file")?;
    parse_toml(&text, path)
}

/// Parses TOML text; `origin` names the source in error messages. An array longer or
/// shorter than its field (`steps = [12, 15, 19]` for a `[min, max]`) is an error: serde
/// fills fixed-size arrays from the first elements and drops the rest silently, so the
/// parsed value is written back to TOML and every array's length compared with the text's.
pub fn parse_toml<T: DeserializeOwned + Serialize>(text: &str, origin: &Path) -> Result<T> {
    let parse_error = |message: String| XylemError::ConfigParse {
        path: origin.to_path_buf(),
        message,
    };
    let value: T =
        toml::from_str(text).map_err(|e| parse_error(e.to_string().trim_end().to_string()))?;
    let given: toml::Value =
        toml::from_str(text).map_err(|e| parse_error(e.to_string().trim_end().to_string()))?;
    let kept = toml::Value::try_from(&value).map_err(|e| parse_error(e.to_string()))?;
    match array_length_mismatch(&given, &kept, "") {
        Some((key, got, expected)) => Err(parse_error(format!(
            "{key}: {got} values given, expected {expected}"
        ))),
        None => Ok(value),
    }
}

/// The first array of `given` whose counterpart in `kept` has another length, as (dotted
/// key, given length, kept length). Keys `kept` lacks (not written back) are not checked.
fn array_length_mismatch(
    given: &toml::Value,
    kept: &toml::Value,
    key: &str,
) -> Option<(String, usize, usize)> {
    use toml::Value;
    match (given, kept) {
        (Value::Table(g), Value::Table(k)) => g.iter().find_map(|(name, gv)| {
            let sub = if key.is_empty() {
                name.clone()
            } else {
                format!("{key}.{name}")
            };
            k.get(name)
                .and_then(|kv| array_length_mismatch(gv, kv, &sub))
        }),
        (Value::Array(g), Value::Array(k)) if g.len() != k.len() => {
            Some((key.to_string(), g.len(), k.len()))
        }
        (Value::Array(g), Value::Array(k)) => g
            .iter()
            .zip(k)
            .enumerate()
            .find_map(|(i, (gv, kv))| array_length_mismatch(gv, kv, &format!("{key}[{i}]"))),
        _ => None,
    }
}

/// Reads, parses and validates a config file: `validate` gets a checker naming `path`.
pub(crate) fn load_checked<T: DeserializeOwned + Serialize>(
    path: &Path,
    validate: impl FnOnce(&T, &Checker) -> Result<()>,
) -> Result<T> {
    let cfg: T = load_toml(path)?;
    validate(&cfg, &Checker::new(path))?;
    Ok(cfg)
}

/// Parses and validates TOML text; `origin` names the source in error messages.
pub(crate) fn parse_checked<T: DeserializeOwned + Serialize>(
    text: &str,
    origin: &Path,
    validate: impl FnOnce(&T, &Checker) -> Result<()>,
) -> Result<T> {
    let cfg: T = parse_toml(text, origin)?;
    validate(&cfg, &Checker::new(origin))?;
    Ok(cfg)
}

/// A config file type: TOML parsed into a serde struct (unknown keys are errors), range
/// checked with errors naming the file and the key, and copied beside the outputs it made.
/// A type states its checks once (`validate`); loading, parsing and the copy come with it.
pub trait ConfigFile: DeserializeOwned + Serialize + Sized {
    /// Range checks of every value; keys in messages are relative to `check`'s prefix.
    fn validate(&self, check: &Checker) -> Result<()>;

    /// Loads and validates a config file.
    fn load(path: &Path) -> Result<Self> {
        load_checked(path, Self::validate)
    }

    /// Parses and validates TOML text (`origin` names it in errors).
    fn parse(text: &str, origin: &Path) -> Result<Self> {
        parse_checked(text, origin, Self::validate)
    }

    /// A built-in config's text (compiled in, so it is known to be valid: tests parse every
    /// one), named `origin` in the impossible error.
    fn built_in(text: &str, origin: &str) -> Self {
        Self::parse(text, Path::new(origin))
            .unwrap_or_else(|e| panic!("built-in config {origin} is invalid: {e}"))
    }

    /// Writes the config as used (all defaults filled in) beside an output, with a header
    /// naming where it came from.
    fn save_copy(&self, path: &Path, source: &str) -> Result<()> {
        write_config_copy(path, self, source)
    }
}

/// Serialises a config to TOML text.
pub fn to_toml<T: Serialize>(value: &T) -> Result<String> {
    toml::to_string(value).map_err(|e| XylemError::input("config serialisation", e.to_string()))
}

/// Writes the config actually used (all defaults filled in) next to an output, with a header
/// naming where it came from, so the output can be reproduced.
pub fn write_config_copy<T: Serialize>(path: &Path, value: &T, source: &str) -> Result<()> {
    let body = to_toml(value)?;
    let text = format!(
        "# Config used by xylem {} (from {source}).\n# Re-run with this file to reproduce the output.\n\n{body}",
        env!("CARGO_PKG_VERSION")
    );
    write_bytes_atomic(path, text.as_bytes())
}

/// Range checks with messages naming the file and the full key (e.g. `growth.years_per_unit`).
pub struct Checker {
    path: PathBuf,
    prefix: String,
}

impl Checker {
    pub fn new(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            prefix: String::new(),
        }
    }

    /// A checker for a nested table: keys are reported as `prefix.key`.
    pub fn nested(&self, prefix: &str) -> Self {
        Self {
            path: self.path.clone(),
            prefix: self.key(prefix),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    fn key(&self, key: &str) -> String {
        if self.prefix.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.prefix)
        }
    }

    /// An error about `key`.
    pub fn error(&self, key: &str, message: impl Into<String>) -> XylemError {
        XylemError::ConfigValue {
            path: self.path.clone(),
            key: self.key(key),
            message: message.into(),
        }
    }

    /// `Ok` when `ok`, else the error about `key` that `message` words (built only on failure).
    fn require(&self, ok: bool, key: &str, message: impl FnOnce() -> String) -> Result<()> {
        if ok {
            Ok(())
        } else {
            Err(self.error(key, message()))
        }
    }

    /// `value` must be finite and within [lo, hi].
    pub fn range(&self, key: &str, value: f32, lo: f32, hi: f32, meaning: &str) -> Result<()> {
        let ok = value.is_finite() && value >= lo && value <= hi;
        self.require(ok, key, || {
            format!("= {value}: expected {meaning} in [{lo}, {hi}]")
        })
    }

    /// `value` must be finite and > 0 (and at most `hi`).
    pub fn positive(&self, key: &str, value: f32, hi: f32, meaning: &str) -> Result<()> {
        let ok = value.is_finite() && value > 0.0 && value <= hi;
        self.require(ok, key, || {
            format!("= {value}: expected {meaning}, a number > 0 and <= {hi}")
        })
    }

    /// All components finite and within [-bound, bound].
    pub fn vector(&self, key: &str, v: [f32; 3], bound: f32, meaning: &str) -> Result<()> {
        let ok = v.iter().all(|x| x.is_finite() && x.abs() <= bound);
        self.require(ok, key, || {
            format!("= {v:?}: expected {meaning}, three finite numbers within +-{bound}")
        })
    }

    /// A direction: finite, not (nearly) zero.
    pub fn direction(&self, key: &str, v: [f32; 3]) -> Result<()> {
        // Bounded components: the squared length of [1e30, 1e30, 0] overflows f32 and the
        // direction would silently become another one.
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let ok = v.iter().all(|x| x.is_finite() && x.abs() <= 1e6) && len > 1e-6;
        self.require(ok, key, || {
            format!("= {v:?}: expected a direction [x, y, z], components within +-1e6, not zero (need not be normalised)")
        })
    }

    /// A list of `n` entries, `lo` to `hi`; its error reads "has {n} {what}", so `what` names the
    /// entries and the limits (e.g. "values; expected 1 to 64 distances").
    pub(crate) fn list_length(
        &self,
        key: &str,
        n: usize,
        lo: usize,
        hi: usize,
        what: &str,
    ) -> Result<()> {
        self.require((lo..=hi).contains(&n), key, || format!("has {n} {what}"))
    }

    /// An integer count within [lo, hi].
    pub fn count(
        &self,
        key: &str,
        value: usize,
        lo: usize,
        hi: usize,
        meaning: &str,
    ) -> Result<()> {
        self.require((lo..=hi).contains(&value), key, || {
            format!("= {value}: expected {meaning}, an integer in [{lo}, {hi}]")
        })
    }
}
