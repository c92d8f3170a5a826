//! Where Saiho keeps its own files: per user and private.
//!
//! - [`runtime_dir`]: what lives as long as the processes run (iceoryx2's root directory
//!   per domain, cloth-lab's control socket): `$XDG_RUNTIME_DIR/saiho`, else
//!   `$TMPDIR/saiho-<uid>`.
//! - [`state_dir`]: what outlives them (autosaves): `$XDG_STATE_HOME/saiho`, else
//!   `~/.local/state/saiho`, else `saiho-state` in the runtime directory.
//!
//! Each is made mode 0700 and checked every time it is used: a directory that is a
//! symbolic link, is not a directory, or belongs to another user is refused (someone
//! could have created it first to read or redirect our files); one of ours that others can
//! enter is closed to 0700.

use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};

/// Why a private directory cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    #[error("{path}: {why}; remove it, or point {var} at a directory of your own")]
    Unsafe {
        path: PathBuf,
        why: String,
        var: &'static str,
    },
    #[error("cannot create the private directory {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// The effective user id of this process.
pub fn uid() -> u32 {
    rustix::process::geteuid().as_raw()
}

/// Creates `dir` (mode 0700, parents as the umask allows) unless it exists, then checks
/// it is a real directory of this user's that nobody else can enter (closing it to 0700
/// if it is ours and open). `var` names the setting that chose it, for the message.
pub fn ensure_private(dir: &Path, var: &'static str) -> Result<(), PathError> {
    let io = |source| PathError::Io {
        path: dir.to_owned(),
        source,
    };
    let unsafe_dir = |why: String| PathError::Unsafe {
        path: dir.to_owned(),
        why,
        var,
    };
    if std::fs::symlink_metadata(dir).is_err() {
        if let Some(parent) = dir.parent() {
            std::fs::create_dir_all(parent).map_err(io)?;
        }
        match std::fs::DirBuilder::new().mode(0o700).create(dir) {
            Ok(()) => {}
            // Made meanwhile by someone else: checked below like any existing one.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(io(e)),
        }
    }
    let meta = std::fs::symlink_metadata(dir).map_err(io)?;
    if meta.file_type().is_symlink() {
        return Err(unsafe_dir("is a symbolic link".into()));
    }
    if !meta.is_dir() {
        return Err(unsafe_dir("is not a directory".into()));
    }
    if meta.uid() != uid() {
        return Err(unsafe_dir(format!(
            "belongs to user {}, not to you (user {})",
            meta.uid(),
            uid()
        )));
    }
    if meta.mode() & 0o077 != 0 {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700)).map_err(io)?;
    }
    Ok(())
}

/// An absolute path from environment variable `var`, if it holds one.
fn env_dir(var: &str) -> Option<PathBuf> {
    std::env::var_os(var)
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
}

/// The per-user directory for what lives while the processes run.
pub fn runtime_dir() -> Result<PathBuf, PathError> {
    let (dir, var) = match env_dir("XDG_RUNTIME_DIR") {
        Some(d) if d.is_dir() => (d.join("saiho"), "XDG_RUNTIME_DIR"),
        _ => (
            std::env::temp_dir().join(format!("saiho-{}", uid())),
            "TMPDIR",
        ),
    };
    ensure_private(&dir, var)?;
    Ok(dir)
}

/// Where the per-user state directory is, and the setting that chose it, without
/// making or checking it ([`state_dir`] does).
pub fn state_dir_path() -> (PathBuf, &'static str) {
    if let Some(d) = env_dir("XDG_STATE_HOME") {
        (d.join("saiho"), "XDG_STATE_HOME")
    } else if let Some(home) = env_dir("HOME") {
        (home.join(".local/state/saiho"), "HOME")
    } else {
        (
            std::env::temp_dir()
                .join(format!("saiho-{}", uid()))
                .join("state"),
            "TMPDIR",
        )
    }
}

/// The per-user directory for what outlives the processes (autosaves), made private.
pub fn state_dir() -> Result<PathBuf, PathError> {
    let (dir, var) = state_dir_path();
    if var == "TMPDIR" {
        runtime_dir()?;
    }
    ensure_private(&dir, var)?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("saiho-paths-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_private_directory_is_made_0700_and_an_open_one_of_ours_is_closed() {
        let d = scratch("made").join("inner");
        ensure_private(&d, "TEST").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().mode() & 0o777;
        assert_eq!(mode(&d), 0o700);
        std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o777)).unwrap();
        ensure_private(&d, "TEST").unwrap();
        assert_eq!(mode(&d), 0o700);
        let _ = std::fs::remove_dir_all(d.parent().unwrap());
    }

    #[test]
    fn a_symbolic_link_or_a_file_is_refused() {
        let base = scratch("link");
        std::fs::create_dir_all(&base).unwrap();
        let target = base.join("elsewhere");
        std::fs::create_dir(&target).unwrap();
        let link = base.join("saiho");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let e = ensure_private(&link, "TEST").unwrap_err().to_string();
        assert!(
            e.contains("is a symbolic link") && e.contains("TEST"),
            "{e}"
        );
        let file = base.join("file");
        std::fs::write(&file, b"x").unwrap();
        let e = ensure_private(&file, "TEST").unwrap_err().to_string();
        assert!(e.contains("is not a directory"), "{e}");
        let _ = std::fs::remove_dir_all(&base);
    }

    /// Another user's directory (root's, seen from an unprivileged user, or nobody's
    /// seen from root) is refused; only runnable where such a directory exists.
    #[test]
    fn another_users_directory_is_refused() {
        let theirs = Path::new("/");
        if std::fs::metadata(theirs).unwrap().uid() == uid() {
            // Running as root: make one that belongs to nobody.
            let d = scratch("theirs");
            std::fs::create_dir_all(&d).unwrap();
            std::os::unix::fs::chown(&d, Some(65534), None).unwrap();
            let e = ensure_private(&d, "TEST").unwrap_err().to_string();
            assert!(e.contains("belongs to user 65534"), "{e}");
            let _ = std::fs::remove_dir_all(&d);
        } else {
            let e = ensure_private(theirs, "TEST").unwrap_err().to_string();
            assert!(e.contains("belongs to user 0"), "{e}");
        }
    }
}
