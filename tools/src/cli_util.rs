//! Small pieces every binary shares: argument value parsers, options
//! parsed from a list of words, writing output to a file (atomically) or
//! standard output, and the process around a command ([`run_main`]):
//! temporary files removed on Ctrl-C or SIGTERM, a closed pipe ending the
//! program quietly, errors printed once.

use anyhow::{Context, Result};
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;

pub use nffkit_gen::options::{parse_args, parse_pair, parse_resolution, parse_squares, parse_triple};

/// A scene language, `nff` or `p3f` (`--dialect`).
pub fn parse_dialect(s: &str) -> Result<nffkit_formats::Dialect, String> {
    s.to_ascii_lowercase().parse().map_err(|_| format!("`{s}` is no scene language; expected nff or p3f"))
}

/// Write through `f` to `path` (atomically: a failure leaves no partial
/// file) or to standard output when `None`.
pub fn write_output(path: Option<&Path>, f: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    match path {
        None => {
            let stdout = io::stdout();
            let mut w = BufWriter::new(stdout.lock());
            match f(&mut w).and_then(|_| w.flush()) {
                Ok(()) => Ok(()),
                // A closed pipe (`| head`) is not an error worth a message.
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(e).context("writing to standard output"),
            }
        }
        Some(path) => Ok(nffkit_formats::atomic::write_with(path, f)?),
    }
}

/// `eprintln!` that never panics: a message that cannot reach a closed or
/// full standard error is dropped (there is nowhere left to report it).
#[macro_export]
macro_rules! eprintln_safe {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `eprint!` that never panics (see [`eprintln_safe!`]).
#[macro_export]
macro_rules! eprint_safe {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

/// Print `text` to standard output: an error where the write fails (a full
/// disk), which [`exit`] turns into a quiet end for a closed pipe.
pub fn print(text: impl std::fmt::Display) -> Result<()> {
    let mut out = io::stdout().lock();
    write!(out, "{text}").and_then(|_| out.flush()).context("writing to standard output")
}

/// Run a command's body: temporary files are removed if the process is
/// interrupted (SIGINT, SIGTERM, SIGHUP; it then exits with 130), and an
/// error is printed, its chain once, with exit code 1. A closed pipe is no
/// error (the reader had what it wanted): exit 0 without a word, as
/// ripgrep does.
pub fn run_main(tool: &str, body: impl FnOnce() -> Result<ExitCode>) -> ExitCode {
    remove_partial_files_on_interrupt();
    if let Some(problem) = nffkit_tracer::simd::cap_problem() {
        eprintln_safe!("{tool}: warning: {problem}");
    }
    match body() {
        Ok(code) => code,
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln_safe!("{tool}: error: {}", chain_once(&e));
            ExitCode::FAILURE
        }
    }
}

/// Install, once, the handler that removes the atomic writer's temporary
/// files when a signal ends the process.
fn remove_partial_files_on_interrupt() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Failing to install it (another handler) only loses the clean-up.
        let _ = ctrlc::set_handler(|| {
            nffkit_formats::atomic::remove_pending();
            std::process::exit(130);
        });
    });
}

/// Run `load`, turning a panic inside it (in a dependency: the project's
/// own checks come first, this is the last line of defence) into an error
/// naming the file, without the panic's own report.
pub fn without_panics<T>(name: &str, load: impl FnOnce() -> T) -> Result<T> {
    static MESSAGE: std::sync::Mutex<String> = std::sync::Mutex::new(String::new());
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        *MESSAGE.lock().unwrap_or_else(|e| e.into_inner()) = format!("{}{at}", panic_text(info.payload()));
    }));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(load));
    std::panic::set_hook(previous);
    result.map_err(|_| {
        let why = MESSAGE.lock().unwrap_or_else(|e| e.into_inner()).clone();
        anyhow::anyhow!("cannot convert {name}: a library it uses failed on this file ({why}); the file is malformed in a way not yet named")
    })
}

/// A panic's message, when it is text.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> &str {
    payload
        .downcast_ref::<&str>()
        .copied()
        .or(payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("a panic")
}

/// Whether `e` comes from writing to a closed pipe.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.downcast_ref::<io::Error>().is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe))
}

/// The error chain joined by `: `, each part once: some errors repeat
/// their source in their own message ("Unknown filter method 210.: Unknown
/// filter method 210.").
pub fn chain_once(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for part in e.chain().map(|c| c.to_string()) {
        if text.contains(&part) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&part);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_becomes_an_error_naming_the_file() {
        let e =
            without_panics("m.gltf", || -> u32 { panic!("index out of bounds") }).unwrap_err().to_string();
        assert!(e.contains("cannot convert m.gltf") && e.contains("index out of bounds"), "{e}");
        assert_eq!(without_panics("m.gltf", || 7).unwrap(), 7);
        assert!(chain_once(&anyhow::anyhow!("a: b").context("a: b")).matches("a: b").count() == 1);
    }
}
