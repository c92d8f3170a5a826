//! Putting design files on disk without ever losing one: writes go to a temporary file
//! that is flushed to disk and renamed over the target (so a crash leaves the old file or
//! the new one, never half of one), a failed write leaves no temporary file behind, and a
//! file that cannot be read is moved aside under a name that says why, never overwritten.

use std::io::Write;
use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

use super::format::DesignError;

/// The temporary file a write of `path` goes through.
pub fn temporary_of(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Writes `bytes` to `path` through a temporary file that is synced and then renamed over
/// it. With `backup`, an existing `path` is first renamed to `backup` (the previous
/// version stays). On failure the temporary file is removed and the error names `path`.
/// A design is private: a new file is 0600 (the user's alone), one that replaces another
/// keeps that file's mode. The temporary file is made afresh (a stale one, or a link
/// someone put in its place, is removed, never written through).
pub fn write_atomically(
    path: &Path,
    bytes: &[u8],
    backup: Option<&Path>,
) -> Result<(), DesignError> {
    let io = |source| DesignError::Io {
        path: path.to_owned(),
        source,
    };
    if path.is_dir() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "it is a directory, not a file",
        )));
    }
    let tmp = temporary_of(path);
    let mode = std::fs::metadata(path).map_or(0o600, |m| m.permissions().mode() & 0o777);
    let _ = std::fs::remove_file(&tmp);
    let written = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            if mode != 0o600 {
                f.set_permissions(std::fs::Permissions::from_mode(mode))?;
            }
            f.sync_all()
        });
    let renamed = written.and_then(|()| {
        if let Some(b) = backup
            && path.is_file()
        {
            std::fs::rename(path, b)?;
        }
        std::fs::rename(&tmp, path)
    });
    if let Err(e) = renamed {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(e));
    }
    // The rename itself reaches the disk with the directory.
    if let Some(dir) = path.parent()
        && let Ok(d) = std::fs::File::open(if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        })
    {
        let _ = d.sync_all();
    }
    Ok(())
}

/// A word for why a design file could not be read, for the name it is kept under.
pub fn unreadable_reason(e: &DesignError) -> &'static str {
    match e {
        DesignError::Newer { .. } => "newer-format",
        DesignError::Io { .. } => "unreadable",
        DesignError::NotADesign => "not-a-design",
        DesignError::Truncated(_) | DesignError::Corrupt(_) | DesignError::Geometry(_) => "damaged",
    }
}

/// Moves an unreadable design file aside, next to it, under a name that says why
/// (`NAME.damaged.saiho`, `NAME.newer-format.2.saiho`, ...; never over another file).
/// Returns where it went.
pub fn set_aside(path: &Path, why: &DesignError) -> Result<PathBuf, std::io::Error> {
    let stem = path
        .file_stem()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned();
    let reason = unreadable_reason(why);
    for n in 1..1000 {
        let name = if n == 1 {
            format!("{stem}.{reason}.saiho")
        } else {
            format!("{stem}.{reason}.{n}.saiho")
        };
        let target = path.with_file_name(name);
        if !target.exists() {
            std::fs::rename(path, &target)?;
            return Ok(target);
        }
    }
    Err(std::io::Error::other("a thousand set-aside copies already"))
}
