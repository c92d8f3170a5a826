//! Autosave and resume: the design is serialised on the frame's thread every few seconds
//! and written by a writer thread (through a temporary file and a rename); at start, a
//! valid autosave is resumed.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;
use std::time::Instant;

use sim_core::design::Design;

use crate::config::{ServiceConfig, ServiceStats};

/// Resumes from the autosave if there is a valid one, else builds the scene with `fresh`.
pub fn resume_or(
    cfg: &ServiceConfig,
    fresh: impl FnOnce() -> Result<Design, String>,
    log: &mut dyn FnMut(&str),
) -> Result<(Design, bool), String> {
    if cfg.autosave.is_file() {
        match Design::load_design_file(&cfg.autosave) {
            Ok(d) => {
                log(&format!(
                    "resumed the design from {}",
                    cfg.autosave.display()
                ));
                return Ok((d, true));
            }
            Err(e) => log(&format!(
                "autosave {} not used: {e}; starting a new design",
                cfg.autosave.display()
            )),
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
    writer: Option<JoinHandle<Vec<String>>>,
    /// How long each save held up its frame, ms.
    hold_ms: Vec<f64>,
}

impl Autosave {
    /// Starts the writer thread for `path` (its directory is created).
    pub(crate) fn start(path: &Path, every_s: f64) -> Result<Self, String> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let (tx, rx) = sync_channel::<Vec<u8>>(1);
        let save_path = path.to_owned();
        let writer = std::thread::spawn(move || write_all(rx, &save_path));
        Ok(Self {
            path: path.to_owned(),
            every_s,
            last: Instant::now(),
            tx: Some(tx),
            writer: Some(writer),
            hold_ms: Vec::new(),
        })
    }

    /// The longest hold-up of a frame so far, ms.
    pub(crate) fn hold_max_ms(&self) -> f64 {
        self.hold_ms.iter().copied().fold(0.0, f64::max)
    }

    /// Saves when the interval has passed: serialises now, writes on the writer thread
    /// (skipped while it is still busy with the last one).
    pub(crate) fn tick(
        &mut self,
        design: &mut Design,
        stats: &mut ServiceStats,
        log: &mut dyn FnMut(&str),
    ) {
        if self.last.elapsed().as_secs_f64() < self.every_s {
            return;
        }
        let t = Instant::now();
        match design
            .refresh_png_cache()
            .and_then(|_| design.save_design())
        {
            // A full channel means the writer is still busy: skip this one.
            Ok(bytes) => {
                if self
                    .tx
                    .as_ref()
                    .is_some_and(|tx| tx.try_send(bytes).is_ok())
                {
                    stats.autosaves += 1;
                }
            }
            Err(e) => log(&format!("autosave failed: {e}")),
        }
        self.hold_ms.push(t.elapsed().as_secs_f64() * 1e3);
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
            for e in w.join().unwrap_or_default() {
                log(&e);
            }
        }
        if let Err(e) = design
            .refresh_png_cache()
            .and_then(|_| design.save_design_file(&self.path))
        {
            log(&format!("final autosave failed: {e}"));
        } else {
            stats.autosaves += 1;
        }
        stats.autosave_ms_max = self.hold_max_ms();
    }
}

/// The writer thread: each design it receives goes to a temporary file, then in place.
fn write_all(rx: Receiver<Vec<u8>>, path: &Path) -> Vec<String> {
    let mut errors = Vec::new();
    for bytes in rx {
        let tmp = path.with_extension("saiho.tmp");
        if let Err(e) = std::fs::write(&tmp, &bytes).and_then(|_| std::fs::rename(&tmp, path)) {
            errors.push(format!("autosave to {} failed: {e}", path.display()));
        }
    }
    errors
}
