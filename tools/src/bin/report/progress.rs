//! Progress on standard error: a line `[k/N] what (t s)` as each step of the run starts, and
//! within a step that runs longer than a few seconds, now and then, the work done, the time
//! spent and the time left at the rate so far.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A step's first line of work done comes after this long (shorter steps print none) ...
const FIRST: Duration = Duration::from_secs(3);
/// ... and the next ones at most this often.
const EVERY: Duration = Duration::from_secs(5);

/// The run's steps: one line each, counted `[1/N]` to `[N/N]`.
pub struct Progress {
    steps: Vec<String>,
    step: usize,
    start: Instant,
}

impl Progress {
    /// The steps the run will take, in order.
    pub fn new(steps: Vec<String>) -> Progress {
        Progress {
            steps,
            step: 0,
            start: Instant::now(),
        }
    }

    /// Announces the next step.
    pub fn next(&mut self) {
        let what = self
            .steps
            .get(self.step)
            .map_or("finishing", String::as_str);
        self.step = (self.step + 1).min(self.steps.len());
        eprintln!(
            "[{}/{}] {what} ({:.1} s)",
            self.step,
            self.steps.len(),
            self.start.elapsed().as_secs_f64()
        );
    }

    /// Seconds since the run started.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// The work of one step, counted in units (sets, trials, folds) as threads finish them: a line
/// `      <what>: 120/400 <units>, 12 s, about 28 s left` once the step has run a few seconds,
/// then at most every few seconds.
pub struct Meter {
    what: String,
    units: &'static str,
    total: AtomicUsize,
    done: AtomicUsize,
    start: Instant,
    /// When the last line was printed (`None`: none yet).
    last: Mutex<Option<Instant>>,
}

impl Meter {
    /// `total` units of `units` to do, for `what`.
    pub fn new(what: impl Into<String>, total: usize, units: &'static str) -> Meter {
        Meter {
            what: what.into(),
            units,
            total: AtomicUsize::new(total),
            done: AtomicUsize::new(0),
            start: Instant::now(),
            last: Mutex::new(None),
        }
    }

    /// More units to do than announced (a step that decides as it goes, such as trials added
    /// until a standard error is small enough).
    pub fn more(&self, units: usize) {
        self.total.fetch_add(units, Ordering::Relaxed);
    }

    /// `units` more done; prints a line when it is time.
    pub fn add(&self, units: usize) {
        let done = self.done.fetch_add(units, Ordering::Relaxed) + units;
        let now = Instant::now();
        let spent = now - self.start;
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        let due = match *last {
            None => spent >= FIRST,
            Some(t) => now - t >= EVERY,
        };
        let total = self.total.load(Ordering::Relaxed).max(done);
        if !due || done == 0 || done >= total {
            return;
        }
        *last = Some(now);
        let left = spent.as_secs_f64() * (total - done) as f64 / done as f64;
        eprintln!(
            "      {}: {done}/{total} {}, {:.0} s, about {:.0} s left",
            self.what,
            self.units,
            spent.as_secs_f64(),
            left
        );
    }

    /// A callback that adds its argument, for the library's functions that report their work.
    pub fn counter(&self) -> impl Fn(usize) + Sync + '_ {
        move |n| self.add(n)
    }
}
