//! The playground's files in the demo folder: its page, scripts and the
//! tracer's WebAssembly module (built by `cargo playground`), under
//! `OUT/playground/`. The page's sampler and filter menus are filled here
//! from the tracer's own lists, so a new pattern appears without an edit.

use anyhow::{bail, Context, Result};
use nffkit_formats::atomic;
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::sampling::SamplerKind;
use std::path::{Path, PathBuf};

const PAGE: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../playground/web/index.html"));
const SCRIPT: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../playground/web/playground.js"));
const WORKER: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../playground/web/worker.js"));

/// The module's file name.
pub const WASM: &str = "nffkit_playground.wasm";

/// Where `cargo playground` leaves the module, seen from this program's
/// own folder (`target/release/aademo` beside
/// `target/wasm32-unknown-unknown/wasm/`).
pub fn built_wasm() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?.canonicalize().ok()?;
    let target = exe.parent()?.parent()?;
    Some(target.join("wasm32-unknown-unknown").join("wasm").join(WASM))
}

/// Read the module at `wasm`, checking it is WebAssembly (before any
/// rendering, so a missing build is said at once).
pub fn read_wasm(wasm: &Path) -> Result<Vec<u8>> {
    let module = std::fs::read(wasm).with_context(|| {
        format!(
            "the playground's WebAssembly ({}) is not built: run `cargo playground` \
             (after `rustup target add wasm32-unknown-unknown`), or name the module with --wasm",
            wasm.display()
        )
    })?;
    if !module.starts_with(b"\0asm") {
        bail!("{} is not a WebAssembly module", wasm.display());
    }
    Ok(module)
}

fn options<T: Copy + Into<&'static str>>(all: &[T], selected: &str) -> String {
    all.iter()
        .map(|&k| {
            let name: &str = k.into();
            let sel = if name == selected { " selected" } else { "" };
            format!("<option{sel}>{name}</option>")
        })
        .collect()
}

/// Write the playground, with its `module` (from [`read_wasm`]), into
/// `dir/playground/`; returns its page.
pub fn write(dir: &Path, module: &[u8]) -> Result<PathBuf> {
    let out = dir.join("playground");
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let page = PAGE
        .replace("{{SAMPLERS}}", &options(SamplerKind::ALL, SamplerKind::MultiJittered.into()))
        .replace("{{FILTERS}}", &options(FilterKind::ALL, FilterKind::Box.into()));
    atomic::write_bytes(&out.join("index.html"), page.as_bytes())?;
    atomic::write_bytes(&out.join("playground.js"), SCRIPT.as_bytes())?;
    atomic::write_bytes(&out.join("worker.js"), WORKER.as_bytes())?;
    atomic::write_bytes(&out.join(WASM), module)?;
    Ok(out.join("index.html"))
}
