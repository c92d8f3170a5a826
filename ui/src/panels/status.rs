//! The status panel: which processes are heard, the haptic loop's and cloth-sim's timing,
//! the UI's frame rate, and latency plots over the last minute.

use std::time::{Duration, Instant};

use crate::store::{Sample, Store};

/// The panel, with the UI's own frame-rate count.
pub struct StatusPanel {
    frames: u64,
    /// Frames per second over the last second.
    pub fps: f32,
    fps_at: (Instant, u64),
}

impl Default for StatusPanel {
    fn default() -> Self {
        Self {
            frames: 0,
            fps: 0.0,
            fps_at: (Instant::now(), 0),
        }
    }
}

impl StatusPanel {
    /// Counts one UI frame; returns the new rate once a second.
    pub fn count_frame(&mut self) -> Option<f32> {
        self.frames += 1;
        let el = self.fps_at.0.elapsed().as_secs_f32();
        if el < 1.0 {
            return None;
        }
        self.fps = (self.frames - self.fps_at.1) as f32 / el;
        self.fps_at = (Instant::now(), self.frames);
        Some(self.fps)
    }

    /// Draws the panel; `linked` says whether iceoryx2 is connected, `design_arrived` how
    /// long after start the whole design had arrived.
    pub fn ui(
        &self,
        ui: &mut egui::Ui,
        store: &Store,
        linked: bool,
        design_arrived: Option<Duration>,
        cap: Option<(f32, &str)>,
    ) {
        ui.heading("Processes");
        self.processes(ui, store, linked, design_arrived, cap);
        ui.separator();
        ui.heading("Latency");
        plots(ui, store);
    }

    fn processes(
        &self,
        ui: &mut egui::Ui,
        store: &Store,
        linked: bool,
        design_arrived: Option<Duration>,
        cap: Option<(f32, &str)>,
    ) {
        let fresh = |t: Option<Instant>| t.is_some_and(|t| t.elapsed() < Duration::from_secs(2));
        let dot = |ui: &mut egui::Ui, ok: bool, what: &str| {
            let c = if ok {
                egui::Color32::from_rgb(80, 200, 120)
            } else {
                egui::Color32::from_rgb(220, 80, 60)
            };
            let state = if ok { "connected" } else { "not connected" };
            ui.colored_label(c, format!("{what}: {state}"));
        };
        dot(ui, fresh(store.heard.sim), "cloth-sim");
        dot(ui, fresh(store.heard.haptic), "haptic-loop");
        dot(ui, linked, "iceoryx2");
        if let Some(l) = &store.loop_tel {
            let us = |ns: u64| ns as f64 / 1000.0;
            ui.label(format!(
                "haptic: {} ticks, {} missed\nperiod p50 {:.0} µs · p99.9 {:.0} µs\ncompute p99 {:.0} µs · force {:.2} N",
                l.ticks,
                l.missed,
                us(l.period.quantile_ns(0.5)),
                us(l.period.quantile_ns(0.999)),
                us(l.compute.quantile_ns(0.99)),
                l.force_n
            ));
        }
        if let Some(s) = &store.sim_tel {
            let rate = if s.paused == 1 {
                "paused".to_string()
            } else {
                format!("{:.0} Hz", s.rate_hz)
            };
            ui.label(format!(
                "sim: {} vertices · {rate}\nframe p50 {:.2} ms · p99 {:.2} ms",
                s.vertices,
                s.frame_time.quantile_ns(0.5) as f64 * 1e-6,
                s.frame_time.quantile_ns(0.99) as f64 * 1e-6
            ));
            if s.asleep == 1 {
                ui.label("cloth at rest: asleep").on_hover_text(
                    "Not simulated until the pen, an edit or a setting wakes it, so the \
                     cores are left to the haptic loop (cloth-sim run --no-sleep: never)",
                );
            }
        }
        match cap {
            Some((max, why)) => ui.label(format!("UI: {:.0} fps (at most {max:.0}: {why})", self.fps))
                .on_hover_text("The studio draws no faster, so it leaves the CPUs to the simulation and the haptic loop"),
            None => ui.label(format!("UI: {:.0} fps", self.fps)),
        };
        if let Some(t) = design_arrived {
            ui.label(format!(
                "design received {:.0} ms after start",
                t.as_secs_f64() * 1000.0
            ))
            .on_hover_text("Mesh, positions, seams, all texture tiles, tool and material");
        }
        if store.rejected > 0 {
            ui.colored_label(
                egui::Color32::from_rgb(230, 160, 40),
                format!(
                    "{} messages rejected (last: {})",
                    store.rejected,
                    store.last_rejection.as_deref().unwrap_or("?")
                ),
            );
        }
    }
}

/// The haptic loop's timing and the local model's age over the last minute, and the
/// haptic period's histogram.
fn plots(ui: &mut egui::Ui, store: &Store) {
    let h = &store.history;
    let series = |f: fn(&Sample) -> f64| -> egui_plot::PlotPoints<'static> {
        h.iter().map(|s| [s.t, f(s)]).collect()
    };
    egui_plot::Plot::new("haptic timing")
        .height(140.0)
        .legend(egui_plot::Legend::default())
        .y_axis_label("µs")
        .show(ui, |p| {
            p.line(egui_plot::Line::new(
                "period p99.9",
                series(|s| s.haptic_period_p999_us),
            ));
            p.line(egui_plot::Line::new(
                "compute p99",
                series(|s| s.haptic_compute_p99_us),
            ));
        });
    egui_plot::Plot::new("model age")
        .height(120.0)
        .legend(egui_plot::Legend::default())
        .y_axis_label("ms")
        .show(ui, |p| {
            p.line(egui_plot::Line::new(
                "model age p99",
                series(|s| s.model_age_p99_ms),
            ));
            p.line(egui_plot::Line::new(
                "sim frame p50",
                series(|s| s.sim_frame_ms),
            ));
        });
    if let Some(l) = &store.loop_tel {
        // The period histogram around 1 ms, bucketed by 10 µs.
        let mut bars = Vec::new();
        for b in (900..1100).step_by(10) {
            // In u64: ten u32 counts from another process may add past u32's range.
            let c: u64 = l.period.counts[b..b + 10]
                .iter()
                .map(|&c| u64::from(c))
                .sum();
            if c > 0 {
                bars.push(egui_plot::Bar::new(b as f64 + 5.0, (c as f64).log10() + 1.0).width(9.0));
            }
        }
        egui_plot::Plot::new("period histogram")
            .height(110.0)
            .y_axis_label("log10 count + 1")
            .x_axis_label("period, µs")
            .show(ui, |p| {
                p.bar_chart(egui_plot::BarChart::new("period", bars))
            });
    }
}
