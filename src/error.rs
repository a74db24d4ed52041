//! The library's one error type. Every variant names the file (or input) it is about, so the
//! binary can print it as is; `anyhow` lives only in the binary.

use std::path::PathBuf;

/// Result alias used throughout the library.
pub type Result<T, E = XylemError> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum XylemError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A TOML config could not be parsed (syntax, unknown key, wrong type). The message from
    /// the TOML parser already names the key and the line.
    #[error("{path}: {message}")]
    ConfigParse { path: PathBuf, message: String },

    /// A config value parsed but is out of range or inconsistent.
    #[error("{path}: `{key}` {message}")]
    ConfigValue {
        path: PathBuf,
        key: String,
        message: String,
    },

    /// An image could not be decoded or has the wrong size or layout.
    #[error("{path}: {message}")]
    Image { path: PathBuf, message: String },

    /// A command-line argument or other in-memory input is malformed. `what` and `message`
    /// may name a caller's setting as `$name` (see [`SettingStyle`]); shown as `name` here,
    /// as the flag `--name` by the command line.
    #[error(
        "{}: {}",
        SettingStyle::Library.apply_lead(.what),
        SettingStyle::Library.apply(.message)
    )]
    Input { what: String, message: String },

    /// A sample folder (Mokume layout) is incomplete or inconsistent.
    #[error("{path}: {message}")]
    Sample { path: PathBuf, message: String },

    /// Something a numerical stage could not do (diverged, empty data, ...).
    #[error("{stage}: {message}")]
    Numeric { stage: String, message: String },

    /// A step of a longer job failed; `what` says which step and on what (`fitting DIR`).
    #[error("{}: {source}", SettingStyle::Library.apply_lead(.what))]
    During {
        what: String,
        #[source]
        source: Box<XylemError>,
    },
}

/// The settings a caller chooses that errors may name in their advice ("pass $force to
/// replace it"). They are the command line's flags and, mostly, fields of the library's
/// option structs of the same name.
pub const SETTINGS: [&str; 11] = [
    "config", "device", "faces", "force", "out", "plane", "preset", "resume", "rings", "size",
    "values",
];

/// User text (a path, a value) to put inside a message that names settings: every `$`
/// doubled, so [`SettingStyle::apply`] shows it exactly as given.
pub fn literal(text: &str) -> String {
    text.replace('$', "$$")
}

/// How an error names a setting: `name` in library errors (a library user has no flags), the
/// flag `--name` on the command line (issue 17: library errors leave flag names to the CLI).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SettingStyle {
    Library,
    Flags,
}

impl SettingStyle {
    /// How this style shows the setting `name`.
    fn show(self, name: &str) -> String {
        match self {
            SettingStyle::Library => format!("`{name}`"),
            SettingStyle::Flags => format!("--{name}"),
        }
    }

    /// `text` (a message written by the library) with every `$name` of [`SETTINGS`] that ends
    /// a word written in this style; `$outdir` or `$forced` stay as they are, and `$$` is a
    /// plain `$` (user text inside a message goes through [`literal`]).
    pub fn apply(self, text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(at) = rest.find('$') {
            out.push_str(&rest[..at]);
            let after = &rest[at + 1..];
            let token = SETTINGS.iter().find(|name| {
                after.starts_with(**name)
                    && !after[name.len()..]
                        .starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            });
            if let Some(escaped) = after.strip_prefix('$') {
                out.push('$');
                rest = escaped;
                continue;
            }
            match token {
                Some(name) => {
                    out.push_str(&self.show(name));
                    rest = &after[name.len()..];
                }
                None => {
                    out.push('$');
                    rest = after;
                }
            }
        }
        out.push_str(rest);
        out
    }

    /// `what` (the input an error is about) with a leading `$name ` written in this style and
    /// the rest, which may be a user's path or value, left exactly as given.
    pub(crate) fn apply_lead(self, what: &str) -> String {
        for name in SETTINGS {
            if let Some(rest) = what.strip_prefix(&format!("${name}"))
                && (rest.is_empty() || rest.starts_with(' '))
            {
                return format!("{}{rest}", self.show(name));
            }
        }
        what.to_string()
    }
}

impl XylemError {
    /// The message with settings named in `style` (its sources included, as `Display` does).
    pub fn render(&self, style: SettingStyle) -> String {
        match self {
            Self::Input { what, message } => {
                format!("{}: {}", style.apply_lead(what), style.apply(message))
            }
            Self::During { what, source } => {
                format!("{}: {}", style.apply_lead(what), source.render(style))
            }
            other => other.to_string(),
        }
    }

    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    pub fn input(what: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Input {
            what: what.into(),
            message: message.into(),
        }
    }

    pub fn image(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Image {
            path: path.into(),
            message: message.into(),
        }
    }

    pub fn sample(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Sample {
            path: path.into(),
            message: message.into(),
        }
    }

    /// This error, said to have happened during `what` (the job's step and its input).
    pub fn during(self, what: impl Into<String>) -> Self {
        Self::During {
            what: what.into(),
            source: Box::new(self),
        }
    }

    pub fn numeric(stage: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Numeric {
            stage: stage.into(),
            message: message.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_are_names_in_the_library_and_flags_on_the_command_line() {
        let err = XylemError::input("out.png", "file exists; pass $force to replace it")
            .during("writing /tmp/$out");
        assert_eq!(
            err.to_string(),
            "writing /tmp/$out: out.png: file exists; pass `force` to replace it"
        );
        assert_eq!(
            err.render(SettingStyle::Flags),
            "writing /tmp/$out: out.png: file exists; pass --force to replace it"
        );
        // A user's path or value is shown as given, even where it looks like a setting.
        let path = XylemError::input(
            "/data/$out/$force.png",
            format!("{} and $outdir stay", literal("$force/x")),
        );
        assert_eq!(
            path.render(SettingStyle::Flags),
            "/data/$out/$force.png: $force/x and $outdir stay"
        );
        let faces = XylemError::input("$faces \"A,X\"", "\"X\" is not a face");
        assert_eq!(
            faces.render(SettingStyle::Flags),
            "--faces \"A,X\": \"X\" is not a face"
        );
    }
}
