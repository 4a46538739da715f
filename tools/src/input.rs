//! Reading scene files (or standard input) and turning parse failures into
//! printed, compiler-like diagnostics.

use anyhow::{bail, Context, Result};
use nffkit_formats::nff::{self, ParseOptions, Parsed, Severity};
use std::io::Read;
use std::path::Path;

/// The bytes of `path`, or of standard input when `path` is `-`.
pub fn read_source(path: &Path) -> Result<Vec<u8>> {
    if path.as_os_str() == "-" {
        let mut buf = Vec::new();
        std::io::stdin().read_to_end(&mut buf).context("reading the scene from standard input")?;
        Ok(buf)
    } else {
        std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
    }
}

/// The name to show for a path in messages.
pub fn display_name(path: &Path) -> String {
    if path.as_os_str() == "-" {
        "<stdin>".into()
    } else {
        path.display().to_string()
    }
}

/// Read and parse a scene, printing warnings (unless `quiet`) and every error
/// to stderr; notes (uses of documented extensions) are left to `--check`. Fails with a one-line summary when the file has errors.
pub fn load_scene(path: &Path, opts: &ParseOptions, quiet: bool) -> Result<Parsed> {
    let src = read_source(path)?;
    let name = display_name(path);
    match nff::parse(&src, opts) {
        Ok(parsed) => {
            if !quiet {
                for d in parsed.diagnostics.iter().filter(|d| d.severity != Severity::Note) {
                    eprint!("{}", d.render(&name, &src));
                }
            }
            Ok(parsed)
        }
        Err(e) => {
            for d in &e.diagnostics {
                eprint!("{}", d.render(&name, &src));
            }
            bail!("{name}: {e}")
        }
    }
}
