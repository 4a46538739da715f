//! Numbers in the wrong place. A vertex line with a number too few makes
//! the reader take the next line's first number, and it fails only at the
//! next entity, naming the wrong vertex; one with a number too many leaves
//! a value over after the polygon. Both are blamed on the line that holds
//! the odd count. A value after any other entity's last is called extra,
//! not an unknown entity. All of this runs only when a message needs it:
//! the lines are read again from the source.

use super::{entity_keyword, whole_number, Entity, Parser};
use crate::nff::diag::Diagnostic;
use crate::nff::lexer::{Lexer, Token};
use crate::nff::number::parse_number;

/// A line in a polygon that holds a number of numbers that no whole
/// number of vertices makes.
struct OddLine<'a> {
    first: Token<'a>,
    last: Token<'a>,
    count: u64,
    /// Numbers of the polygon before the line.
    before: u64,
    /// The numbers a line is expected to hold a multiple of.
    unit: u64,
}

impl Entity {
    /// How many numbers the entity takes, for "extra value" messages.
    fn takes(&self, p3f: bool) -> &'static str {
        match self.keyword {
            "f" if p3f => "a P3F material takes 11 numbers",
            "l" if p3f => "a P3F light takes 6 numbers: a position and a colour",
            "bclr" => "a background takes 3 numbers",
            "al" => "an area light takes 11 numbers: centre, the point it faces, width, height, colour",
            "mesh" => "a mesh takes two counts, 3 numbers per vertex and 3 indices per triangle",
            "env" => "`env` takes one folder name",
            "spp" | "accel" => "a directive takes one whole number",
            "v" => {
                "a view's `from`, `at` and `up` take 3 numbers each, `angle` and `hither` 1, `resolution` 2"
            }
            "b" => "a background takes 3 numbers",
            "l" => "a light takes 3 numbers, or 6 with a colour",
            "f" => "a material takes 8 numbers",
            "c" => "a cone takes 8 numbers",
            "s" => "a sphere takes 4 numbers",
            "p" => "a polygon takes a count and 3 numbers per vertex",
            "pp" => "a patch takes a count and 6 numbers per vertex",
            "pl" => "a plane takes 9 numbers",
            "aabb" | "box" => "a box takes 6 numbers",
            _ => "see docs/p3f.md for what each entity takes",
        }
    }
}

impl<'a> Parser<'a> {
    /// A number where an entity keyword should be: a value too many for
    /// the entity before, or for one of its lines.
    pub(super) fn extra_value(&self, t: &Token<'a>, read: Token<'a>) -> Diagnostic {
        let e = Entity { keyword: entity_keyword(read.text).unwrap_or("?"), line: read.line };
        if let Some((n, odd, patch)) = self.odd_polygon_line(&read) {
            let mut d = self.odd_line_error(&odd, n, patch);
            d.note = Some(format!(
                "the `{}` on line {} ended before `{}` at {}:{}, which is left over",
                e.keyword,
                e.line,
                t.display(),
                t.line,
                self.column(t)
            ));
            return d;
        }
        let mut d = self.error_at(
            t,
            format!("extra value `{}` after the `{}` on line {}", t.display(), e.keyword, e.line),
        );
        d.note = Some(e.takes(self.opts.dialect == crate::scene::Dialect::P3f).to_string());
        d
    }

    /// The error `d` of the entity that `keyword` starts, blamed on a line
    /// of a polygon's vertices that holds a number too few or too many,
    /// when there is one: where the reader failed is later, and the vertex
    /// it names is not the one that was short.
    #[cold]
    #[inline(never)]
    pub(super) fn blame_odd_line(&self, d: Diagnostic, keyword: &Token<'a>) -> Diagnostic {
        // The vertices ran out at a word or the end of the file, which is
        // left unread; not a number that was read but refused (`inf`), nor
        // a count out of range.
        let ran_out = self.peeked.is_some();
        let Some((n, odd, patch)) = self.odd_polygon_line(keyword).filter(|_| ran_out) else {
            return d;
        };
        let mut blamed = self.odd_line_error(&odd, n, patch);
        blamed.note = Some(format!(
            "so the `{}` on line {} read on, and failed at {}:{}: {}",
            keyword.display(),
            keyword.line,
            d.line,
            d.column,
            d.message
        ));
        blamed
    }

    /// For the polygon or patch whose keyword is `keyword`: its vertex
    /// count, its first line of numbers no whole number of vertices makes
    /// ([`Self::odd_line`]), and whether it is a patch. The count is read
    /// again from the source.
    fn odd_polygon_line(&self, keyword: &Token<'a>) -> Option<(u64, OddLine<'a>, bool)> {
        let patch = match keyword.text {
            b"p" => false,
            b"pp" => true,
            _ => return None,
        };
        let count = Lexer::after(self.lexer.source(), keyword).next()?;
        let n = whole_number(count.text)?;
        Some((n, self.odd_line(&count, n, patch)?, patch))
    }

    /// The first line of a polygon's vertices that holds a number of
    /// numbers no whole number of vertices makes: not a multiple of 3 (or,
    /// for a patch written a vertex and its normal to a line, of 6). Lines
    /// are read again from the vertex count on, up to the first word or
    /// the line after the polygon's last number; only when a message needs
    /// them.
    fn odd_line(&self, count: &Token<'a>, n: u64, patch: bool) -> Option<OddLine<'a>> {
        let numbers = n * if patch { 6 } else { 3 };
        let mut unit = 3;
        let mut before = 0;
        let mut tokens = Lexer::after(self.lexer.source(), count)
            .take_while(|t| parse_number(t.text).is_some())
            .peekable();
        while let Some(first) = tokens.next() {
            let mut line = OddLine { first, last: first, count: 1, before, unit };
            while let Some(t) = tokens.next_if(|t| t.line == first.line) {
                line.last = t;
                line.count += 1;
            }
            if !line.count.is_multiple_of(unit) {
                return Some(line);
            }
            if patch && before == 0 && first.line != count.line && line.count.is_multiple_of(6) {
                unit = 6;
            }
            before += line.count;
            if before >= numbers {
                return None;
            }
        }
        None
    }

    /// "vertex 2 of 3 has 2 numbers on line 37, not 3", underlining the
    /// line's numbers.
    fn odd_line_error(&self, odd: &OddLine, n: u64, patch: bool) -> Diagnostic {
        let per_vertex = if patch { 6 } else { 3 };
        let k = odd.before / per_vertex + 1;
        let line = odd.first.line;
        let part =
            if patch && odd.unit == 3 && odd.before % 6 == 3 { "the normal of vertex" } else { "vertex" };
        let numbers = if odd.count == 1 { "number" } else { "numbers" };
        let message = if odd.count < 2 * odd.unit {
            format!("{part} {k} of {n} has {} {numbers} on line {line}, not {}", odd.count, odd.unit)
        } else {
            format!(
                "line {line} has {} numbers, not a whole number of vertices ({} each); {part} {k} of {n} starts there",
                odd.count, odd.unit
            )
        };
        let mut d = self.error_at(&odd.first, message);
        d.width = (self.column(&odd.last) + odd.last.width()).saturating_sub(d.column).max(1);
        d
    }
}
