//! Where a command will write, checked before it does any work: a render
//! of minutes must not end in "folder does not exist", two outputs must not
//! land on one file, and no output may replace an input.
//!
//! Paths are compared where they land: a symbolic link followed (as the
//! atomic writer follows it), the folder made absolute, and, for files that
//! exist, by device and inode too (a hard link is the same file).

use anyhow::{anyhow, bail, Context, Result};
use std::path::{Path, PathBuf};

/// The outputs and inputs of one command, checked as they are added.
#[derive(Debug, Default)]
pub struct Outputs {
    inputs: Vec<(PathBuf, Option<FileId>)>,
    outputs: Vec<(String, PathBuf)>,
}

/// A file's identity on its device.
type FileId = (u64, u64);

fn file_id(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        None
    }
}

impl Outputs {
    /// No inputs or outputs yet.
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Files the command reads (`-`, standard input, is none; a file that
    /// does not exist is left to the reader's error).
    pub fn inputs<'a>(mut self, paths: impl IntoIterator<Item = &'a Path>) -> Outputs {
        for p in paths.into_iter().filter(|p| p.as_os_str() != "-") {
            if let Ok(real) = std::fs::canonicalize(p) {
                self.inputs.push((real, file_id(p)));
            }
        }
        self
    }

    /// A file the command will write, named by `flag` in messages: its
    /// folder exists and can be written, it is not a folder or a device,
    /// and it is neither an input nor another output.
    pub fn file(mut self, flag: &str, path: &Path) -> Result<Outputs> {
        let at = || format!("{flag} {}", path.display());
        let landing = landing(path).with_context(at)?;
        self.not_taken(flag, path, &landing)?;
        self.outputs.push((flag.to_string(), landing));
        Ok(self)
    }

    /// A folder the command will fill (created if missing): it is not a
    /// file, and it or the folder it goes in can be written.
    pub fn folder(mut self, flag: &str, path: &Path) -> Result<Outputs> {
        let at = || format!("{flag} {}", path.display());
        let meta = std::fs::metadata(path);
        let existing = match &meta {
            Ok(m) if m.is_dir() => path.to_path_buf(),
            Ok(_) => bail!("{}: it is a file, not a folder", at()),
            Err(_) => {
                let parent = parent_of(path);
                folder_exists(&parent).with_context(at)?;
                parent
            }
        };
        writable(&existing).with_context(at)?;
        let real = std::fs::canonicalize(&existing)?;
        let landing = if meta.is_ok() { real } else { real.join(path.file_name().unwrap_or_default()) };
        self.not_taken(flag, path, &landing)?;
        self.outputs.push((flag.to_string(), landing));
        Ok(self)
    }

    fn not_taken(&self, flag: &str, path: &Path, landing: &Path) -> Result<()> {
        let id = file_id(landing);
        if let Some((input, _)) =
            self.inputs.iter().find(|(real, iid)| real == landing || (id.is_some() && *iid == id))
        {
            bail!("{flag} {} would overwrite the input {}; write elsewhere", path.display(), input.display());
        }
        if let Some((other, _)) = self.outputs.iter().find(|(_, l)| l == landing) {
            bail!("{other} and {flag} both name {}; give each output its own file", path.display());
        }
        Ok(())
    }
}

/// Where a write to `path` lands, checked: see [`Outputs::file`].
fn landing(path: &Path) -> Result<PathBuf> {
    let target = nffkit_formats::atomic::target_of(path)?;
    let Some(name) = target.file_name() else { bail!("it names a folder, not a file") };
    let dir = parent_of(&target);
    folder_exists(&dir)?;
    let full = std::fs::canonicalize(&dir)?.join(name);
    if let Ok(m) = std::fs::metadata(&full) {
        if m.is_dir() {
            bail!("it is a folder; name a file in it");
        }
        if !m.is_file() {
            bail!("it is not a regular file (a device, pipe or socket): outputs are written whole and renamed into place");
        }
    }
    writable(&dir)?;
    Ok(full)
}

fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn folder_exists(dir: &Path) -> Result<()> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(_) => bail!("{} is not a folder", dir.display()),
        Err(_) => bail!("folder {} does not exist", dir.display()),
    }
}

/// Whether a file can be created in `dir`: by creating one (and removing
/// it), as permissions, read-only mounts and ACLs all decide.
fn writable(dir: &Path) -> Result<()> {
    tempfile::Builder::new()
        .prefix(".nffkit-can-write.")
        .tempfile_in(dir)
        .map(drop)
        .map_err(|e| anyhow!("cannot write in folder {}: {}", dir.display(), e.kind()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_checked_against_folders_inputs_and_each_other() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let input = d.join("scene.png");
        std::fs::write(&input, b"s 0 0 0 1\n").unwrap();
        let err = |r: Result<Outputs>| format!("{:#}", r.unwrap_err());

        let e = err(Outputs::new().file("-o", &d.join("nodir/x.png")));
        assert!(e.contains("-o") && e.contains("does not exist"), "{e}");
        assert!(err(Outputs::new().file("-o", d)).contains("folder"));
        let e = err(Outputs::new().inputs([input.as_path()]).file("-o", &input));
        assert!(e.contains("would overwrite the input"), "{e}");
        // Through another spelling of the same path.
        let other = d.join(".").join("scene.png");
        assert!(err(Outputs::new().inputs([input.as_path()]).file("-o", &other)).contains("overwrite"));
        let both = Outputs::new().file("-o", &d.join("a.png")).unwrap().file("--aov-cost", &d.join("a.png"));
        let e = err(both);
        assert!(e.contains("-o and --aov-cost both name"), "{e}");
        assert!(Outputs::new()
            .file("-o", &d.join("a.png"))
            .unwrap()
            .file("--aov-cost", &d.join("b.png"))
            .is_ok());
        // Nothing was left behind by the checks.
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 1);

        assert!(err(Outputs::new().folder("--out", &input)).contains("a file, not a folder"));
        assert!(Outputs::new().folder("--out", &d.join("page")).is_ok());
        assert!(err(Outputs::new().folder("--out", &d.join("no/page"))).contains("does not exist"));
    }

    #[cfg(unix)]
    #[test]
    fn a_link_or_hard_link_to_an_input_is_the_input() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let input = d.join("part-0.exr");
        std::fs::write(&input, b"x").unwrap();
        std::os::unix::fs::symlink(&input, d.join("soft.exr")).unwrap();
        std::fs::hard_link(&input, d.join("hard.exr")).unwrap();
        for out in ["soft.exr", "hard.exr"] {
            let r = Outputs::new().inputs([input.as_path()]).file("-o", &d.join(out));
            assert!(r.is_err(), "{out}");
        }
        let dev = Outputs::new().file("-o", Path::new("/dev/null"));
        assert!(format!("{:#}", dev.unwrap_err()).contains("not a regular file"));
    }
}
