//! Reading scene files (or standard input) and turning parse failures into
//! printed, compiler-like diagnostics.

use anyhow::{bail, Context, Result};
use nffkit_formats::dialect;
use nffkit_formats::nff::{self, escape, ParseOptions, Parsed, Report, Severity};
use nffkit_formats::Dialect;
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Files at least this large are memory-mapped rather than read, which
/// would copy every byte into freshly zeroed memory; smaller files gain
/// nothing.
const MAP_MIN_BYTES: u64 = 1 << 20;

/// A scene file's bytes: read into memory, or mapped from the file.
pub enum Source {
    /// Read (standard input and small files).
    Read(Vec<u8>),
    /// Memory-mapped (large regular files).
    Mapped(memmap2::Mmap),
}

impl std::ops::Deref for Source {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match self {
            Source::Read(v) => v,
            Source::Mapped(m) => m,
        }
    }
}

/// The bytes of `path`, or of standard input when `path` is `-`. Regular
/// files are read or mapped whole; anything else (standard input, a pipe,
/// a device) is a stream, read as [`read_stream`] says.
pub fn read_source(path: &Path) -> Result<Source> {
    if path.as_os_str() == "-" {
        return read_stream(&mut std::io::stdin().lock(), "standard input", stream_cap()).map(Source::Read);
    }
    let cannot = || format!("cannot read {}", path.display());
    let file = std::fs::File::open(path).with_context(cannot)?;
    let meta = file.metadata().with_context(cannot)?;
    if !meta.is_file() {
        let mut file = file;
        return read_stream(&mut file, &path.display().to_string(), stream_cap()).map(Source::Read);
    }
    if meta.len() >= MAP_MIN_BYTES {
        if let Some(map) = map(&file) {
            return Ok(Source::Mapped(map));
        }
    }
    std::fs::read(path).map(Source::Read).with_context(cannot)
}

/// A stream's bytes, read a megabyte at a time until it ends, or until a
/// NUL byte shows it is not text (`/dev/zero`, `/dev/urandom`, a binary
/// file; what was read goes to the reader, which names the problem at its
/// line), or refused when it passes `cap` bytes (a pipe fed for ever).
pub fn read_stream(r: &mut impl Read, name: &str, cap: u64) -> Result<Vec<u8>> {
    const CHUNK: usize = 1 << 20;
    let mut buf = Vec::new();
    loop {
        let start = buf.len();
        let n = r.take(CHUNK as u64).read_to_end(&mut buf).with_context(|| format!("reading {name}"))?;
        if n == 0 || buf[start..].contains(&0) {
            return Ok(buf);
        }
        if buf.len() as u64 > cap {
            bail!(
                "{name} passed {} without ending: a scene from a stream is read whole, up to \
                 {} (render --stream-limit MB raises it, to at most a third of the memory \
                 available); a file is mapped instead, without a limit",
                crate::memory::gib(buf.len() as u64),
                crate::memory::gib(cap)
            );
        }
    }
}

/// The most a stream may bring, set by `render --stream-limit`.
static STREAM_LIMIT: AtomicU64 = AtomicU64::new(DEFAULT_STREAM_LIMIT);

/// 2 GiB: more than any SPD database at its published size, and soon
/// reached by a pipe fed for ever.
pub const DEFAULT_STREAM_LIMIT: u64 = 2 << 30;

/// Set the most a stream may bring (this process's setting).
pub fn set_stream_limit(bytes: u64) {
    STREAM_LIMIT.store(bytes, Ordering::Relaxed);
}

/// The most a stream may bring: the limit set, and at most a third of the
/// memory available (the scene read from it takes about twice its size
/// again), but no less than 256 MB.
pub fn stream_cap() -> u64 {
    let memory = crate::memory::available().map_or(u64::MAX, |m| (m / 3).max(256 << 20));
    STREAM_LIMIT.load(Ordering::Relaxed).min(memory)
}

/// Map `file` for reading; `None` where mapping fails (then it is read).
#[allow(unsafe_code)]
fn map(file: &std::fs::File) -> Option<memmap2::Mmap> {
    // SAFETY: the map is only read, as bytes of any value. What mapping
    // cannot rule out is another process changing the file while it is
    // read: then the reader sees changed bytes (which it handles like any
    // bytes), or, if the file is truncated, the process gets SIGBUS. That
    // is the trade ripgrep makes for large files too; a scene being
    // rewritten under the renderer has no meaningful image anyway.
    unsafe { memmap2::Mmap::map(file) }.ok()
}

/// The name to show for a path in messages.
pub fn display_name(path: &Path) -> String {
    if path.as_os_str() == "-" {
        "<stdin>".into()
    } else {
        path.display().to_string()
    }
}

/// Which of a file's warnings to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Warnings {
    /// None (`--quiet`, and tools that only read fixtures).
    Hide,
    /// The first few of each kind, the rest counted.
    Summarise,
    /// Every one (`--all-warnings`).
    All,
}

/// The report that prints `src`'s diagnostics as `warnings` asks.
pub fn report<'s>(name: &'s str, src: &'s [u8], warnings: Warnings) -> Report<'s> {
    let report = Report::new(name, src);
    if warnings == Warnings::All {
        report.all()
    } else {
        report
    }
}

/// Read and parse a scene in its language (`dialect`, else as
/// [`dialect::detect`] finds), printing its warnings as `warnings` asks and
/// every error to stderr; notes (uses of documented extensions) are left to
/// `--check`. Fails with a one-line summary when the file has errors.
pub fn load_scene(
    path: &Path,
    opts: &ParseOptions,
    dialect: Option<Dialect>,
    warnings: Warnings,
) -> Result<Parsed> {
    let src = read_source(path)?;
    let name = display_name(path);
    let mut out = report(&name, &src, warnings);
    let opts = ParseOptions { dialect: dialect::detect(path, &src, dialect), ..*opts };
    match nff::parse(&src, &opts) {
        Ok(parsed) => {
            if warnings != Warnings::Hide {
                for d in parsed.diagnostics.iter().filter(|d| d.severity == Severity::Warning) {
                    out.render(d).inspect(|text| crate::eprint_safe!("{text}"));
                }
                crate::eprint_safe!("{}", out.held_back());
            }
            Ok(parsed)
        }
        Err(e) => {
            for d in
                e.diagnostics.iter().filter(|d| warnings != Warnings::Hide || d.severity == Severity::Error)
            {
                out.render(d).inspect(|text| crate::eprint_safe!("{text}"));
            }
            crate::eprint_safe!("{}", out.held_back());
            bail!("{name}: {}", escape(&e.to_string()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_files_are_mapped_small_ones_read_both_whole() {
        let dir = tempfile::tempdir().unwrap();
        let small = dir.path().join("small.nff");
        let large = dir.path().join("large.nff");
        let line = b"s 0.272166 0.272166 0.544331 0.166667\n";
        std::fs::write(&small, line).unwrap();
        let big: Vec<u8> = line.iter().copied().cycle().take(MAP_MIN_BYTES as usize + 7).collect();
        std::fs::write(&large, &big).unwrap();

        let s = read_source(&small).unwrap();
        assert!(matches!(s, Source::Read(_)));
        assert_eq!(&*s, line);
        let l = read_source(&large).unwrap();
        assert!(matches!(l, Source::Mapped(_)));
        assert_eq!(&*l, &big[..]);
        let missing = read_source(&dir.path().join("missing.nff"));
        assert!(missing.is_err_and(|e| e.to_string().contains("cannot read")));
    }
}
