//! Autosave and resume, without ever losing a design.
//!
//! - Every few seconds the design is serialised on the frame's thread and written by a
//!   writer thread through a synced temporary file renamed into place; the autosave it
//!   replaces becomes the backup (`NAME.previous.saiho`). After an edit it is saved within
//!   [`EDIT_SAVE_S`], so a crash loses at most that much of the designer's work.
//! - A write that fails leaves no temporary file, is logged, and is counted as a failure,
//!   not as an autosave.
//! - At start the autosave is resumed; if it cannot be read it is moved aside under a name
//!   that says why (`NAME.damaged.saiho`, `NAME.newer-format.saiho`, ...), never
//!   overwritten, and the backup is tried next.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;
use std::time::Instant;

use sim_core::design::Design;
use sim_core::design::file::{set_aside, write_atomically};

use crate::config::{ServiceConfig, ServiceStats};

/// Makes the autosave's directory ready before anything in it is read or written: the
/// user's state directory (the default) is made private and refused if it is a symbolic
/// link or another user's; a directory the user chose is created as the umask allows.
pub fn prepare_dir(autosave: &Path) -> Result<(), String> {
    let Some(dir) = autosave.parent().filter(|d| !d.as_os_str().is_empty()) else {
        return Ok(());
    };
    let (state, var) = shared::paths::state_dir_path();
    if dir == state {
        shared::paths::state_dir()
            .map(|_| ())
            .map_err(|e| format!("autosave directory ({var}): {e}"))
    } else {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))
    }
}

/// How soon after an edit the design is saved, s: the most of a designer's work a crash
/// can take (the cloth's motion is saved every `--autosave-every`).
pub const EDIT_SAVE_S: f64 = 0.25;

/// Where the previous good autosave is kept: `NAME.previous.saiho` beside `NAME.saiho`.
pub fn backup_of(autosave: &Path) -> PathBuf {
    let stem = autosave.file_stem().unwrap_or_default().to_string_lossy();
    autosave.with_file_name(format!("{stem}.previous.saiho"))
}

/// Starts a new design with `fresh` (`--fresh`), the autosave there kept as the backup
/// (what the last one was is not thrown away). Nothing is resumed: before, `--fresh`
/// moved the autosave to the backup and then resumed the backup, so that it started
/// with the old design after all.
pub fn start_fresh(
    cfg: &ServiceConfig,
    fresh: impl FnOnce() -> Result<Design, String>,
    log: &mut dyn FnMut(&str),
) -> Result<Design, String> {
    if cfg.autosave.is_dir() {
        return Err(format!(
            "the autosave path {} is a directory; give a file path (--autosave FILE.saiho)",
            cfg.autosave.display()
        ));
    }
    prepare_dir(&cfg.autosave)?;
    // Built first: a new design that cannot be made (a pattern file that does not read)
    // is refused with nothing moved.
    let design = fresh()?;
    if cfg.autosave.is_file() {
        let kept = backup_of(&cfg.autosave);
        std::fs::rename(&cfg.autosave, &kept).map_err(|e| {
            format!(
                "--fresh: cannot move the autosave {} aside to {}: {e}",
                cfg.autosave.display(),
                kept.display()
            )
        })?;
        log(&format!(
            "--fresh: the previous autosave is kept as {}",
            kept.display()
        ));
    }
    Ok(design)
}

/// Resumes the newest design that reads: the autosave, else its backup. A file that
/// cannot be read is moved aside (and the log says where); if it cannot be moved, start
/// is refused rather than overwrite it. With neither, builds the scene with `fresh`.
/// Returns the design and whether it was resumed.
pub fn resume_or(
    cfg: &ServiceConfig,
    fresh: impl FnOnce() -> Result<Design, String>,
    log: &mut dyn FnMut(&str),
) -> Result<(Design, bool), String> {
    if cfg.autosave.is_dir() {
        return Err(format!(
            "the autosave path {} is a directory; give a file path (--autosave FILE.saiho)",
            cfg.autosave.display()
        ));
    }
    prepare_dir(&cfg.autosave)?;
    for (path, what) in [
        (cfg.autosave.clone(), "autosave"),
        (backup_of(&cfg.autosave), "backup of the autosave"),
    ] {
        if !path.exists() {
            continue;
        }
        match Design::load_design_file(&path) {
            Ok(d) => {
                log(&format!(
                    "resumed the design from the {what} {}",
                    path.display()
                ));
                return Ok((d, true));
            }
            Err(e) => {
                let kept = set_aside(&path, &e).map_err(|m| {
                    format!(
                        "the {what} {} cannot be read ({e}) and cannot be moved aside ({m}); \
                         not starting, so that it is not overwritten",
                        path.display()
                    )
                })?;
                log(&format!(
                    "the {what} {} cannot be read ({e}); it is kept as {}",
                    path.display(),
                    kept.display()
                ));
            }
        }
    }
    Ok((fresh()?, false))
}

/// The autosave of a running service.
pub(crate) struct Autosave {
    path: PathBuf,
    every_s: f64,
    last: Instant,
    tx: Option<SyncSender<Vec<u8>>>,
    results: Receiver<Result<(), String>>,
    writer: Option<JoinHandle<()>>,
    /// The longest a save held up its frame, ms.
    hold_ms_max: f64,
    /// The design was edited since the last save.
    edited: bool,
    /// The frame of the last design handed to the writer.
    sent_frame: Option<u64>,
    /// The last failure logged (the same one again is only counted).
    last_error: Option<String>,
}

impl Autosave {
    /// Starts the writer thread for `path` (its directory is created).
    pub(crate) fn start(path: &Path, every_s: f64) -> Result<Self, String> {
        prepare_dir(path)?;
        if path.is_dir() {
            return Err(format!(
                "the autosave path {} is a directory; give a file path",
                path.display()
            ));
        }
        let (tx, rx) = sync_channel::<Vec<u8>>(1);
        let (done_tx, results) = std::sync::mpsc::channel();
        let save_path = path.to_owned();
        let writer = std::thread::spawn(move || {
            let backup = backup_of(&save_path);
            for bytes in rx {
                let r = write_atomically(&save_path, &bytes, Some(&backup))
                    .map_err(|e| format!("autosave failed: {e}"));
                if done_tx.send(r).is_err() {
                    break;
                }
            }
        });
        Ok(Self {
            path: path.to_owned(),
            every_s,
            last: Instant::now(),
            tx: Some(tx),
            results,
            writer: Some(writer),
            hold_ms_max: 0.0,
            edited: false,
            sent_frame: None,
            last_error: None,
        })
    }

    /// The longest hold-up of a frame so far, ms.
    pub(crate) fn hold_max_ms(&self) -> f64 {
        self.hold_ms_max
    }

    /// Counts what the writer finished: successes as autosaves, failures as failures
    /// (each new reason logged once).
    fn collect(&mut self, stats: &mut ServiceStats, log: &mut dyn FnMut(&str)) {
        while let Ok(r) = self.results.try_recv() {
            self.count(r, stats, log);
        }
    }

    fn count(
        &mut self,
        r: Result<(), String>,
        stats: &mut ServiceStats,
        log: &mut dyn FnMut(&str),
    ) {
        match r {
            Ok(()) => stats.autosaves += 1,
            Err(e) => {
                stats.autosave_failures += 1;
                if self.last_error.as_ref() != Some(&e) {
                    log(&e);
                    self.last_error = Some(e);
                }
            }
        }
    }

    /// The design was edited: it is saved within [`EDIT_SAVE_S`].
    pub(crate) fn edited(&mut self) {
        self.edited = true;
    }

    /// Saves when the interval has passed, or soon after an edit: serialises now, writes
    /// on the writer thread (skipped while it is still busy with the last one, and then an
    /// edit stays unsaved for the next tick).
    pub(crate) fn tick(
        &mut self,
        design: &mut Design,
        stats: &mut ServiceStats,
        log: &mut dyn FnMut(&str),
    ) {
        self.collect(stats, log);
        let since = self.last.elapsed().as_secs_f64();
        if since < self.every_s && !(self.edited && since >= EDIT_SAVE_S) {
            return;
        }
        let t = Instant::now();
        match design
            .refresh_png_cache()
            .and_then(|_| design.save_design())
        {
            // A full channel means the writer is still busy: skip this one.
            Ok(bytes) => {
                if let Some(tx) = &self.tx
                    && tx.try_send(bytes).is_ok()
                {
                    self.edited = false;
                    self.sent_frame = Some(design.sim.frame);
                }
            }
            Err(e) => self.count(Err(format!("autosave failed: {e}")), stats, log),
        }
        self.hold_ms_max = self.hold_ms_max.max(t.elapsed().as_secs_f64() * 1e3);
        self.last = Instant::now();
    }

    /// Stops the writer, then saves the design one last time, in place.
    pub(crate) fn finish(
        mut self,
        design: &mut Design,
        stats: &mut ServiceStats,
        log: &mut dyn FnMut(&str),
    ) {
        drop(self.tx.take());
        if let Some(w) = self.writer.take() {
            let _ = w.join();
        }
        self.collect(stats, log);
        // The design as last written, unedited since: writing it again would only push the
        // previous autosave out of the backup.
        if !self.edited && self.sent_frame == Some(design.sim.frame) && self.last_error.is_none() {
            stats.autosave_ms_max = self.hold_max_ms();
            return;
        }
        let r = design
            .refresh_png_cache()
            .and_then(|_| design.save_design())
            .and_then(|bytes| write_atomically(&self.path, &bytes, Some(&backup_of(&self.path))))
            .map_err(|e| format!("final autosave failed: {e}"));
        self.count(r, stats, log);
        stats.autosave_ms_max = self.hold_max_ms();
    }
}
