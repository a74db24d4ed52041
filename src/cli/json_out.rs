//! `--json`: one machine-readable summary on stdout at the end of `run`, `fit`, `train` and
//! `compare`; the human lines go to stderr then, so stdout holds exactly one JSON object.
//!
//! `run` calls the fit and training commands; only the command the user typed prints its
//! summary, so the nested ones stay quiet.

use std::fmt::Write as _;
use std::sync::OnceLock;

/// The command given on the command line, when `--json` was asked for.
static JSON_FOR: OnceLock<Option<String>> = OnceLock::new();

/// Commands that print a summary with `--json`.
pub const COMMANDS: [&str; 4] = ["run", "fit", "train", "compare"];

/// Records the command line's choice (call once, before the command runs).
pub fn init(command: &str, json: bool) {
    let _ = JSON_FOR.set(json.then(|| command.to_string()));
}

/// Whether `--json` was given.
pub fn json_mode() -> bool {
    JSON_FOR.get().is_some_and(|c| c.is_some())
}

/// A line for people: stdout normally, stderr under `--json`.
pub fn say(line: &str) {
    if json_mode() {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
}

/// One JSON object, built field by field.
pub struct Summary {
    command: String,
    fields: Vec<(String, String)>,
}

impl Summary {
    pub fn new(command: &str) -> Self {
        Self {
            command: command.to_string(),
            fields: vec![("command".into(), quote(command))],
        }
    }

    /// A nested object (no `command` field), for arrays of records inside a summary.
    pub fn new_object() -> Self {
        Self {
            command: String::new(),
            fields: Vec::new(),
        }
    }

    pub fn text(mut self, key: &str, value: &str) -> Self {
        self.fields.push((key.into(), quote(value)));
        self
    }

    /// A number; NaN and infinities become `null` (JSON has no such numbers).
    pub fn number(mut self, key: &str, value: f64) -> Self {
        let v = if value.is_finite() {
            format!("{value}")
        } else {
            "null".into()
        };
        self.fields.push((key.into(), v));
        self
    }

    pub fn integer(mut self, key: &str, value: u64) -> Self {
        self.fields.push((key.into(), value.to_string()));
        self
    }

    pub fn flag(mut self, key: &str, value: bool) -> Self {
        self.fields.push((key.into(), value.to_string()));
        self
    }

    /// A value that is already JSON (e.g. the metrics object of `compare`).
    pub fn raw(mut self, key: &str, json: String) -> Self {
        self.fields.push((key.into(), json));
        self
    }

    pub fn to_json(&self) -> String {
        let body: Vec<String> = self
            .fields
            .iter()
            .map(|(k, v)| format!("{}: {v}", quote(k)))
            .collect();
        format!("{{{}}}", body.join(", "))
    }

    /// Prints the summary if `--json` was given for this very command.
    pub fn emit(self) {
        if JSON_FOR.get().and_then(|c| c.as_deref()) == Some(self.command.as_str()) {
            println!("{}", self.to_json());
        }
    }
}

/// A JSON string literal.
fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_is_one_json_object_with_escaped_text_and_null_for_nan() {
        let s = Summary::new("fit")
            .text("out", "a \"b\"\\c\n")
            .number("loss", f64::NAN)
            .number("mm", 0.125)
            .integer("n", 3)
            .flag("done", true);
        assert_eq!(
            s.to_json(),
            r#"{"command": "fit", "out": "a \"b\"\\c\n", "loss": null, "mm": 0.125, "n": 3, "done": true}"#
        );
    }
}
