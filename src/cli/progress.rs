//! Progress on a terminal: a spinner for stages of unknown length, a counting bar for the
//! others (tensors, glyphs); nothing with `--quiet` or when stderr is not a terminal.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::Duration;

use crate::progress::Progress;
use indicatif::{ProgressBar, ProgressStyle};

pub struct Terminal {
    on: bool,
    bar: Mutex<Option<ProgressBar>>,
}

impl Terminal {
    pub fn new(quiet: bool) -> Self {
        Self {
            on: !quiet && std::io::stderr().is_terminal(),
            bar: Mutex::new(None),
        }
    }

    fn bar(&self) -> std::sync::MutexGuard<'_, Option<ProgressBar>> {
        self.bar.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A bar for `total` steps of a run whose message changes (the bench's configurations).
    pub fn steps(&self, total: u64, message: &str) {
        if !self.on {
            return;
        }
        let mut bar = self.bar();
        let pb = bar.get_or_insert_with(|| {
            let pb = ProgressBar::new(total);
            pb.set_style(
                ProgressStyle::with_template("{bar:30} {pos}/{len} [{elapsed}] {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            pb
        });
        pb.set_length(total);
        pb.set_message(message.to_string());
    }

    pub fn step_to(&self, done: u64, message: &str) {
        if let Some(pb) = self.bar().as_ref() {
            pb.set_position(done);
            pb.set_message(message.to_string());
        }
    }
}

impl Progress for Terminal {
    fn begin(&self, stage: &str, items: Option<u64>) {
        if !self.on {
            return;
        }
        let mut bar = self.bar();
        if let Some(old) = bar.take() {
            old.finish_and_clear();
        }
        let pb = match items {
            None => {
                let pb = ProgressBar::new_spinner();
                pb.set_style(
                    ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
                        .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                );
                pb.enable_steady_tick(Duration::from_millis(120));
                pb
            }
            Some(n) => {
                let pb = ProgressBar::new(n);
                pb.set_style(
                    ProgressStyle::with_template(
                        "{msg:>18} [{elapsed_precise}] {wide_bar} {human_pos}/{human_len} ({eta})",
                    )
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                pb.enable_steady_tick(Duration::from_millis(200));
                pb
            }
        };
        pb.set_message(stage.to_string());
        *bar = Some(pb);
    }

    fn advance(&self, n: u64) {
        if let Some(pb) = self.bar().as_ref() {
            pb.inc(n);
        }
    }

    fn end(&self) {
        if let Some(pb) = self.bar().take() {
            pb.finish_and_clear();
        }
    }

    /// Printed with or without `--quiet`: it says what was assumed about the data.
    fn notice(&self, line: &str) {
        match self.bar().as_ref() {
            Some(pb) => pb.suspend(|| eprintln!("notice: {line}")),
            None => eprintln!("notice: {line}"),
        }
    }
}
