//! Diagnostics: what went wrong (or looks suspicious), and exactly where;
//! and [`Report`], which prints them for one source: in linear time (lines
//! found through an index built once), with long lines shown as a window
//! around the column, control characters escaped (a file must not retitle
//! or colour the terminal), and, unless all are asked for, only the first
//! few warnings and notes of each kind, the rest counted.

use super::lexer::line_starts;
use std::collections::HashMap;
use std::fmt;

/// Warnings or notes of one kind shown before the rest are counted.
pub const SHOWN_PER_KIND: usize = 5;
/// Widest part of a source line shown, in characters.
const SNIPPET: usize = 100;

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
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
    ///
    /// For many diagnostics of one source, a [`Report`] is linear in time.
    pub fn render(&self, file: &str, source: &[u8]) -> String {
        Report::new(file, source).all().render(self).unwrap_or_default()
    }

    /// The kind of message, for grouping repeats: its text with every run
    /// of digits as `#` ("patch normal of vertex # has length #.#, not #").
    pub fn kind(&self) -> (Severity, String) {
        let mut key = String::with_capacity(self.message.len());
        for c in self.message.chars() {
            if c.is_ascii_digit() {
                if !key.ends_with('#') {
                    key.push('#');
                }
            } else {
                key.push(c);
            }
        }
        (self.severity, key)
    }
}

/// Prints the diagnostics of one source (see the module doc).
pub struct Report<'s> {
    file: &'s str,
    source: &'s [u8],
    /// Where each line starts, made at the first diagnostic with a line.
    lines: Option<Vec<usize>>,
    /// Warnings and notes shown per kind, `None` when all are shown.
    shown: Option<HashMap<(Severity, String), usize>>,
    /// Per kind held back: the first message held back, and how many.
    held: Vec<((Severity, String), String, usize)>,
    /// Source bytes looked at so far (the line index, then the lines
    /// shown), for tests that printing is linear.
    scanned: u64,
    /// The character offsets of the last line shown.
    chars: Option<(u32, Vec<usize>)>,
}

impl<'s> Report<'s> {
    /// A report on `source`, read from `file`, that summarises repeats.
    pub fn new(file: &'s str, source: &'s [u8]) -> Report<'s> {
        Report {
            file,
            source,
            lines: None,
            shown: Some(HashMap::new()),
            held: Vec::new(),
            scanned: 0,
            chars: None,
        }
    }

    /// Show every diagnostic, repeats too.
    pub fn all(mut self) -> Report<'s> {
        self.shown = None;
        self
    }

    /// `d` rendered, or `None` when it is a repeat held back (errors never
    /// are).
    pub fn render(&mut self, d: &Diagnostic) -> Option<String> {
        if let (Some(shown), true) = (&mut self.shown, d.severity != Severity::Error) {
            let kind = d.kind();
            let n = shown.entry(kind.clone()).or_insert(0);
            *n += 1;
            if *n > SHOWN_PER_KIND {
                match self.held.iter_mut().find(|h| h.0 == kind) {
                    Some(h) => h.2 += 1,
                    None => self.held.push((kind, d.message.clone(), 1)),
                }
                return None;
            }
        }
        Some(self.format(d))
    }

    /// Source bytes looked at so far.
    pub fn scanned(&self) -> u64 {
        self.scanned
    }

    /// Lines saying how many repeats were held back, per kind (empty when
    /// none were).
    pub fn held_back(&self) -> String {
        let mut out = String::new();
        for ((severity, _), first, n) in &self.held {
            let what = match severity {
                Severity::Note => "note",
                _ => "warning",
            };
            out += &format!(
                "{what}: ... and {n} more like `{}` in {} (--all-warnings shows them)\n",
                escape(first),
                escape(self.file)
            );
        }
        out
    }

    fn format(&mut self, d: &Diagnostic) -> String {
        let kind = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Note => "note",
        };
        let mut out = format!("{kind}: {}\n", escape(&d.message));
        let num = d.line.to_string();
        let pad = " ".repeat(num.len());
        out += &format!("{pad}--> {}:{}:{}\n", escape(self.file), d.line, d.column);
        if let Some((shown, caret, width)) = self.snippet(d.line, d.column, d.width) {
            let carets = "^".repeat(width.max(1));
            out += &format!("{pad} |\n{num} | {shown}\n{pad} | {}{carets}\n", " ".repeat(caret));
        }
        if let Some(note) = &d.note {
            out += &format!("{pad} = note: {}\n", escape(note));
        }
        out
    }

    /// The bytes of 1-based line `line`, without its line ending, and where
    /// each of its characters starts (cached: many diagnostics share a
    /// line).
    fn line(&mut self, line: u32) -> Option<(&'s [u8], &[usize])> {
        let source = self.source;
        if self.lines.is_none() {
            self.scanned += source.len() as u64;
        }
        let starts = self.lines.get_or_insert_with(|| line_starts(source));
        let k = line.checked_sub(1)? as usize;
        let start = *starts.get(k)?;
        let end = starts.get(k + 1).copied().unwrap_or(source.len());
        let bytes = &source[start..end];
        let bytes = bytes.strip_suffix(b"\n").unwrap_or(bytes);
        let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
        if self.chars.as_ref().is_none_or(|(l, _)| *l != line) {
            self.scanned += bytes.len() as u64;
            // UTF-8 continuation bytes are 0b10xx_xxxx, as the lexer counts.
            let chars = (0..bytes.len()).filter(|&i| bytes[i] & 0xC0 != 0x80).collect();
            self.chars = Some((line, chars));
        }
        self.chars.as_ref().map(|(_, c)| (bytes, c.as_slice()))
    }

    /// Line `line` as shown under a diagnostic at 1-based `column` spanning
    /// `width` characters: a window of at most [`SNIPPET`] characters
    /// around the column (marked `...` where cut), escaped; with where, in
    /// shown characters, the underline starts and how wide it is.
    fn snippet(&mut self, line: u32, column: u32, width: u32) -> Option<(String, usize, usize)> {
        let (bytes, chars) = self.line(line)?;
        let n = chars.len();
        let first = (column.saturating_sub(1) as usize).min(n);
        let last = (first + width.max(1) as usize).min(n).max(first);
        let (from, to) = if n <= SNIPPET {
            (0, n)
        } else {
            let from = first.saturating_sub(SNIPPET / 3).min(n - SNIPPET);
            (from, from + SNIPPET)
        };
        let byte = |c: usize| if c < n { chars[c] } else { bytes.len() };
        let mut text = String::from(if from > 0 { "..." } else { "" });
        let (mut caret, mut end) = (text.len(), text.len());
        for (k, c) in String::from_utf8_lossy(&bytes[byte(from)..byte(to)]).chars().enumerate() {
            if from + k == first {
                caret = text.chars().count();
            }
            text.push_str(&shown(c));
            if from + k < last {
                end = text.chars().count();
            }
        }
        if first >= to {
            caret = text.chars().count();
        }
        if to < n {
            text.push_str("...");
        }
        self.scanned += (byte(to) - byte(from)) as u64;
        Some((text, caret, end.saturating_sub(caret).max(1)))
    }
}

/// How character `c` is shown: tabs as a space, control characters and
/// the bidirectional overrides (which reorder what a terminal shows)
/// escaped, anything else as itself.
fn shown(c: char) -> String {
    match c {
        '\t' => " ".into(),
        c if (c as u32) < 0x80 && c.is_control() => format!("\\x{:02X}", c as u32),
        c if c.is_control() || matches!(c, '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}') => {
            format!("\\u{{{:X}}}", c as u32)
        }
        c => c.to_string(),
    }
}

/// `text` with control characters escaped.
pub fn escape(text: &str) -> String {
    text.chars().map(shown).collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    fn warning(line: u32, column: u32, message: &str) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            line,
            column,
            width: 1,
            message: message.into(),
            note: None,
        }
    }

    #[test]
    fn repeats_are_counted_after_the_first_few_of_each_kind() {
        let src = "a\n".repeat(30);
        let mut r = Report::new("f.nff", src.as_bytes());
        let shown: Vec<_> = (1..=20)
            .filter_map(|k| {
                r.render(&warning(k, 1, &format!("patch normal of vertex {k} has length 1.3{k}")))
            })
            .collect();
        assert_eq!(shown.len(), SHOWN_PER_KIND);
        assert!(r.render(&warning(21, 1, "another kind")).is_some());
        let held = r.held_back();
        assert!(held.contains("... and 15 more like `patch normal of vertex 6 has length 1.36`"), "{held}");
        let mut all = Report::new("f.nff", src.as_bytes()).all();
        assert_eq!((1..=20).filter_map(|k| all.render(&warning(k, 1, &format!("n {k}")))).count(), 20);
        assert!(all.held_back().is_empty());
    }

    #[test]
    fn printing_is_linear_in_the_source() {
        // One warning on each of 30,000 lines, all printed: every byte of
        // the source is looked at a few times (the index, its line), where
        // finding each line from the start would look at 10^10.
        let src = "pp 3 0 0 0 0 0 2 1 0 0 0 0 2 0 1 0 0 0 2\n".repeat(30_000);
        let mut r = Report::new("f.nff", src.as_bytes()).all();
        for line in 1..=30_000 {
            assert!(r.render(&warning(line, 1, "patch normal of vertex 1 has length 2, not 1")).is_some());
        }
        assert!(r.scanned() <= 3 * src.len() as u64, "{} bytes looked at", r.scanned());
    }

    #[test]
    fn control_bytes_are_escaped_in_messages_and_lines() {
        let src = b"\x1b]0;PWNED\x07 x\n";
        let d = warning(1, 12, "unknown entity `\u{1b}]0;PWNED\u{7}`");
        let text = d.render("f.nff", src);
        assert!(!text.contains('\u{1b}') && !text.contains('\u{7}'), "{text:?}");
        assert!(text.contains("1 | \\x1B]0;PWNED\\x07 x"), "{text}");
        // The caret still points at `x`, though the escapes moved it on.
        let (snippet, caret_line) = (text.lines().nth(3).unwrap(), text.lines().nth(4).unwrap());
        let at = caret_line.find('^').unwrap();
        assert_eq!(&snippet[at..], "x", "{text}");
    }

    #[test]
    fn many_diagnostics_on_one_long_line_look_at_it_once() {
        let line = "pp 3 0 0 0 0 0 2 1 0 0 0 0 2 0 1 0 0 0 2 ".repeat(5000);
        let mut r = Report::new("f.nff", line.as_bytes()).all();
        for k in 0..5000 {
            let text = r.render(&warning(1, 1 + 42 * k, "patch normal")).unwrap();
            assert!(text.len() < 400);
        }
        assert!(r.scanned() < 3 * line.len() as u64 + 5000 * 400, "{} bytes looked at", r.scanned());
    }

    #[test]
    fn long_lines_are_shown_as_a_window_around_the_column() {
        let line = format!("{}TARGET{}", "a ".repeat(20_000), " b".repeat(20_000));
        let d = Diagnostic { width: 6, ..warning(1, 40_001, "here") };
        let text = d.render("f.nff", line.as_bytes());
        assert!(text.len() < 400, "{} bytes", text.len());
        let snippet = text.lines().nth(3).unwrap();
        let carets = text.lines().nth(4).unwrap();
        let at = carets.find('^').unwrap();
        assert_eq!(&snippet[at..at + 6], "TARGET", "{text}");
        assert!(snippet.starts_with("1 | ... a a") && snippet.ends_with("b b ..."), "{text}");
    }
}
