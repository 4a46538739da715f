//! Reading NFF: the one entry point, [`parse`]. A file of a megabyte or
//! more goes to the parallel reader ([`super::parallel`], chunks on every
//! core); everything else, and whatever the parallel reader hands back,
//! to the sequential one ([`super::parse`]). The result and the
//! diagnostics are the sequential reader's either way.

use super::parallel::{default_chunks, parse_in_chunks, PARALLEL_MIN_BYTES};
use super::parse::{parse_sequential, strip_dos_eof, utf16, ParseError, ParseOptions, Parsed, BOM};

/// Read an NFF scene from bytes. Never panics, whatever the bytes. Files
/// of several megabytes are read on every core ([`parse_chunked`]), with
/// exactly the result and diagnostics of [`parse_sequential`].
pub fn parse(src: &[u8], opts: &ParseOptions) -> Result<Parsed, ParseError> {
    let len = strip_dos_eof(src).len();
    if len >= PARALLEL_MIN_BYTES {
        if let Some(parsed) = parse_chunked(src, opts, default_chunks(len)) {
            return Ok(parsed);
        }
    }
    parse_sequential(src, opts)
}

/// `src` read in `chunks` pieces on as many threads, when that gives
/// exactly what [`parse_sequential`] gives; `None` when the file must be
/// read in one piece (it says something, or cannot be cut).
pub fn parse_chunked(src: &[u8], opts: &ParseOptions, chunks: usize) -> Option<Parsed> {
    let body = strip_dos_eof(src);
    if body.starts_with(BOM) || utf16(body).is_some() {
        return None;
    }
    parse_in_chunks(body, opts, chunks)
}
