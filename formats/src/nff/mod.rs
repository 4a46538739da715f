//! The Neutral File Format: reading ([`parse`], in `read.rs`, above the
//! sequential reader `parse/` and the parallel one `parallel.rs`), writing
//! ([`write`], [`NffWriter`]) and the diagnostics that point into the
//! source ([`Diagnostic`]).
//!
//! NFF is read as a stream of whitespace-separated tokens, not lines: the SPD
//! writes a cone on one line where the spec shows three, and real files wrap
//! polygons freely. `#` starts a comment anywhere on a line.

mod diag;
mod geometry_checks;
mod lexer;
mod number;
mod parallel;
mod parse;
mod read;
mod write;

pub use diag::{escape, Diagnostic, Report, Severity, SHOWN_PER_KIND};
pub(crate) use parse::P3F_KEYWORDS;
pub use parse::{parse_sequential, ParseError, ParseOptions, Parsed, MAX_VERTICES};
pub use read::{parse, parse_chunked};
pub use write::{format_number, write, NffWriter};
