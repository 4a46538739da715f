//! The playground in a real browser: the WebAssembly module built as the
//! README builds it (`cargo playground`), the page written by `aademo
//! --playground` and served by `aademo --serve`, driven in headless
//! Chromium (puppeteer-core): a sampler and a count set on the form, the
//! canvas read back after the last pass and compared, byte for byte, with
//! `render`'s PNG from the command the page prints.

use crate::common::program;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

const AADEMO: &str = env!("CARGO_BIN_EXE_aademo");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `cargo playground`, as the README runs it; the module's path.
fn build_wasm() -> PathBuf {
    let o = Command::new(env!("CARGO")).arg("playground").current_dir(root()).output().unwrap();
    assert!(
        o.status.success(),
        "cargo playground failed (rustup target add wasm32-unknown-unknown?):\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    root().join("target/wasm32-unknown-unknown/wasm/nffkit_playground.wasm")
}

/// `aademo --serve`, stopped when dropped.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn serve(dir: &Path) -> (Server, u16) {
    let mut child = Command::new(AADEMO)
        .args(["--out", dir.to_str().unwrap(), "--serve", "--port", "0"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let port = line.split("127.0.0.1:").nth(1).and_then(|r| r.split('/').next()).and_then(|p| p.parse().ok());
    (Server(child), port.unwrap_or_else(|| panic!("no port in `{line}`")))
}

#[test]
fn the_playground_in_chromium_renders_what_render_renders() {
    let (Some(node), Some(chromium)) = (program("node"), program("chromium")) else { return };
    let pptr = root().join("target/test-tools/npm/node_modules/puppeteer-core");
    if !pptr.is_dir() {
        let required = std::env::var("NFFKIT_TEST_TOOLS").is_ok_and(|v| v == "required");
        assert!(!required, "puppeteer-core is missing (scripts/install-test-tools.sh installs it)");
        eprintln!("skipped: puppeteer-core is not installed");
        return;
    }
    let wasm = build_wasm();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = Command::new(AADEMO)
        .args(["--out", out.to_str().unwrap(), "--playground", "--wasm", wasm.to_str().unwrap()])
        .args(["--size", "32", "--spp", "1,4", "--reference-spp", "16", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_server, port) = serve(&out);
    let url = format!("http://127.0.0.1:{port}/playground/?size=128&refspp=64&squares=24&rotate=30");
    let result = dir.path().join("browser");
    let o = Command::new(node)
        .arg(root().join("tools/tests/support/playground-drive.js"))
        .args([&pptr, &chromium, Path::new(&url), &result, Path::new("-")])
        .args(["sampler=cmj", "spp=16"])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(result.with_extension("json")).unwrap()).unwrap();
    let command = report["command"].as_str().unwrap();
    assert_eq!(
        command,
        "planegen --nx 24 --ny 24 --rotate 30 | render - --width 128 --height 128 --sampler cmj --spp 16 \
         --filter box --seed 1 -o playground.png"
    );
    assert_eq!((report["width"].as_u64(), report["passes"].as_u64()), (Some(128), Some(16)));
    // The error against the reference falls as the passes go.
    let rmse: Vec<f64> = report["rmse"].as_array().unwrap().iter().map(|p| p[1].as_f64().unwrap()).collect();
    assert_eq!(rmse.len(), 16, "{report}");
    assert!(rmse[15] < 0.5 * rmse[0], "{rmse:?}");
    assert!(report["caption"].as_str().unwrap().contains("16 samples of cmj, 16 taken"), "{report}");
    // The page's command, run with this build's binaries.
    let bin = Path::new(AADEMO).parent().unwrap();
    let png = dir.path().join("render.png");
    let shell = command
        .replace("planegen ", &format!("{}/planegen ", bin.display()))
        .replace("| render ", &format!("| {}/render ", bin.display()));
    let shell = shell.replace("playground.png", png.to_str().unwrap());
    let o = Command::new("sh").args(["-c", &shell]).output().unwrap();
    assert!(o.status.success(), "{shell}: {}", String::from_utf8_lossy(&o.stderr));
    let want = image::open(&png).unwrap().to_rgba8();
    let got = std::fs::read(result.with_extension("rgba")).unwrap();
    assert_eq!(got.len(), want.as_raw().len());
    let differ = got.iter().zip(want.as_raw()).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} canvas bytes differ from render's PNG");
}
