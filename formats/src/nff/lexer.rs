//! Splits NFF source into tokens with their positions.
//!
//! Whitespace (space, tab, CR, LF, form feed, vertical tab) separates tokens;
//! `#` ends the line as a comment, even in the middle of a token. Lines end
//! at LF, CR LF, or a CR alone (old Mac files). Any byte sequence is
//! accepted: a token that is not UTF-8 is reported by the parser like any
//! other unexpected token.

use super::number::number_prefix;

/// A token: its bytes and where it starts.
#[derive(Debug, Clone, Copy)]
pub struct Token<'a> {
    pub text: &'a [u8],
    pub line: u32,
    /// The token's line up to the token: its column is counted from this
    /// only when a message needs it (see [`Token::column`]).
    pub before: &'a [u8],
    /// The first token on its line (error recovery restarts at such tokens).
    pub starts_line: bool,
}

impl Token<'_> {
    /// The token for messages: lossily decoded and shortened.
    pub fn display(&self) -> String {
        let s = String::from_utf8_lossy(self.text);
        if s.chars().count() > 40 {
            let short: String = s.chars().take(40).collect();
            format!("{short}...")
        } else {
            s.into_owned()
        }
    }

    /// Column in characters, 1-based.
    pub fn column(&self) -> u32 {
        char_count(self.before) + 1
    }

    /// Characters in `bytes` (UTF-8 lead bytes).
    pub fn char_count(bytes: &[u8]) -> u32 {
        char_count(bytes)
    }

    /// Width in characters, for underlining.
    pub fn width(&self) -> u32 {
        char_count(self.text).clamp(1, 200)
    }
}

fn char_count(bytes: &[u8]) -> u32 {
    // UTF-8 continuation bytes are 0b10xx_xxxx; count every other byte.
    bytes.iter().filter(|&&b| b & 0xC0 != 0x80).count() as u32
}

/// The byte offsets where the lines of `src` start, by the lexer's rule.
pub(super) fn line_starts(src: &[u8]) -> Vec<usize> {
    let mut starts = vec![0];
    for (i, &b) in src.iter().enumerate() {
        if b == b'\n' || (b == b'\r' && src.get(i + 1) != Some(&b'\n')) {
            starts.push(i + 1);
        }
    }
    starts
}

/// An iterator over tokens.
pub struct Lexer<'a> {
    src: &'a [u8],
    pos: usize,
    line: u32,
    /// Line of the last token returned (0 before the first).
    last_line: u32,
    /// Where the current line starts.
    line_start: usize,
}

impl<'a> Lexer<'a> {
    /// A lexer over `src`, which begins at the start of line `line` of its
    /// file (1 for a whole file; later for a chunk of a large one).
    pub fn starting_at(src: &'a [u8], line: u32) -> Self {
        Lexer { src, pos: 0, line, last_line: 0, line_start: 0 }
    }

    /// The source being read.
    pub fn source(&self) -> &'a [u8] {
        self.src
    }

    /// The line the lexer has reached: past the end of its source, the
    /// first line plus every line break in it.
    pub fn line(&self) -> u32 {
        self.line
    }

    /// A lexer over `src` that goes on after `t`, a token of `src` (or of
    /// a longer source `src` is the start of, if `t` lies within `src`),
    /// with the lines and columns the first lexer gave.
    pub fn after(src: &'a [u8], t: &Token<'a>) -> Self {
        let offset = |bytes: &[u8]| (bytes.as_ptr() as usize).saturating_sub(src.as_ptr() as usize);
        let pos = (offset(t.text) + t.text.len()).min(src.len());
        let line_start = offset(t.before).min(pos);
        Lexer { src, pos, line: t.line, last_line: t.line, line_start }
    }
}

/// Byte classes, looked up rather than compared in the hot loops.
const TOKEN: u8 = 0;
const SPACE: u8 = 1;
const NEWLINE: u8 = 2;
const COMMENT: u8 = 3;
const CR: u8 = 4;

const CLASS: [u8; 256] = {
    let mut c = [TOKEN; 256];
    c[b' ' as usize] = SPACE;
    c[b'\t' as usize] = SPACE;
    c[b'\r' as usize] = CR;
    c[0x0b] = SPACE;
    c[0x0c] = SPACE;
    c[b'\n' as usize] = NEWLINE;
    c[b'#' as usize] = COMMENT;
    c
};

impl<'a> Lexer<'a> {
    /// Skip whitespace and comments up to the next token; `false` at the
    /// end of the source.
    #[inline]
    fn skip_space(&mut self) -> bool {
        let src = self.src;
        loop {
            let Some(&b) = src.get(self.pos) else { return false };
            match CLASS[b as usize] {
                NEWLINE => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                SPACE => self.pos += 1,
                // A CR before an LF is space; alone, it ends the line.
                CR if src.get(self.pos + 1) == Some(&b'\n') => self.pos += 1,
                CR => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                COMMENT => {
                    self.pos += src[self.pos..]
                        .iter()
                        .position(|&b| b == b'\n' || b == b'\r')
                        .unwrap_or(src.len() - self.pos);
                }
                _ => return true,
            }
        }
    }

    /// The token from `start` to the current position.
    #[inline]
    fn token(&mut self, start: usize) -> Token<'a> {
        let starts_line = self.line != self.last_line;
        self.last_line = self.line;
        let before = &self.src[self.line_start..start];
        Token { text: &self.src[start..self.pos], line: self.line, before, starts_line }
    }

    /// The next token and its value if the token is a number, both found in
    /// one pass over its bytes (the reader's hot path: NFF is mostly
    /// numbers). Otherwise `None`, having consumed only the whitespace
    /// before the token, so [`Iterator::next`] returns it as usual. The
    /// value is the one [`parse_number`](super::number::parse_number) gives
    /// for the token.
    #[inline]
    pub fn number(&mut self) -> Option<(f64, Token<'a>)> {
        let (value, start) = self.next_number()?;
        Some((value, self.token(start)))
    }

    /// The next `N` tokens when every one is a finite number (as
    /// [`Lexer::number`] takes them), their values and the last of them;
    /// otherwise `None`, with nothing consumed. The reader's path for an
    /// entity's numbers: only the last token is made, the one a later
    /// message may point at.
    #[inline]
    pub fn numbers<const N: usize>(&mut self) -> Option<([f64; N], Token<'a>)> {
        let saved = (self.pos, self.line, self.last_line, self.line_start);
        let mut values = [0.0; N];
        for k in 0..N {
            let Some((value, start)) = self.next_number().filter(|(v, _)| v.is_finite()) else { break };
            values[k] = value;
            if k + 1 == N {
                return Some((values, self.token(start)));
            }
            // What making its token would record.
            self.last_line = self.line;
        }
        (self.pos, self.line, self.last_line, self.line_start) = saved;
        None
    }

    /// [`Lexer::number`] without making the token: the value and where
    /// the token starts, the lexer past it; `None` with only the
    /// whitespace before the next token consumed.
    #[inline(always)]
    fn next_number(&mut self) -> Option<(f64, usize)> {
        if !self.skip_space() {
            return None;
        }
        let start = self.pos;
        let (value, len) = number_prefix(&self.src[start..])?;
        // A number glued to more token bytes (`1.5x`, `1e`) is not one.
        if self.src.get(start + len).is_some_and(|&b| CLASS[b as usize] == TOKEN) {
            return None;
        }
        self.pos = start + len;
        Some((value, start))
    }
}

impl<'a> Iterator for Lexer<'a> {
    type Item = Token<'a>;

    #[inline]
    fn next(&mut self) -> Option<Token<'a>> {
        if !self.skip_space() {
            return None;
        }
        let src = self.src;
        let start = self.pos;
        self.pos +=
            src[start..].iter().position(|&b| CLASS[b as usize] != TOKEN).unwrap_or(src.len() - start);
        Some(self.token(start))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nff::number::parse_number;

    fn tokens(s: &str) -> Vec<(String, u32, u32)> {
        Lexer::starting_at(s.as_bytes(), 1).map(|t| (t.display(), t.line, t.column())).collect()
    }

    #[test]
    fn splits_on_any_whitespace_and_tracks_positions() {
        let t = tokens("b 1\t2\r\n  3 # four\n#five\ns");
        let expect = [("b", 1, 1), ("1", 1, 3), ("2", 1, 5), ("3", 2, 3), ("s", 4, 1)];
        assert_eq!(t.len(), expect.len());
        for (got, want) in t.iter().zip(expect) {
            assert_eq!((got.0.as_str(), got.1, got.2), want);
        }
    }

    #[test]
    fn comment_cuts_a_token() {
        let t = tokens("1.5#x 2\n3");
        assert_eq!(t[0].0, "1.5");
        assert_eq!(t[1].0, "3");
    }

    #[test]
    fn columns_equal_counting_from_the_line_start() {
        let src = "λ a  é#c é\n\t x   yy λλλ z\n\n  #\n q é é é\r\n w";
        for t in Lexer::starting_at(src.as_bytes(), 1) {
            let line = src.lines().nth(t.line as usize - 1).unwrap();
            let byte = t.text.as_ptr() as usize - line.as_ptr() as usize;
            assert_eq!(t.column(), line[..byte].chars().count() as u32 + 1, "{}", t.display());
        }
    }

    proptest::proptest! {
        /// Reading numbers in one pass finds the tokens, positions and
        /// values that tokenising and then parsing find.
        #[test]
        fn numbers_read_in_one_pass_match_tokens_then_parse(src in "[0-9.eE+x#\\- \n\t]{0,40}") {
            let plain: Vec<_> = Lexer::starting_at(src.as_bytes(), 1)
                .map(|t| (t.text, t.line, t.column(), t.starts_line, parse_number(t.text).map(f64::to_bits)))
                .collect();
            let mut fused = Vec::new();
            let mut lexer = Lexer::starting_at(src.as_bytes(), 1);
            loop {
                if let Some((v, t)) = lexer.number() {
                    fused.push((t.text, t.line, t.column(), t.starts_line, Some(v.to_bits())));
                } else if let Some(t) = lexer.next() {
                    // Not a number by the fast path: must not be one at all.
                    fused.push((t.text, t.line, t.column(), t.starts_line, parse_number(t.text).map(f64::to_bits)));
                    proptest::prop_assert!(fused.last().unwrap().4.is_none(), "{:?}", src);
                } else {
                    break;
                }
            }
            proptest::prop_assert_eq!(plain, fused);
        }

        /// Three numbers at once are the next three tokens when all are
        /// finite numbers, the last one's token as tokenising gives it;
        /// otherwise nothing is consumed.
        #[test]
        fn numbers_at_once_are_the_next_tokens_or_none(
            words in proptest::collection::vec(
                (
                    proptest::sample::select(vec!["1", "-2.5", ".5", "1e999", "inf", "x", "1x", "#c", "0"]),
                    proptest::sample::select(vec![" ", "\n", "\r\n", "\r", "\t"]),
                ),
                0..24,
            ),
        ) {
            let src: String = words.iter().map(|(w, sep)| format!("{w}{sep}")).collect();
            let plain: Vec<_> = Lexer::starting_at(src.as_bytes(), 1)
                .map(|t| (t.text, t.line, t.column(), t.starts_line, parse_number(t.text)))
                .collect();
            let finite = |k: usize| plain.get(k).and_then(|p| p.4).is_some_and(f64::is_finite);
            let (mut lexer, mut k) = (Lexer::starting_at(src.as_bytes(), 1), 0);
            while k < plain.len() {
                if let Some((values, t)) = lexer.numbers::<3>() {
                    proptest::prop_assert!((k..k + 3).all(finite), "{:?}", src);
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    let want: Vec<f64> = plain[k..k + 3].iter().map(|p| p.4.unwrap()).collect();
                    proptest::prop_assert_eq!(bits(&values), bits(&want));
                    let last = &plain[k + 2];
                    proptest::prop_assert_eq!((t.text, t.line, t.column(), t.starts_line), (last.0, last.1, last.2, last.3));
                    k += 3;
                } else {
                    proptest::prop_assert!(!(k..k + 3).all(finite), "{:?}", src);
                    let t = lexer.next().expect("a token is left");
                    let p = &plain[k];
                    proptest::prop_assert_eq!((t.text, t.line, t.column(), t.starts_line), (p.0, p.1, p.2, p.3));
                    k += 1;
                }
            }
            proptest::prop_assert!(lexer.next().is_none());
        }
    }

    #[test]
    fn a_lone_cr_ends_a_line_as_lf_and_cr_lf_do() {
        let t = tokens("a\rb\r\nc\nd # e\rf");
        let lines: Vec<u32> = t.iter().map(|t| t.1).collect();
        assert_eq!(lines, [1, 2, 3, 4, 5]);
        assert_eq!(line_starts(b"a\rb\r\nc"), [0, 2, 5]);
    }

    #[test]
    fn columns_count_characters() {
        let t = tokens("# é\nλλ x");
        assert_eq!((t[1].1, t[1].2), (2, 4));
    }
}
