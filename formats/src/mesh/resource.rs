//! Files a model refers to (glTF buffers and images, OBJ material libraries
//! and textures), and the rule for which ones may be read.
//!
//! A model downloaded from elsewhere must not make the converter read files
//! outside the model's folder: an absolute path, a scheme (`file:`), a drive
//! letter or a `..` component is refused unless the user allows it
//! ([`ImportOptions::allow_outside_paths`]).

use base64::Engine;
use std::path::{Path, PathBuf};

/// What an import may read beyond the model file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImportOptions {
    /// Read base-colour and emission textures (off: the factors alone).
    pub textures: bool,
    /// Follow references that leave the model's folder.
    pub allow_outside_paths: bool,
    /// The most triangles a model may expand to (and three times as many
    /// elements in any one accessor), checked before anything is read.
    pub max_triangles: u64,
    /// The most memory the decoded textures may take in all.
    pub max_texture_bytes: u64,
}

/// The default bound on the decoded textures' memory: 1 GiB.
pub const MAX_TEXTURE_BYTES: u64 = 1 << 30;

/// The default bound on a model's triangles: 20 million (an NFF file of
/// about 3 GB).
pub const MAX_TRIANGLES: u64 = 20_000_000;

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            textures: true,
            allow_outside_paths: false,
            max_triangles: MAX_TRIANGLES,
            max_texture_bytes: MAX_TEXTURE_BYTES,
        }
    }
}

/// Whether a relative reference stays inside its folder.
fn stays_inside(reference: &str) -> bool {
    let first = reference.split(['/', '\\']).next().unwrap_or("");
    !(reference.starts_with(['/', '\\'])
        || first.contains(':')
        || Path::new(reference).is_absolute()
        || reference.split(['/', '\\']).any(|c| c == ".."))
}

/// The largest file a model may reference (a buffer, an image, a material
/// library).
pub const MAX_REFERENCED_BYTES: u64 = 2 << 30;

/// `reference` (a plain path) resolved against `dir`, or why it may not be
/// read. Checked as text first (no absolute path, no `..`), then, when it
/// exists, where it really is: every link followed, it must still lie in
/// `dir` (a link inside the folder may point anywhere), be a regular file
/// (not a device or a pipe: `/dev/zero` behind a link) and hold at most
/// [`MAX_REFERENCED_BYTES`]. `--allow-outside-paths` lifts the folder rule,
/// not the others. A reference to nothing is returned as joined, for the
/// read to say it is missing.
pub fn resolve(dir: &Path, reference: &str, opts: &ImportOptions) -> Result<PathBuf, String> {
    if !opts.allow_outside_paths && !stays_inside(reference) {
        return Err(format!(
            "`{reference}` leaves the model's folder; not read (--allow-outside-paths allows it)"
        ));
    }
    let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    let joined = dir.join(reference);
    let Ok(real) = std::fs::canonicalize(&joined) else { return Ok(joined) };
    if !opts.allow_outside_paths {
        let root = std::fs::canonicalize(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        if !real.starts_with(&root) {
            return Err(format!(
                "`{reference}` leads out of the model's folder through a link (to {}); not read \
                 (--allow-outside-paths allows it)",
                real.display()
            ));
        }
    }
    let meta = std::fs::metadata(&real).map_err(|e| format!("{}: {e}", real.display()))?;
    if !meta.is_file() {
        return Err(format!("`{reference}` is not a regular file ({}); not read", real.display()));
    }
    if meta.len() > MAX_REFERENCED_BYTES {
        return Err(format!(
            "`{reference}` holds {} bytes, more than the {MAX_REFERENCED_BYTES} a referenced file may",
            meta.len()
        ));
    }
    Ok(real)
}

/// A URI's percent escapes decoded (`my%20file.png` → `my file.png`).
pub fn percent_decode(uri: &str) -> String {
    String::from_utf8_lossy(&percent_bytes(uri)).into_owned()
}

/// The bytes a percent-encoded URI stands for.
pub fn percent_bytes(uri: &str) -> Vec<u8> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%' && i + 2 < b.len() {
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    out
}

/// The bytes a glTF URI names: a `data:` URI's payload, else the file it
/// names relative to `dir` (under the folder rule).
pub fn read_uri(dir: &Path, uri: &str, opts: &ImportOptions) -> Result<Vec<u8>, String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (meta, payload) = data.split_once(',').ok_or("a data: URI without a comma")?;
        return if meta.ends_with(";base64") {
            base64::engine::general_purpose::STANDARD
                .decode(payload.trim())
                .map_err(|e| format!("a data: URI that is not valid base64: {e}"))
        } else {
            Ok(percent_decode(payload).into_bytes())
        };
    }
    let path = resolve(dir, &percent_decode(uri), opts)?;
    std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_leaving_the_folder_are_refused_unless_allowed() {
        let strict = ImportOptions::default();
        let dir = Path::new("models");
        for bad in
            ["/etc/passwd", "../secret.png", "a/../../b.png", "C:\\x.png", "file:///etc/x", "\\\\host\\x"]
        {
            let e = resolve(dir, bad, &strict).unwrap_err();
            assert!(
                e.contains("leaves the model's folder") && e.contains("--allow-outside-paths"),
                "{bad}: {e}"
            );
        }
        assert_eq!(resolve(dir, "tex/a.png", &strict).unwrap(), dir.join("tex/a.png"));
        let open = ImportOptions { allow_outside_paths: true, ..strict };
        assert_eq!(resolve(dir, "../b.png", &open).unwrap(), dir.join("../b.png"));
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_before_the_folder_rule_is_applied() {
        use std::os::unix::fs::symlink;
        let root = tempfile::tempdir().unwrap();
        let (model, outside) = (root.path().join("model"), root.path().join("outside"));
        std::fs::create_dir_all(model.join("real")).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        std::fs::write(outside.join("secret.bin"), b"secret").unwrap();
        std::fs::write(model.join("real/inside.bin"), b"ok").unwrap();
        symlink(outside.join("secret.bin"), model.join("inside.bin")).unwrap();
        symlink(&outside, model.join("sub")).unwrap();
        symlink("/dev/zero", model.join("zero.mtl")).unwrap();
        symlink(model.join("real/inside.bin"), model.join("alias.bin")).unwrap();
        let strict = ImportOptions::default();
        for (reference, says) in [
            ("inside.bin", "leads out of the model's folder through a link"),
            ("sub/secret.bin", "leads out of the model's folder through a link"),
            ("zero.mtl", "leads out of the model's folder through a link (to /dev/zero)"),
            ("real", "is not a regular file"),
        ] {
            let e = resolve(&model, reference, &strict).unwrap_err();
            assert!(e.contains(says), "{reference}: {e}");
        }
        // A link that stays inside is fine; outside paths may be allowed.
        assert!(resolve(&model, "alias.bin", &strict).is_ok());
        let open = ImportOptions { allow_outside_paths: true, ..strict };
        assert!(resolve(&model, "inside.bin", &open).is_ok());
        assert!(resolve(&model, "zero.mtl", &open).is_err());
        assert!(read_uri(&model, "sub/secret.bin", &strict).is_err());
    }

    #[test]
    fn uris_are_percent_decoded_and_data_uris_read() {
        assert_eq!(percent_decode("my%20file%2Epng"), "my file.png");
        assert_eq!(percent_decode("100%"), "100%");
        let opts = ImportOptions::default();
        assert_eq!(
            read_uri(Path::new("."), "data:application/octet-stream;base64,AAEC", &opts).unwrap(),
            [0, 1, 2]
        );
        assert!(read_uri(Path::new("."), "data:;base64,@@@", &opts).is_err());
        let e = read_uri(Path::new("."), "%2E%2E/x.bin", &opts).unwrap_err();
        assert!(e.contains("leaves"), "escaped .. is still refused: {e}");
    }
}
