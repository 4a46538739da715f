//! A P3F scene's `env DIR`: the six images of its cube map, found beside
//! the scene file, read under the folder rule mesh2nff applies to a model's
//! files (nothing outside the scene's folder, links followed, unless
//! `--allow-outside-paths`), each decoded once within the texture limits.

use anyhow::{bail, Context, Result};
use nffkit_formats::mesh::resource::{resolve, ImportOptions};
use nffkit_formats::mesh::texture::Texture;
use nffkit_tracer::environment::{CubeMap, Face, FACES};
use std::path::Path;

/// The image types a face may be, in the order they are looked for (the
/// course's files are `.jpg`).
const EXTENSIONS: [&str; 4] = ["jpg", "jpeg", "png", "JPG"];

/// The cube map in folder `dir` (as the scene wrote it) of the scene at
/// `scene` (standard input's, `-`, or the default scene's, `None`, is
/// looked for from the current directory).
pub fn load(scene: Option<&Path>, dir: &str, allow_outside_paths: bool) -> Result<CubeMap> {
    let base = match scene {
        Some(p) if p.as_os_str() != "-" => p.parent().unwrap_or(Path::new(".")).to_path_buf(),
        _ => ".".into(),
    };
    let folder = base.join(dir);
    // The course's programs look from the folder they run in, so its
    // repositories keep `skybox/` beside the program, not the scenes.
    if !folder.is_dir() && Path::new(dir).is_dir() && base != Path::new(".") {
        bail!(
            "the scene's cube map `env {dir}` is not beside it ({} is no folder); `{dir}` here is: \
             `--env {dir}` uses it",
            folder.display()
        );
    }
    from_folder(&base, dir, &ImportOptions { allow_outside_paths, ..ImportOptions::default() })
}

/// The cube map in the folder the user named (`render --env DIR`): their
/// own path, read wherever it is.
pub fn load_given(dir: &Path) -> Result<CubeMap> {
    let opts = ImportOptions { allow_outside_paths: true, ..ImportOptions::default() };
    from_folder(Path::new("."), &dir.to_string_lossy(), &opts)
}

/// The six faces in `base/dir`, read as `opts` allows.
fn from_folder(base: &Path, dir: &str, opts: &ImportOptions) -> Result<CubeMap> {
    let folder = base.join(dir);
    let context = || format!("the cube map `{dir}` ({})", folder.display());
    let mut faces = Vec::with_capacity(6);
    for face in FACES {
        faces.push(load_face(base, dir, face, opts).with_context(context)?);
    }
    let faces: [Face; 6] = faces.try_into().map_err(|_| anyhow::anyhow!("six faces"))?;
    Ok(CubeMap::new(faces))
}

/// One face: the first of `DIR/NAME.jpg`, `.jpeg`, `.png` that exists.
fn load_face(base: &Path, dir: &str, face: &str, opts: &ImportOptions) -> Result<Face> {
    let dir = dir.trim_end_matches(['/', '\\']);
    for ext in EXTENSIONS {
        let reference = format!("{dir}/{face}.{ext}");
        let path = resolve(base, &reference, opts).map_err(anyhow::Error::msg)?;
        if !path.exists() {
            continue;
        }
        let bytes = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        let texture = Texture::decode(&bytes).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let (w, h) = texture.size();
        return Face::new(w, h, texture.texels().to_vec())
            .with_context(|| format!("{}: an empty image", path.display()));
    }
    bail!(
        "no `{face}` image: looked for {}",
        EXTENSIONS[..3].iter().map(|e| format!("{dir}/{face}.{e}")).collect::<Vec<_>>().join(", ")
    )
}
