//! Diagnostics: what went wrong (or looks suspicious), and exactly where.

use std::fmt;

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// Information only: a documented extension was used, for example.
    /// Shown by `render --check`, not by a render.
    Note,
    /// The scene renders, but something looks wrong.
    Warning,
    /// The file is not valid NFF; nothing is rendered.
    Error,
}

/// One message about the source, pointing at a line and column (both 1-based;
/// the column counts characters).
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// Line of the offending token.
    pub line: u32,
    /// Column of its first character.
    pub column: u32,
    /// Its length in characters (at least 1), for the underline.
    pub width: u32,
    /// What is wrong, in one sentence.
    pub message: String,
    /// Extra context, such as where a truncated entity started.
    pub note: Option<String>,
}

impl Diagnostic {
    /// Render in the compiler-like form the tools print:
    ///
    /// ```text
    /// error: expected a number, found `0.0780.3610.753`
    ///  --> scene.nff:1:3
    ///   |
    /// 1 | b 0.0780.3610.753
    ///   |   ^^^^^^^^^^^^^^^
    /// ```
    pub fn render(&self, file: &str, source: &[u8]) -> String {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Note => "note",
        };
        let mut out = format!("{kind}: {}\n", self.message);
        let num = self.line.to_string();
        let pad = " ".repeat(num.len());
        out += &format!("{pad}--> {file}:{}:{}\n", self.line, self.column);
        if let Some(text) = source_line(source, self.line) {
            let shown: String = text.chars().map(|c| if c == '\t' { ' ' } else { c }).collect();
            let caret_pad = " ".repeat(self.column.saturating_sub(1) as usize);
            let carets = "^".repeat(self.width.max(1) as usize);
            out += &format!("{pad} |\n{num} | {shown}\n{pad} | {caret_pad}{carets}\n");
        }
        if let Some(note) = &self.note {
            out += &format!("{pad} = note: {note}\n");
        }
        out
    }
}

impl fmt::Display for Diagnostic {
    /// The one-line form: `line 1, column 3: expected a number, found ...`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}: {}", self.line, self.column, self.message)?;
        if let Some(note) = &self.note {
            write!(f, " ({note})")?;
        }
        Ok(())
    }
}

/// The text of a 1-based line, lossily decoded, without its line ending; long
/// lines are cut so a binary file does not flood the terminal.
fn source_line(source: &[u8], line: u32) -> Option<String> {
    let bytes = source.split(|&b| b == b'\n').nth(line.checked_sub(1)? as usize)?;
    let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
    let text = String::from_utf8_lossy(bytes);
    Some(text.chars().take(200).collect())
}
