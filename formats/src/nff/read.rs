//! Reading NFF: the one entry point, [`parse`]. A file of a megabyte or
//! more goes to the parallel reader ([`super::parallel`], chunks on every
//! core); everything else, and whatever the parallel reader hands back,
//! to the sequential one ([`super::parse`]). The result and the
//! diagnostics are the sequential reader's either way.

use super::parallel::{default_chunks, parse_in_chunks, PARALLEL_MIN_BYTES};
use super::parse::{parse_sequential, strip_dos_eof, utf16, ParseError, ParseOptions, Parsed, BOM};

/// Read an NFF scene from bytes. Never panics, whatever the bytes. Files
/// of several megabytes are read on every core ([`parse_in_chunks`]), with
/// exactly the result and diagnostics of [`parse_sequential`].
pub fn parse(src: &[u8], opts: &ParseOptions) -> Result<Parsed, ParseError> {
    let body = strip_dos_eof(src);
    if body.len() >= PARALLEL_MIN_BYTES && !body.starts_with(BOM) && utf16(body).is_none() {
        if let Some(parsed) = parse_in_chunks(body, opts, default_chunks(body.len())) {
            return Ok(parsed);
        }
    }
    parse_sequential(src, opts)
}
