//! Helpers shared by the integration tests.

use std::path::Path;
use std::process::Command;

/// A GLB file: the JSON chunk (padded with spaces) and the binary chunk
/// (padded with zeros), behind the 12-byte header.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + j.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// A program a test runs (the farm tests, the exporters' readers), or `None` (the test is skipped, saying so)
/// where it is missing, unless NFFKIT_TEST_TOOLS=required (the README's
/// test command, which CI runs): then a missing one fails. The PyPI
/// programs are looked for in the virtual environment
/// `scripts/install-test-tools.sh` makes (target/test-tools, or
/// NFFKIT_TEST_VENV), then on PATH.
pub fn program(name: &str) -> Option<std::path::PathBuf> {
    let venv = std::env::var_os("NFFKIT_TEST_VENV")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-tools"));
    let found = Some(venv.join("bin").join(name)).filter(|p| p.is_file()).or_else(|| {
        let o = Command::new("sh").args(["-c", &format!("command -v {name}")]).output().ok()?;
        o.status.success().then(|| String::from_utf8_lossy(&o.stdout).trim().into())
    });
    if found.is_none() {
        let required = std::env::var("NFFKIT_TEST_TOOLS").is_ok_and(|v| v == "required");
        assert!(!required, "{name} is missing (scripts/install-test-tools.sh installs it)");
        eprintln!("skipped: {name} is not installed (scripts/install-test-tools.sh installs it)");
    }
    found
}
