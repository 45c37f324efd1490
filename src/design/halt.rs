//! When a design's searches end early: at a deadline, at a flag, or never ([`Halt`]), with
//! what runs after them reserved at the pace the searches measure ([`After`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// When the searches end early, each keeping its best layout so far: at a deadline
/// (`shotdamp design --time-limit`), when a flag is raised (Ctrl-C), or never (the default).
/// A setting of the run, not of the design: every halt compares equal, and none enters a
/// stored answer's fingerprint.
///
/// A deadline bounds the whole design, not the searches only: what runs after them (each
/// placement's best evaluated for the page, the drive levels; [`Halt::plan_after`])
/// is reserved at the pace the searches measure, so the searches end that much earlier
/// ([`Halt::reached`]).
#[derive(Debug, Clone, Default)]
pub struct Halt {
    /// The design ends by this instant: its searches at their first evaluation after it, less
    /// the time reserved for what follows them.
    pub deadline: Option<Instant>,
    /// The searches end at their first evaluation after this flag is set.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// The evaluations planned after the searches and the pace measured so far.
    pub after: Arc<After>,
    /// What is expected to be left of the design, updated as its searches go.
    pub outlook: Arc<Outlook>,
    /// Which of the design's searches this halt stops (0 the main one, then one per Pareto
    /// budget): its share of the outlook.
    pub search: usize,
}

/// A design's work expected to be left, in layout evaluations: the search going on updates
/// its own share after each round (runs that ended leave nothing; a run going on is expected
/// to need what a placement of its size usually needs, [`crate::design::search::expected_per_start`],
/// or half again what it has done when it has already done more), the design the rest
/// (searches not yet begun, what follows them). A progress line divides it by the pace.
#[derive(Debug, Default)]
pub struct Outlook {
    /// Of each search (by [`Halt::search`]).
    searches: std::sync::Mutex<Vec<u64>>,
    /// Of what follows the searches.
    later: AtomicU64,
    /// Whether anything was set (else nothing is known).
    known: AtomicBool,
    /// What the design is doing, in words.
    phase: std::sync::Mutex<&'static str>,
    /// Layout evaluations made, and how many had been made when a share was last set.
    evaluated: AtomicU64,
    evaluated_at_set: AtomicU64,
}

impl Outlook {
    /// Says what the design is doing now and how many evaluations follow it.
    pub fn set_phase(&self, words: &'static str, later: u64) {
        if let Ok(mut p) = self.phase.lock() {
            *p = words;
        }
        self.set_later(later);
    }

    /// What the design is doing, in words ("" before it says).
    pub fn phase(&self) -> &'static str {
        self.phase.lock().map_or("", |p| *p)
    }

    /// Sets search `k`'s share.
    pub fn set_search(&self, k: usize, evaluations: u64) {
        if let Ok(mut s) = self.searches.lock() {
            if s.len() <= k {
                s.resize(k + 1, 0);
            }
            s[k] = evaluations;
        }
        self.evaluated_at_set.store(self.evaluated.load(Ordering::Relaxed), Ordering::Relaxed);
        self.known.store(true, Ordering::Relaxed);
    }

    /// Sets what follows the searches.
    pub fn set_later(&self, evaluations: u64) {
        self.later.store(evaluations, Ordering::Relaxed);
        self.evaluated_at_set.store(self.evaluated.load(Ordering::Relaxed), Ordering::Relaxed);
        self.known.store(true, Ordering::Relaxed);
    }

    /// The evaluations expected to be left, if known: the shares as last set, less the
    /// evaluations made since (down to a quarter of them: a share is set again at the end of
    /// every round of its search).
    pub fn left(&self) -> Option<u64> {
        let searches: u64 = self.searches.lock().map_or(0, |s| s.iter().sum());
        let set = searches.saturating_add(self.later.load(Ordering::Relaxed));
        let since =
            self.evaluated.load(Ordering::Relaxed).saturating_sub(self.evaluated_at_set.load(Ordering::Relaxed));
        self.known.load(Ordering::Relaxed).then(|| set.saturating_sub(since).max(set / 4))
    }
}

/// The work a design plans after its searches, and the searches' measured pace.
#[derive(Debug, Default)]
pub struct After {
    /// Layout evaluations planned after the searches on the searched model, at its pace.
    evaluations: AtomicU64,
    /// Layout evaluations planned after the searches on the file's model (when the searches
    /// run on a coarser one), and what one costs there on one thread, ns.
    judged: AtomicU64,
    judged_nanos: AtomicU64,
    /// How many times dearer an evaluation on the file's model is than the searches' by the
    /// nominal rule, in thousandths (0: not set): with the pace, a floor under `judged_nanos`
    /// (the cases may be cheaper than the searched layouts: the plate's corner case 1.1 s, a
    /// searched layout with points that never settle 5-20 s).
    dearer_milli: AtomicU64,
    /// Evaluations timed, and their total wall time, ns.
    timed: AtomicU64,
    nanos: AtomicU64,
    /// Evaluations on the file's model that follow the judging of a screened search (the
    /// best layout's drive levels): the judging leaves them room at its own pace.
    after_judging: AtomicU64,
}

impl PartialEq for Halt {
    fn eq(&self, _: &Halt) -> bool {
        true
    }
}

impl Halt {
    /// Whether the searches should end now: the flag is raised, or the deadline is nearer
    /// than the time reserved for what follows them ([`Halt::reserve`]).
    pub fn reached(&self) -> bool {
        self.interrupted()
            || self.deadline.is_some_and(|d| Instant::now().checked_add(self.reserve()).is_none_or(|t| t >= d))
    }

    /// Whether the deadline itself has passed (no reserve) or the flag was raised: what runs
    /// after the searches stops there.
    pub fn passed(&self) -> bool {
        self.interrupted() || self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    /// Whether the flag was raised.
    pub fn interrupted(&self) -> bool {
        self.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Plans `searched` layout evaluations after the searches at the searches' pace, and
    /// `judged` more at `per_judged` each (measured on the file's model; set before the
    /// design searches).
    pub fn plan_after(&self, searched: u64, judged: u64, per_judged: Option<Duration>) {
        self.plan_after_dearer(searched, judged, per_judged, 0.0);
    }

    /// [`Halt::plan_after`], with each judged evaluation costing at least `dearer` times the
    /// searches' measured pace.
    pub fn plan_after_dearer(&self, searched: u64, judged: u64, per_judged: Option<Duration>, dearer: f64) {
        self.after.dearer_milli.store((dearer.max(0.0) * 1e3) as u64, Ordering::Relaxed);
        self.after.evaluations.store(searched, Ordering::Relaxed);
        self.after.judged.store(judged, Ordering::Relaxed);
        let ns = per_judged.map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX));
        self.after.judged_nanos.store(ns, Ordering::Relaxed);
    }

    /// Sets the evaluations on the file's model that follow the judging ([`Halt::after_judging`]).
    pub fn plan_after_judging(&self, evaluations: u64) {
        self.after.after_judging.store(evaluations, Ordering::Relaxed);
    }

    /// The evaluations on the file's model that follow the judging of a screened search.
    pub fn after_judging(&self) -> u64 {
        self.after.after_judging.load(Ordering::Relaxed)
    }

    /// Sets this halt's search's share of the outlook ([`Outlook`]).
    pub fn expect(&self, evaluations: u64) {
        self.outlook.set_search(self.search, evaluations);
    }

    /// `f`, one layout evaluation, timed for the pace.
    pub fn timed<T>(&self, f: impl FnOnce() -> T) -> T {
        let started = Instant::now();
        let out = f();
        self.count(started, true);
        out
    }

    /// [`Halt::timed`] for an evaluation that may end early (`None`,
    /// [`crate::design::evaluate_below`]): counted, but only a whole one sets the pace (what
    /// runs after the searches are whole evaluations).
    pub fn timed_whole<T>(&self, f: impl FnOnce() -> Option<T>) -> Option<T> {
        let started = Instant::now();
        let out = f();
        self.count(started, out.is_some());
        out
    }

    /// Counts an evaluation begun at `started`; a `whole` one's time sets the pace.
    fn count(&self, started: Instant, whole: bool) {
        self.outlook.evaluated.fetch_add(1, Ordering::Relaxed);
        if whole {
            let ns = u64::try_from(started.elapsed().as_nanos()).unwrap_or(u64::MAX);
            self.after.nanos.fetch_add(ns, Ordering::Relaxed);
            self.after.timed.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// The mean wall time of an evaluation so far (zero before the first).
    pub fn pace(&self) -> Duration {
        let n = self.after.timed.load(Ordering::Relaxed);
        Duration::from_nanos(self.after.nanos.load(Ordering::Relaxed).checked_div(n).unwrap_or(0))
    }

    /// The time reserved after the searches: the planned evaluations spread over the threads,
    /// and one more (those in flight when the searches end), at the measured pace; and those
    /// planned on the file's model at theirs.
    pub fn reserve(&self) -> Duration {
        let threads = rayon::current_num_threads().max(1) as u64;
        let times = |n: u64| u32::try_from(n).unwrap_or(u32::MAX);
        let planned = self.after.evaluations.load(Ordering::Relaxed);
        let judged = self.after.judged.load(Ordering::Relaxed).div_ceil(threads);
        let dearer = self.after.dearer_milli.load(Ordering::Relaxed) as f64 / 1e3;
        let per_judged =
            Duration::from_nanos(self.after.judged_nanos.load(Ordering::Relaxed)).max(self.pace().mul_f64(dearer));
        self.pace()
            .saturating_mul(times(planned.div_ceil(threads) + 1))
            .saturating_add(per_judged.saturating_mul(times(judged)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outlook_is_the_shares_less_what_was_evaluated_since() {
        let halt = Halt::default();
        assert_eq!(halt.outlook.left(), None, "nothing known");
        halt.outlook.set_search(0, 100);
        Halt { search: 2, ..halt.clone() }.expect(40);
        halt.outlook.set_later(10);
        assert_eq!(halt.outlook.left(), Some(150));
        for _ in 0..30 {
            halt.timed(|| ());
        }
        assert_eq!(halt.outlook.left(), Some(120));
        for _ in 0..200 {
            halt.timed(|| ());
        }
        assert_eq!(halt.outlook.left(), Some(150 / 4), "a quarter of the shares while no round says better");
        halt.expect(0);
        assert_eq!(halt.outlook.left(), Some(50));
    }

    #[test]
    fn a_deadline_keeps_the_planned_work_after_the_searches_inside_it() {
        let threads = rayon::current_num_threads().max(1) as u32;
        let halt = Halt { deadline: Some(Instant::now() + Duration::from_secs(3600)), ..Halt::default() };
        assert_eq!(halt.reserve(), Duration::ZERO, "nothing timed, nothing planned");
        halt.timed(|| std::thread::sleep(Duration::from_millis(20)));
        let pace = halt.pace();
        assert!(pace >= Duration::from_millis(20), "{pace:?}");
        // Two evaluations a thread on the searched model, and one a thread at 100 s on the
        // file's: one round in flight more.
        halt.plan_after(2 * u64::from(threads), u64::from(threads), Some(Duration::from_secs(100)));
        assert_eq!(halt.reserve(), pace * 3 + Duration::from_secs(100));
        assert!(!halt.reached(), "an hour ahead holds the reserve");
        let near = Halt { deadline: Some(Instant::now() + Duration::from_secs(60)), ..halt.clone() };
        assert!(near.reached() && !near.passed(), "a minute ahead does not hold 100 s of work");
        // A reserve too large to add to an instant ends the searches; it does not overflow.
        near.plan_after(u64::MAX, u64::MAX, Some(Duration::MAX));
        assert!(near.reached());
    }
}
