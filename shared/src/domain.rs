//! Domains: `--domain NAME` (or the `SAIHO_DOMAIN` environment variable) gives a running
//! system an iceoryx2 configuration of its own (file prefix and root path), so two systems
//! on one machine, or tests running in parallel, never see each other's services.
//!
//! A domain is per user: its root directory is in the user's private runtime directory
//! ([`crate::paths::runtime_dir`]) and its shared-memory files in `/dev/shm` carry the
//! user id in their prefix (`saiho_<uid>_<name>_`) and are the user's alone (0600; iceoryx2
//! makes its management segment 0666, [`Domain::secure_shared_memory`] closes it). Another
//! user's file under that prefix is refused, never opened.

use std::os::unix::fs::{MetadataExt, PermissionsExt};

use iceoryx2::config::Config;
use iceoryx2::prelude::{FileName, Path, SemanticString};

/// The environment variable that names the domain when `--domain` is not given.
pub const DOMAIN_ENV: &str = "SAIHO_DOMAIN";
/// The domain when neither is given.
pub const DEFAULT_DOMAIN: &str = "default";

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DomainError {
    #[error(
        "domain name '{0}' must be 1 to 32 characters of a-z, 0-9, '-' or '_' (it becomes part of file names)"
    )]
    BadName(String),
    #[error("cannot set up the iceoryx2 configuration for domain '{0}': {1}")]
    Config(String, String),
    #[error(
        "domain '{domain}': /dev/shm/{file} belongs to user {owner}, not to you; another user \
         placed it where this domain's shared memory goes. Remove it (as that user or root) \
         or choose another --domain"
    )]
    Squatted {
        domain: String,
        file: String,
        owner: u32,
    },
    #[error("domain '{0}': cannot close its shared memory to other users: {1}")]
    Permissions(String, String),
}

/// Where POSIX shared memory lives.
const SHM: &str = "/dev/shm";

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Domain {
    name: String,
}

impl Domain {
    pub fn new(name: &str) -> Result<Self, DomainError> {
        let ok = !name.is_empty()
            && name.len() <= 32
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_');
        if ok {
            Ok(Self { name: name.into() })
        } else {
            Err(DomainError::BadName(name.into()))
        }
    }

    /// `--domain` if given, else `SAIHO_DOMAIN`, else `default`.
    pub fn from_arg_or_env(arg: Option<&str>) -> Result<Self, DomainError> {
        match arg {
            Some(a) => Self::new(a),
            None => match std::env::var(DOMAIN_ENV) {
                Ok(v) if !v.is_empty() => Self::new(&v),
                _ => Self::new(DEFAULT_DOMAIN),
            },
        }
    }

    /// This domain's directory in the user's private runtime directory (iceoryx2's root
    /// path; the launcher's control socket lives here too), created 0700.
    pub fn root_dir(&self) -> Result<std::path::PathBuf, DomainError> {
        let dir = self.root_path()?;
        for d in [dir.parent().unwrap_or(&dir), &dir] {
            crate::paths::ensure_private(d, "XDG_RUNTIME_DIR")
                .map_err(|e| DomainError::Config(self.name.clone(), e.to_string()))?;
        }
        Ok(dir)
    }

    /// Where [`Domain::root_dir`] is, without making it (for looking into a domain that
    /// may not run).
    pub fn root_path(&self) -> Result<std::path::PathBuf, DomainError> {
        let runtime = crate::paths::runtime_dir()
            .map_err(|e| DomainError::Config(self.name.clone(), e.to_string()))?;
        Ok(runtime.join("iceoryx2").join(&self.name))
    }

    /// The start of every file name iceoryx2 makes for this domain.
    pub fn prefix(&self) -> String {
        format!("saiho_{}_{}_", crate::paths::uid(), self.name)
    }

    /// Checks this domain's files in /dev/shm: another user's is refused (before anything
    /// of ours opens it); one of ours that others may read or write is closed to 0600.
    /// Returns how many were closed.
    pub fn secure_shared_memory(&self) -> Result<usize, DomainError> {
        let mut closed = 0;
        for (path, meta) in self.shm_files() {
            let file = path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            if meta.uid() != crate::paths::uid() || meta.file_type().is_symlink() {
                return Err(DomainError::Squatted {
                    domain: self.name.clone(),
                    file,
                    owner: meta.uid(),
                });
            }
            if meta.mode() & 0o077 != 0 {
                std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).map_err(
                    |err| DomainError::Permissions(self.name.clone(), format!("{file}: {err}")),
                )?;
                closed += 1;
            }
        }
        Ok(closed)
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The iceoryx2 configuration of this domain: prefix `saiho_<name>_` on every file it
    /// creates, and its own root directory under the system temp directory.
    pub fn config(&self) -> Result<Config, DomainError> {
        let err = |e: String| DomainError::Config(self.name.clone(), e);
        let mut cfg = Config::default();
        let prefix = self.prefix();
        cfg.global.prefix = FileName::new(prefix.as_bytes()).map_err(|e| err(format!("{e:?}")))?;
        let root = self.root_dir()?;
        let mut root_s = root.display().to_string();
        root_s.push('/');
        let path = Path::new(root_s.as_bytes()).map_err(|e| err(format!("{e:?}")))?;
        cfg.global.set_root_path(&path);
        Ok(cfg)
    }
}

impl Domain {
    /// Deletes what iceoryx2 left in /dev/shm for this domain (its `*_global_mgmt`
    /// segment, and any segment a killed process left) and the domain's root directory.
    /// Only for when no process of the domain runs (tests, after a clean shutdown of
    /// all): see [`crate::services::release`]. Only this user's files are touched.
    pub fn remove_leftovers(&self) {
        for (path, meta) in self.shm_files() {
            if meta.uid() == crate::paths::uid() {
                let _ = std::fs::remove_file(path);
            }
        }
        if let Ok(root) = self.root_path() {
            let _ = std::fs::remove_dir_all(root);
        }
    }

    /// This domain's files in /dev/shm (anyone's, under its prefix), with their metadata
    /// as they are (a symbolic link is not followed).
    pub fn shm_files(&self) -> Vec<(std::path::PathBuf, std::fs::Metadata)> {
        let prefix = self.prefix();
        let Ok(dir) = std::fs::read_dir(SHM) else {
            return Vec::new();
        };
        dir.flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
            // Gone meanwhile (its owner stopped): not there.
            .filter_map(|e| Some((e.path(), std::fs::symlink_metadata(e.path()).ok()?)))
            .collect()
    }
}

/// A domain for one test or one measurement, removed with all it left when dropped (a
/// failed test's too, as its panic unwinds): declare it before the nodes and the child
/// processes' guards, so it goes last.
pub struct ScratchDomain(pub Domain);

impl ScratchDomain {
    /// A scratch domain named `name` (see [`Domain::new`]).
    pub fn new(name: &str) -> Result<Self, DomainError> {
        Domain::new(name).map(Self)
    }
}

impl std::ops::Deref for ScratchDomain {
    type Target = Domain;
    fn deref(&self) -> &Domain {
        &self.0
    }
}

impl Drop for ScratchDomain {
    fn drop(&mut self) {
        self.0.remove_leftovers();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_checked() {
        assert!(Domain::new("lab-1").is_ok());
        assert!(Domain::new("").is_err());
        assert!(Domain::new("../etc").is_err());
        assert!(Domain::new("Upper").is_err());
        assert!(Domain::new(&"x".repeat(33)).is_err());
        assert_eq!(Domain::from_arg_or_env(Some("t1")).unwrap().name(), "t1");
    }
}
