//! The sequential NFF reader: tokens in, [`Scene`] plus diagnostics out
//! (the entry point, which may hand a large file to the parallel reader
//! instead, is [`super::read`]).
//!
//! The reader recovers from an error by skipping to the next entity keyword
//! or the next line that starts with a word, so one run reports every broken
//! entity and every unknown one, not just the first.
//!
//! Two extensions from the 2017 course files are read unless
//! [`ParseOptions::strict`] is set: `pl x1 y1 z1 x2 y2 z2 x3 y3 z3`, the
//! infinite plane through three points, and `aabb xmin ymin zmin xmax ymax
//! zmax`, an axis-aligned box. Each use is reported as a note.
//!
//! With [`ParseOptions::dialect`] P3F, the course's own language is read
//! (its entities in `p3f.rs`, its view lines in `view.rs`).

mod misplaced;
mod p3f;
mod view;

use super::diag::{Diagnostic, Severity};
use super::geometry_checks;
use super::lexer::{Lexer, Token};
use crate::scene::{Dialect, Light, Material, Primitive, Scene, Shape, SourceLine, MAX_COORDINATE};

use glam::DVec3;
use std::fmt;

/// How strictly to read.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParseOptions {
    /// Unknown entities become warnings and are skipped up to the next known
    /// keyword (for dialect files: `la`, `fp`, mail headers, ...).
    pub lenient: bool,
    /// The file is a fragment meant to be appended to another scene, so a
    /// missing `v` block is not an error.
    pub fragment: bool,
    /// The plain language: in NFF the course extensions `pl` and `aabb`
    /// are errors; in P3F what the course's description does not hold
    /// (extra `f` values, unknown directives) is an error, not a warning.
    pub strict: bool,
    /// NFF or the course's P3F.
    pub dialect: Dialect,
}

/// A successfully read scene and its warnings.
#[derive(Debug, Clone)]
pub struct Parsed {
    /// The scene.
    pub scene: Scene,
    /// Warnings (never errors), in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// A file that could not be read: every diagnostic found, errors and
/// warnings, in source order. At least one is an error.
#[derive(Debug, Clone)]
pub struct ParseError {
    /// All diagnostics.
    pub diagnostics: Vec<Diagnostic>,
}

impl ParseError {
    /// The first error, the one to show when only one is shown.
    pub fn first_error(&self) -> &Diagnostic {
        self.diagnostics
            .iter()
            .find(|d| d.severity == Severity::Error)
            .expect("a ParseError holds at least one error")
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
        write!(f, "{}", self.first_error())?;
        if n > 1 {
            write!(f, " (and {} more errors)", n - 1)?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseError {}

/// A UTF-8 byte-order mark.
pub(super) const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Read an NFF scene from bytes on the calling thread.
pub fn parse_sequential(src: &[u8], opts: &ParseOptions) -> Result<Parsed, ParseError> {
    // A UTF-8 byte-order mark (Windows editors) is one invisible character:
    // dropping it keeps the columns of line 1 as the user sees them.
    let (src, bom) = match src.strip_prefix(BOM) {
        Some(rest) => (rest, true),
        None => (src, false),
    };
    if let Some(encoding) = utf16(src) {
        return Err(utf16_error(encoding));
    }
    let mut p = Parser::new(strip_dos_eof(src), *opts);
    reserve_room(&mut p.scene.primitives, primitives_hint(src, src.len()));
    if bom {
        p.diags.push(Diagnostic {
            severity: Severity::Warning,
            line: 1,
            column: 1,
            width: 1,
            message: "the file starts with a UTF-8 byte-order mark; it is ignored".into(),
            note: None,
        });
    }
    p.run();
    p.finish()
}

/// The error for a file in `encoding`, a UTF-16 one.
#[cold]
fn utf16_error(encoding: &str) -> ParseError {
    ParseError {
        diagnostics: vec![Diagnostic {
            severity: Severity::Error,
            line: 1,
            column: 1,
            width: 1,
            message: format!("the file is {encoding} text; NFF is ASCII"),
            note: Some(format!(
                "convert it first, e.g. `iconv -f {encoding} -t UTF-8 scene.nff > scene-utf8.nff` \
                 (Windows editors and PowerShell's `>` write UTF-16)"
            )),
        }],
    }
}

/// The encoding, if `src` is UTF-16: it starts with a UTF-16 byte-order
/// mark, or its first characters are ASCII each paired with a NUL byte.
pub(super) fn utf16(src: &[u8]) -> Option<&'static str> {
    match src {
        [0xFF, 0xFE, ..] => return Some("UTF-16LE"),
        [0xFE, 0xFF, ..] => return Some("UTF-16BE"),
        _ => {}
    }
    let start = &src[..src.len().min(128)];
    let ascii_then_nul = |a: u8, b: u8| a != 0 && a.is_ascii() && b == 0;
    let all = |order: fn(&[u8]) -> (u8, u8)| {
        start.len() >= 4
            && start.chunks_exact(2).all(|p| {
                let (a, b) = order(p);
                ascii_then_nul(a, b)
            })
    };
    if all(|p| (p[0], p[1])) {
        Some("UTF-16LE")
    } else if all(|p| (p[1], p[0])) {
        Some("UTF-16BE")
    } else {
        None
    }
}

/// One chunk of a file, read on its own as a fragment: its scene (material
/// indices local to the chunk), its diagnostics, and, when there are none,
/// the line breaks it holds. Its lines count from 1, as if it began the
/// file; room is made for `primitives` primitives.
pub(super) fn parse_chunk(
    src: &[u8],
    opts: &ParseOptions,
    primitives: usize,
) -> (Scene, Vec<Diagnostic>, u32) {
    let mut p = Parser::new(src, ParseOptions { fragment: true, ..*opts });
    reserve_room(&mut p.scene.primitives, primitives);
    p.run();
    // A read that says nothing reads to the end, so the lexer has passed
    // every line break (one that stops early has diagnostics).
    let lines = p.lexer.line() - 1;
    (p.scene, p.diags, lines)
}

/// How much of a file the room estimate reads: enough lines for a density,
/// little beside reading the file (64 KiB of a 300 KB file is 0.4 million
/// instructions).
const SAMPLE_BYTES: usize = 1 << 16;

/// Room to make for the primitives of `bytes` bytes of NFF like `sample`
/// (its first [`SAMPLE_BYTES`]):
/// as many as the sample's density of object lines (`s`, `p`, `pp`, `c`,
/// `pl`, `aabb` at a line's start) predicts, and a tenth more. Reserving
/// up front spares a large list its copies as it doubles (and the higher
/// peak they make); a sample without objects (a long view or comment)
/// predicts one per 40 bytes, the shortest an SPD line gets, up to 2^20.
pub(super) fn primitives_hint(sample: &[u8], bytes: usize) -> usize {
    let sample = &sample[..sample.len().min(SAMPLE_BYTES)];
    let objects = sample
        .split(|&b| b == b'\n')
        .filter(|line| {
            let word = line.split(|b| b.is_ascii_whitespace()).next().unwrap_or_default();
            matches!(word, b"s" | b"p" | b"pp" | b"c" | b"pl" | b"aabb")
        })
        .count();
    if objects == 0 || sample.is_empty() {
        return (bytes / 40).min(1 << 20);
    }
    let per_byte = objects as f64 / sample.len() as f64;
    (per_byte * bytes as f64 * 1.1) as usize + 16
}

/// Make room for `n` more primitives if the allocator can give it; where
/// it cannot (a hint too large for the machine), the list grows as read.
pub(super) fn reserve_room(list: &mut Vec<crate::scene::Primitive>, n: usize) {
    let _ = list.try_reserve(n);
}

/// The source without a DOS end-of-file byte (0x1A, Ctrl-Z) at its end, as
/// old DOS editors and the SPD's DOS builds wrote it.
pub(super) fn strip_dos_eof(src: &[u8]) -> &[u8] {
    let end = src.iter().rposition(|b| !b.is_ascii_whitespace()).map_or(0, |i| i + 1);
    match src[..end].iter().rposition(|&b| b != 0x1A) {
        Some(i) if i + 1 < end => &src[..i + 1],
        None if end > 0 => &[],
        _ => src,
    }
}

/// More errors than this and the reader stops: the file is probably not NFF.
const MAX_ERRORS: usize = 50;
/// Largest vertex count accepted for one polygon; beyond it the count is an
/// error before anything is allocated.
pub const MAX_VERTICES: u64 = 1 << 24;
/// Largest image side accepted in a `resolution` line.
const MAX_RESOLUTION: u64 = 1 << 16;

pub(super) const ENTITY_KEYWORDS: [&str; 8] = ["v", "b", "l", "f", "c", "s", "p", "pp"];
/// The 2017 course's extensions (see the module doc).
const EXTENSION_KEYWORDS: [&str; 2] = ["pl", "aabb"];
/// P3F's own entities and directives.
pub(crate) const P3F_KEYWORDS: [&str; 7] = ["bclr", "al", "box", "mesh", "env", "spp", "accel"];
/// The view's lines: NFF's six, then P3F's two.
const VIEW_KEYWORDS: [&[u8]; 8] =
    [b"from", b"at", b"up", b"angle", b"hither", b"resolution", b"aperture", b"focal"];
/// How many of [`VIEW_KEYWORDS`] NFF has.
const NFF_VIEW_LINES: usize = 6;

/// The entity keyword (NFF's, an extension's or P3F's) that `t` is, if any.
fn entity_keyword(t: &[u8]) -> Option<&'static str> {
    ENTITY_KEYWORDS
        .iter()
        .chain(&EXTENSION_KEYWORDS)
        .chain(&P3F_KEYWORDS)
        .find(|k| k.as_bytes() == t)
        .copied()
}

fn is_entity_keyword(t: &[u8]) -> bool {
    entity_keyword(t).is_some()
}

/// Where error recovery stops: an entity keyword, or a word (not a number,
/// not a view keyword) that starts a line, which is then reported as an
/// unknown entity rather than skipped unseen.
fn is_recovery_point(t: &Token) -> bool {
    is_entity_keyword(t.text)
        || (t.starts_line
            && t.text.first().is_some_and(|b| b.is_ascii_alphabetic())
            && !VIEW_KEYWORDS[..NFF_VIEW_LINES].contains(&t.text)
            && parse_number(t.text).is_none())
}

// Rust's float grammar accepts what C's strtod does for NFF's purposes
// (`.5`, `-0`, `1e-16`, `+2`), plus `inf`/`nan`, which the caller rejects
// with their own message.
use super::number::parse_number;

/// What a number is, described only when a message needs it (formatting a
/// description per vertex would dominate the reading time).
#[derive(Clone, Copy)]
enum What<'s> {
    Text(&'s str),
    Vertex { normal: bool, i: u64, n: u64 },
    FValue(usize),
    P3fValue(usize),
    MeshVertex { i: u64, n: u64 },
}

impl What<'_> {
    fn describe(self) -> String {
        const F_NAMES: [&str; 8] = ["red", "green", "blue", "Kd", "Ks", "Shine", "T", "index of refraction"];
        match self {
            What::Text(t) => t.to_string(),
            What::Vertex { normal: false, i, n } => format!("a coordinate of vertex {} of {n}", i + 1),
            What::Vertex { normal: true, i, n } => format!("a normal component of vertex {} of {n}", i + 1),
            What::FValue(i) => format!("`f` value {} ({})", i + 1, F_NAMES[i]),
            What::P3fValue(i) => format!("`f` value {} ({})", i + 1, p3f::F_NAMES[i]),
            What::MeshVertex { i, n } => format!("a coordinate of mesh vertex {} of {n}", i + 1),
        }
    }
}

/// A count: a whole number, written as an integer or (as some exporters
/// write `512.0`) a float with no fraction.
fn whole_number(text: &[u8]) -> Option<u64> {
    let text = std::str::from_utf8(text).ok()?;
    text.parse::<u64>().ok().or_else(|| {
        let f = text.parse::<f64>().ok()?;
        (f.fract() == 0.0 && f >= 0.0 && f <= u64::MAX as f64).then_some(f as u64)
    })
}

/// The entity being read, for notes on truncated input.
#[derive(Clone, Copy)]
struct Entity {
    keyword: &'static str,
    line: u32,
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    peeked: Option<Option<Token<'a>>>,
    opts: ParseOptions,
    scene: Scene,
    diags: Vec<Diagnostic>,
    errors: usize,
    first_object_line: Option<u32>,
    /// Whether a `v` keyword was read (even one whose block had errors).
    view_seen: bool,
    /// The keyword of the last entity read, for blaming an extra value on
    /// it (the rest is read again when that happens).
    read: Option<Token<'a>>,
    /// The last token read, for the position just after it (where an
    /// unexpected end of file is reported); kept whole so the width is
    /// only counted when such an error happens.
    last: Option<Token<'a>>,
    /// The last column found: its line's start (address), the length of the
    /// line up to it, and the column.
    last_column: std::cell::Cell<(usize, usize, u32)>,
}

type Res<T> = Result<T, Diagnostic>;

impl<'a> Parser<'a> {
    /// A parser over `src`, its lines counted from 1.
    fn new(src: &'a [u8], opts: ParseOptions) -> Self {
        let lexer = Lexer::starting_at(src, 1);
        Parser {
            lexer,
            peeked: None,
            opts,
            scene: Scene { dialect: opts.dialect, ..Scene::default() },
            diags: Vec::new(),
            errors: 0,
            first_object_line: None,
            view_seen: false,
            read: None,
            last: None,
            last_column: std::cell::Cell::new((0, 0, 1)),
        }
    }

    /// Line and column just after the last token read ((1, 1) before any).
    fn eof(&self) -> (u32, u32) {
        self.last.map_or((1, 1), |t| (t.line, self.column(&t) + t.width()))
    }

    fn peek(&mut self) -> Option<Token<'a>> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lexer.next());
        }
        self.peeked.unwrap()
    }

    fn bump(&mut self) -> Option<Token<'a>> {
        let t = match self.peeked.take() {
            Some(t) => t,
            None => self.lexer.next(),
        };
        if t.is_some() {
            self.last = t;
        }
        t
    }

    fn diag_at(&self, severity: Severity, t: &Token, message: String) -> Diagnostic {
        Diagnostic { severity, line: t.line, column: self.column(t), width: t.width(), message, note: None }
    }

    /// [`Token::column`], counted on from the last column found on the same
    /// line, so that many diagnostics on one long line cost linear time.
    fn column(&self, t: &Token) -> u32 {
        let (start, len, column) = self.last_column.get();
        let column = if start == t.before.as_ptr() as usize && len <= t.before.len() {
            column + Token::char_count(&t.before[len..])
        } else {
            t.column()
        };
        self.last_column.set((t.before.as_ptr() as usize, t.before.len(), column));
        column
    }

    fn error_at(&self, t: &Token, message: String) -> Diagnostic {
        self.diag_at(Severity::Error, t, message)
    }

    fn warn(&mut self, t: &Token, message: String) {
        let d = self.diag_at(Severity::Warning, t, message);
        self.diags.push(d);
    }

    fn note(&mut self, t: &Token, message: String) {
        let d = self.diag_at(Severity::Note, t, message);
        self.diags.push(d);
    }

    fn push_error(&mut self, d: Diagnostic) {
        self.errors += 1;
        self.diags.push(d);
    }

    fn eof_error(&self, expected: What, entity: Entity) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            line: self.eof().0,
            column: self.eof().1,
            width: 1,
            message: format!("unexpected end of file: expected {}", expected.describe()),
            note: Some(format!("the `{}` that starts on line {} is cut short", entity.keyword, entity.line)),
        }
    }

    /// Read one number. On a token that is not a number, it is left unread
    /// (it may be the next entity's keyword) and the error names the entity.
    fn number(&mut self, what: What, entity: Entity) -> Res<f64> {
        if self.peeked.is_none() {
            // The hot path: token and value in one pass.
            if let Some((v, t)) = self.lexer.number() {
                if v.is_finite() {
                    self.last = Some(t);
                    return Ok(v);
                }
                // `inf`, `nan`, `1e999`: reported below like any other token.
                self.peeked = Some(Some(t));
            }
        }
        let Some(t) = self.peek() else {
            return Err(self.eof_error(what, entity));
        };
        match parse_number(t.text) {
            Some(v) if v.is_finite() => {
                self.bump();
                Ok(v)
            }
            Some(_) => {
                self.bump();
                Err(self.error_at(
                    &t,
                    format!("expected {} (a finite number), found `{}`", what.describe(), t.display()),
                ))
            }
            None => {
                let mut d =
                    self.error_at(&t, format!("expected {}, found `{}`", what.describe(), t.display()));
                if is_entity_keyword(t.text) || t.line != entity.line {
                    d.note = Some(format!("in the `{}` that starts on line {}", entity.keyword, entity.line));
                }
                Err(d)
            }
        }
    }

    /// `N` finite numbers read at once, where nothing was peeked; `None`,
    /// with nothing read, where [`Parser::number`] is to read them one by
    /// one (and say what is wrong). Either way the last number's token is
    /// the one kept.
    #[inline]
    fn numbers<const N: usize>(&mut self) -> Option<[f64; N]> {
        if self.peeked.is_some() {
            return None;
        }
        let (values, t) = self.lexer.numbers::<N>()?;
        self.last = Some(t);
        Some(values)
    }

    fn vec3(&mut self, what: What, entity: Entity) -> Res<DVec3> {
        if let Some([x, y, z]) = self.numbers() {
            return Ok(DVec3::new(x, y, z));
        }
        let x = self.number(what, entity)?;
        let y = self.number(what, entity)?;
        let z = self.number(what, entity)?;
        Ok(DVec3::new(x, y, z))
    }

    /// A whole number in `[min, max]`, returned with its token.
    fn count(&mut self, what: &str, min: u64, max: u64, entity: Entity) -> Res<(u64, Token<'a>)> {
        let Some(t) = self.peek() else {
            return Err(self.eof_error(What::Text(what), entity));
        };
        match whole_number(t.text) {
            Some(n) if (min..=max).contains(&n) => {
                self.bump();
                Ok((n, t))
            }
            Some(n) => {
                self.bump();
                let range =
                    if max == u64::MAX { format!("at least {min}") } else { format!("{min} to {max}") };
                Err(self.error_at(&t, format!("{what} must be {range}, found {n}")))
            }
            None => {
                if !is_entity_keyword(t.text) {
                    self.bump();
                }
                Err(self.error_at(&t, format!("expected {what} (a whole number), found `{}`", t.display())))
            }
        }
    }

    fn run(&mut self) {
        let mut first = true;
        while let Some(t) = self.bump() {
            if first && t.text == b"nff" {
                let d = self.error_at(
                    &t,
                    "this is a Sense8 NFF file (it begins with `nff` and `version`), a different format \
                     from Eric Haines' Neutral File Format; it cannot be read"
                        .into(),
                );
                self.push_error(d);
                return;
            }
            first = false;
            if let Err(d) = self.entity(t) {
                self.push_error(d);
                if self.errors >= MAX_ERRORS {
                    let mut d = self.error_at(&t, "too many errors; giving up".into());
                    d.note = Some("is this an NFF file?".into());
                    self.push_error(d);
                    return;
                }
                self.skip_to_keyword();
            }
        }
    }

    fn skip_to_keyword(&mut self) {
        while let Some(t) = self.peek() {
            if is_recovery_point(&t) {
                return;
            }
            self.bump();
        }
    }

    fn entity(&mut self, t: Token<'a>) -> Res<()> {
        let Some(kw) = entity_keyword(t.text) else {
            return self.unknown(t);
        };
        let e = Entity { keyword: kw, line: t.line };
        let p3f = self.opts.dialect == Dialect::P3f;
        if P3F_KEYWORDS.contains(&kw) && !p3f {
            return self.unknown(t);
        }
        self.read = Some(t);
        match kw {
            "f" if p3f => self.p3f_material(e),
            "l" if p3f => self.p3f_light(t, e),
            "bclr" => self.background(e),
            "al" => self.area_light(t, e),
            "box" => self.aabb(t, e),
            "mesh" => self.mesh(t, e),
            "env" => self.environment(t, e),
            "spp" | "accel" => self.directive(t, e),
            "v" => self.view(t, e),
            "b" => self.background(e),
            "l" => self.light(t, e),
            "f" => self.material(e),
            "s" => {
                let (center, radius) = match self.numbers() {
                    Some([x, y, z, r]) => (DVec3::new(x, y, z), r),
                    None => (
                        self.vec3(What::Text("a sphere centre coordinate"), e)?,
                        self.number(What::Text("a sphere radius"), e)?,
                    ),
                };
                if radius == 0.0 {
                    self.warn(&t, "sphere of radius 0 is invisible".into());
                }
                self.object(t, Shape::Sphere { center, radius });
                Ok(())
            }
            "c" => self.cone(t, e),
            "p" | "pp" => self.polygon(t, e, kw == "pp").map_err(|d| self.blame_odd_line(d, &t)),
            "pl" | "aabb" => self.extension(t, e),
            _ => unreachable!("every entity keyword is matched"),
        }
    }

    fn unknown(&mut self, t: Token<'a>) -> Res<()> {
        let number = parse_number(t.text).is_some();
        let p3f = self.opts.dialect == Dialect::P3f;
        let mut d = match self.read.filter(|_| number) {
            Some(read) => self.extra_value(&t, read),
            None if p3f => {
                let mut d = self.error_at(&t, format!("unknown entity `{}`", t.display()));
                d.note = Some(
                    "P3F entities are v, bclr, env, l, al, f, s, c, p, pp, pl, box, mesh, spp, accel; \
                     without --strict an unknown one is skipped"
                        .into(),
                );
                d
            }
            None => {
                let mut d = self.error_at(&t, format!("unknown entity `{}`", t.display()));
                d.note = Some(if entity_keyword(t.text).is_some_and(|k| P3F_KEYWORDS.contains(&k)) {
                    format!(
                        "`{}` is P3F, the P3D course's language: read the file as P3F (a .p3f name, \
                         or --dialect p3f)",
                        t.display()
                    )
                } else {
                    "NFF entities are v, b, l, f, c, s, p, pp (and the extensions pl, aabb); \
                     --lenient skips unknown ones"
                        .into()
                });
                d
            }
        };
        // P3F files carry students' own extensions: skipped with a warning
        // unless --strict.
        if !(self.opts.lenient || (p3f && !self.opts.strict)) {
            return Err(d);
        }
        d.severity = Severity::Warning;
        if !number {
            d.note =
                Some("skipped up to the next known keyword or line starting with a word (--lenient)".into());
        }
        self.diags.push(d);
        self.skip_to_keyword();
        Ok(())
    }

    fn object(&mut self, t: Token, shape: Shape) {
        self.first_object_line.get_or_insert(t.line);
        if shape.magnitude() > MAX_COORDINATE {
            self.too_large(&t, &shape);
        }
        let material = self.scene.materials.len().checked_sub(1).map(|m| m as u32);
        self.scene.primitives.push(Primitive { shape, material, line: SourceLine(t.line) });
    }

    #[cold]
    fn too_large(&mut self, t: &Token, shape: &Shape) {
        self.warn(
            t,
            format!(
                "a coordinate or radius of this {} is {:e}, beyond what single-precision rendering \
                 holds (at most {MAX_COORDINATE:e}); renders leave it out",
                shape.kind().name(),
                shape.magnitude()
            ),
        );
    }

    fn warn_if_after_objects(&mut self, t: &Token, what: &str) {
        if let Some(line) = self.first_object_line {
            self.warn(
                t,
                format!(
                    "{what} after the first object (line {line}); the spec requires it before any object"
                ),
            );
        }
    }

    fn light(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        self.warn_if_after_objects(&t, "light");
        let position = self.vec3(What::Text("a light position coordinate"), e)?;
        // The colour is optional: present only if a number follows.
        let has_color = self.peek().is_some_and(|n| parse_number(n.text).is_some());
        let color =
            if has_color { Some(self.vec3(What::Text("a light colour component"), e)?) } else { None };
        self.push_light(&t, Light { position, color, area: None });
        Ok(())
    }

    /// Add a light, warning where single precision cannot place it.
    fn push_light(&mut self, t: &Token<'a>, light: Light) {
        let far = light.position.abs().max_element();
        if far > MAX_COORDINATE {
            self.warn(
                t,
                format!(
                    "the light's position has a coordinate of {far:e}, beyond what single-precision \
                     rendering holds (at most {MAX_COORDINATE:e}); renders leave it out"
                ),
            );
        }
        self.scene.lights.push(light);
    }

    fn material(&mut self, e: Entity) -> Res<()> {
        let mut v = [0.0; 8];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = self.number(What::FValue(i), e).map_err(|mut d| {
                d.note = Some(format!(
                    "`f` takes 8 numbers: red green blue Kd Ks Shine T index_of_refraction; \
                     the one on line {} has {i}",
                    e.line
                ));
                d
            })?;
        }
        self.scene.materials.push(Material {
            color: DVec3::new(v[0], v[1], v[2]),
            specular: DVec3::ONE,
            kd: v[3],
            ks: v[4],
            shine: v[5],
            t: v[6],
            ior: v[7],
        });
        Ok(())
    }

    fn cone(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let base = self.vec3(What::Text("a cone base coordinate"), e)?;
        let base_radius = self.number(What::Text("the cone base radius"), e)?;
        let apex = self.vec3(What::Text("a cone apex coordinate"), e)?;
        let apex_radius = self.number(What::Text("the cone apex radius"), e)?;
        if base == apex {
            return Err(self.error_at(&t, "cone base and apex are the same point".into()));
        }
        if (base_radius < 0.0) != (apex_radius < 0.0) && base_radius != 0.0 && apex_radius != 0.0 {
            return Err(self.error_at(
                &t,
                format!("cone radii {base_radius} and {apex_radius} differ in sign; both negative means inside visible"),
            ));
        }
        if base_radius == 0.0 && apex_radius == 0.0 {
            self.warn(&t, "cone with both radii 0 is invisible".into());
        } else if apex_radius.abs() > base_radius.abs() {
            self.warn(
                &t,
                format!(
                    "cone apex radius {} exceeds its base radius {}; NFF.TXT defines the apex radius \
                     as the smaller (the cone renders, but other readers may swap or reject it)",
                    apex_radius.abs(),
                    base_radius.abs()
                ),
            );
        }
        self.object(t, Shape::cone(base, base_radius, apex, apex_radius));
        Ok(())
    }

    fn polygon(&mut self, t: Token<'a>, e: Entity, patch: bool) -> Res<()> {
        let (n, _) = self.count("a vertex count", 3, MAX_VERTICES, e)?;
        // Capacity is capped: the count is only a promise until the vertices
        // are actually read.
        let cap = n.min(4096) as usize;
        let mut vertices = Vec::with_capacity(cap);
        let mut normals = Vec::with_capacity(if patch { cap } else { 0 });
        for i in 0..n {
            vertices.push(self.vec3(What::Vertex { normal: false, i, n }, e)?);
            if patch {
                normals.push(self.vec3(What::Vertex { normal: true, i, n }, e)?);
            }
        }
        let warnings = geometry_checks::polygon(&vertices, if patch { Some(&normals) } else { None });
        for w in warnings {
            self.warn(&t, w);
        }
        let shape = if patch { Shape::patch(vertices, normals) } else { Shape::Polygon { vertices } };
        self.object(t, shape);
        Ok(())
    }

    fn background(&mut self, e: Entity) -> Res<()> {
        let c = self.vec3(What::Text("a colour component"), e)?;
        self.scene.background = Some(c);
        Ok(())
    }

    /// `pl` and `aabb`: the course extensions (module doc), native in P3F.
    fn extension(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let p3f = self.opts.dialect == Dialect::P3f;
        if self.opts.strict && !p3f {
            let mut d = self.error_at(&t, format!("`{}` is not NFF (--strict)", e.keyword));
            d.note = Some(
                "`pl` (plane through three points) and `aabb` (axis-aligned box) are extensions \
                 from the 2017 course files; without --strict they are read"
                    .into(),
            );
            return Err(d);
        }
        if e.keyword != "pl" {
            return self.aabb(t, e);
        }
        let what = What::Text("a plane point coordinate");
        let points = [self.vec3(what, e)?, self.vec3(what, e)?, self.vec3(what, e)?];
        let [a, b, c] = points;
        if (b - a).cross(c - a).length_squared() == 0.0 {
            return Err(
                self.error_at(&t, "the three points of `pl` lie on one line: they make no plane".into())
            );
        }
        if !p3f {
            self.note(&t, "`pl` (infinite plane through three points) is a course extension to NFF".into());
        }
        self.object(t, Shape::plane(points));
        Ok(())
    }

    /// `aabb` (and P3F's `box`): an axis-aligned box.
    fn aabb(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let what = What::Text("a box corner coordinate");
        let (lo, hi) = (self.vec3(what, e)?, self.vec3(what, e)?);
        let kw = e.keyword;
        if lo.cmpgt(hi).any() {
            self.warn(
                &t,
                format!("`{kw}` corners are not min then max on every axis; using them as opposite corners"),
            );
        }
        if lo.cmpeq(hi).any() {
            self.warn(&t, format!("`{kw}` box is flat (zero extent on an axis)"));
        }
        if self.opts.dialect == Dialect::Nff {
            self.note(&t, "`aabb` (axis-aligned box) is a course extension to NFF".into());
        }
        self.object(t, Shape::aabb(lo.min(hi), lo.max(hi)));
        Ok(())
    }

    fn finish(mut self) -> Result<Parsed, ParseError> {
        if !self.view_seen && !self.opts.fragment {
            // Reported where the file ends, after whatever else is wrong.
            self.push_error(Diagnostic {
                severity: Severity::Error,
                line: self.eof().0,
                column: self.eof().1,
                width: 1,
                message: "the file has no view (`v` block): a scene needs a camera".into(),
                note: Some(
                    "a file meant to be appended to another scene is a fragment (render --check --fragment)"
                        .into(),
                ),
            });
        }
        self.diags.sort_by_key(|d| (d.line, d.column));
        if self.errors > 0 {
            Err(ParseError { diagnostics: self.diags })
        } else {
            Ok(Parsed { scene: self.scene, diagnostics: self.diags })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::primitives_hint;

    #[test]
    fn room_follows_the_files_density_of_objects() {
        // Long numbers (as sphereflake writes them): 85 bytes a sphere, so
        // one per 40 bytes would reserve more than twice the room.
        let line = "s 0.27216552697590868 0.27216552697590868 0.54433105395181736 0.16666666666666666\n";
        let src = format!("v\nfrom 0 0 5\n{}", line.repeat(1000));
        let hint = primitives_hint(src.as_bytes(), src.len() * 1000);
        assert!((1_000_000..=1_150_000).contains(&hint), "{hint}");
        // Polygons: one object per four lines.
        let poly = "p 3\n0 0 0\n1 0 0\n0 1 0\n".repeat(500);
        let hint = primitives_hint(poly.as_bytes(), poly.len());
        assert!((500..=600).contains(&hint), "{hint}");
        // No object in the sample: a bounded guess.
        assert_eq!(primitives_hint(b"# comment\n", 1 << 40), 1 << 20);
    }
}
