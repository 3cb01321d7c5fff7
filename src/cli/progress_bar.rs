//! indicatif progress bar behind the library's `Progress` trait: drawn on a terminal; where
//! standard error is not one (a pipe, a log), a line at each tenth of a long job instead, so
//! that a run of minutes is never silent.

use geardyn::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// A job this long (seconds) or longer reports its tenths in plain lines off a terminal.
const PLAIN_AFTER_S: f64 = 5.0;

/// A progress bar on standard error, or plain progress lines off a terminal.
pub struct Bar {
    bar: ProgressBar,
    /// Off a terminal: what the job is and when it started, and the last tenth reported.
    plain: Option<(Mutex<(String, Instant)>, AtomicU64)>,
}

impl Bar {
    pub fn new() -> Self {
        let terminal = std::io::stderr().is_terminal();
        Bar {
            bar: ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr()),
            plain: (!terminal).then(|| {
                (
                    Mutex::new((String::new(), Instant::now())),
                    AtomicU64::new(0),
                )
            }),
        }
    }

    /// Off a terminal: a line when the job has passed another tenth and has run for
    /// [`PLAIN_AFTER_S`] or more.
    fn report_plain(&self) {
        let Some((job, tenth)) = &self.plain else {
            return;
        };
        let (pos, len) = (self.bar.position(), self.bar.length().unwrap_or(0));
        if len == 0 {
            return;
        }
        let now = 10 * pos / len;
        if tenth.fetch_max(now, Ordering::Relaxed) >= now {
            return;
        }
        let Ok(job) = job.lock() else {
            return;
        };
        let elapsed = job.1.elapsed().as_secs_f64();
        if elapsed < PLAIN_AFTER_S || pos >= len {
            return;
        }
        let left = elapsed * (len - pos) as f64 / pos.max(1) as f64;
        eprintln!(
            "{}: {pos}/{len} ({}%), {elapsed:.0} s, about {left:.0} s left",
            job.0,
            10 * now
        );
    }
}

impl Progress for Bar {
    fn start(&self, total: u64, what: &str) {
        self.bar.set_length(total);
        self.bar.set_position(0);
        if let Ok(style) = ProgressStyle::with_template(&format!(
            "{{bar:40}} {{pos}}/{{len}} {what} [{{elapsed_precise}} < {{eta_precise}}]"
        )) {
            self.bar.set_style(style);
        }
        if let Some((job, tenth)) = &self.plain {
            if let Ok(mut j) = job.lock() {
                *j = (what.to_string(), Instant::now());
            }
            tenth.store(0, Ordering::Relaxed);
        }
    }
    fn advance(&self, n: u64) {
        self.bar.inc(n);
        self.report_plain();
    }
    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
