//! Domains: `--domain NAME` (or the `SAIHO_DOMAIN` environment variable) gives a running
//! system an iceoryx2 configuration of its own (file prefix and root path), so two systems
//! on one machine, or tests running in parallel, never see each other's services.

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
}

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

    /// This domain's directory under the system temp directory (iceoryx2's root path; the
    /// launcher's control socket lives here too).
    pub fn root_dir(&self) -> std::path::PathBuf {
        std::env::temp_dir().join("saiho-iceoryx2").join(&self.name)
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The iceoryx2 configuration of this domain: prefix `saiho_<name>_` on every file it
    /// creates, and its own root directory under the system temp directory.
    pub fn config(&self) -> Result<Config, DomainError> {
        let err = |e: String| DomainError::Config(self.name.clone(), e);
        let mut cfg = Config::default();
        let prefix = format!("saiho_{}_", self.name);
        cfg.global.prefix = FileName::new(prefix.as_bytes()).map_err(|e| err(format!("{e:?}")))?;
        let root = self.root_dir();
        std::fs::create_dir_all(&root).map_err(|e| err(e.to_string()))?;
        let mut root_s = root.display().to_string();
        root_s.push('/');
        let path = Path::new(root_s.as_bytes()).map_err(|e| err(format!("{e:?}")))?;
        cfg.global.set_root_path(&path);
        Ok(cfg)
    }
}

impl Domain {
    /// Deletes what iceoryx2 left in /dev/shm for this domain (its `*_global_mgmt`
    /// segment). Only for when no process of the domain runs (tests, after a clean
    /// shutdown of all). The small root directory under the temp directory stays: iceoryx2
    /// may still touch it until the process exits.
    pub fn remove_leftovers(&self) {
        let prefix = format!("saiho_{}_", self.name);
        if let Ok(dir) = std::fs::read_dir("/dev/shm") {
            for e in dir.flatten() {
                if e.file_name().to_string_lossy().starts_with(&prefix) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        let _ =
            std::fs::remove_dir_all(std::env::temp_dir().join("saiho-iceoryx2").join(&self.name));
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
