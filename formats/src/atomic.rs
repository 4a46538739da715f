//! Writing a file all at once or not at all: the bytes go to a hidden
//! sibling, which is renamed over the target only when everything was
//! written. A failed or interrupted write leaves no partial file, and the
//! temporary name never reaches a message: errors name the target.
//!
//! The sibling is created exclusively (`O_EXCL`) under an unpredictable
//! name (`.NAME.XXXXXX.tmp`, by `tempfile`), so a link planted in the
//! folder cannot redirect the write. An existing target keeps its
//! permissions. A target that is itself a symbolic link is followed: the
//! file it names is replaced (in that file's folder) and the link stays, as
//! `cp` and shell redirection treat a link; a link to nothing is refused.
//!
//! Every sibling not yet renamed is listed in [`pending`], so that a
//! program interrupted by a signal can remove them ([`remove_pending`]).

#[cfg(unix)]
use std::fs::Permissions;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files being written, for [`remove_pending`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Write through `f` into `path`, atomically.
pub fn write_with(path: &Path, f: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    write_resolved(path, f)
        .map_err(|e| io::Error::new(e.kind(), format!("cannot write {}: {}", path.display(), e)))
}

/// Write `bytes` to `path`, atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |w| w.write_all(bytes))
}

/// The file a write to `path` replaces: `path`, or where the symbolic link
/// `path` points.
pub fn target_of(path: &Path) -> io::Result<PathBuf> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path)
            .map_err(|e| io::Error::new(e.kind(), "it is a symbolic link to a file that does not exist")),
        _ => Ok(path.to_path_buf()),
    }
}

/// Remove every temporary file still being written (from a signal handler,
/// just before the process exits). Returns how many were removed.
pub fn remove_pending() -> usize {
    let list = PENDING.lock().unwrap_or_else(|e| e.into_inner());
    list.iter().filter(|p| std::fs::remove_file(p).is_ok()).count()
}

/// The temporary files being written now.
pub fn pending() -> Vec<PathBuf> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

fn write_resolved(path: &Path, f: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let target = target_of(path)?;
    let dir = target.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name =
        target.file_name().ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
    let keep = std::fs::metadata(&target).ok().filter(|m| m.is_file()).map(|m| m.permissions());
    let prefix = format!(".{}.", name.to_string_lossy());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    builder.permissions(keep.clone().unwrap_or_else(default_permissions));
    let tmp = builder.tempfile_in(dir)?;
    let tmp_path = tmp.path().to_path_buf();
    PENDING.lock().unwrap_or_else(|e| e.into_inner()).push(tmp_path.clone());
    let result = (|| {
        let mut w = BufWriter::new(tmp.as_file());
        f(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?;
        if let Some(p) = keep {
            // The mode given at creation passed through the umask.
            tmp.as_file().set_permissions(p)?;
        }
        // Renamed while listed, so a signal never finds the file renamed
        // and the list stale, nor the file gone and a rename to come.
        let mut list = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        let renamed = tmp.persist(&target).map(|_| ()).map_err(|e| e.error);
        list.retain(|p| p != &tmp_path);
        renamed
    })();
    // On failure `tmp` (moved into the closure) removed itself when dropped.
    if result.is_err() {
        PENDING.lock().unwrap_or_else(|e| e.into_inner()).retain(|p| p != &tmp_path);
    }
    result
}

/// Read and write for everyone, less the umask (applied by `open`), as a
/// new file gets from `File::create`.
#[cfg(unix)]
fn default_permissions() -> Permissions {
    use std::os::unix::fs::PermissionsExt;
    Permissions::from_mode(0o666)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failure_leaves_nothing_behind() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        let err = write_with(&path, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("out.txt"), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        assert!(pending().iter().all(|p| !p.starts_with(dir.path())));
        write_bytes(&path, b"whole").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"whole");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_planted_link_is_not_followed_and_permissions_are_kept() {
        use std::os::unix::fs::{symlink, PermissionsExt};
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, b"precious").unwrap();
        let out = dir.path().join("out.png");
        // Every name the old writer could have picked, planted.
        symlink(&victim, dir.path().join(format!(".out.png.{}.tmp", std::process::id()))).unwrap();
        write_bytes(&out, b"image").unwrap();
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
        assert!(!std::fs::symlink_metadata(&out).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&out).unwrap(), b"image");

        std::fs::set_permissions(&out, Permissions::from_mode(0o640)).unwrap();
        write_bytes(&out, b"again").unwrap();
        assert_eq!(std::fs::metadata(&out).unwrap().permissions().mode() & 0o777, 0o640);

        // An output that is a link: the file it names is replaced.
        let link = dir.path().join("latest.png");
        symlink(&out, &link).unwrap();
        write_bytes(&link, b"through").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&out).unwrap(), b"through");
        symlink(dir.path().join("gone"), dir.path().join("dangling.png")).unwrap();
        let err = write_bytes(&dir.path().join("dangling.png"), b"x").unwrap_err();
        assert!(err.to_string().contains("symbolic link to a file that does not exist"), "{err}");
    }
}
