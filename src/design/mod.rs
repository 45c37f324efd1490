//! Damper design (docs/design.md): which masses carry a container, how a budget of shot is
//! split among them and what clearance each gets, chosen to lower the largest (or the RMS)
//! compliance of chosen masses over frequency bands. The paper's conclusion is a claim of this
//! kind: "multi-unit dampers with properly selected mass ratios and clearances effectively
//! suppress the resonant peaks over a wide frequency range".
//!
//! [`evaluate`] computes the objective of one [`Layout`] with the exact simulator; the search
//! over layouts is in [`search`]. No I/O.

mod band;
mod evaluation;
pub mod halt;
pub mod limits;
pub mod nelder_mead;
pub mod race;
pub mod rounds;
pub mod search;
pub mod seismic;
pub mod space;
pub mod stored;

use rayon::prelude::*;

pub use evaluation::{Evaluation, Motion, Point, SAME_ORBIT};

use crate::model::{Clearance, Damper, Structure};
use crate::sim::motion::system::Dynamics;
use crate::sim::settle::statistic::ClassCounts;
use crate::sim::{SteadyOptions, System};

/// Periods of a design point's orbit search before a point with no orbit is measured
/// ([`crate::sim::settle::handed_over`]): an irregular point then costs about 550 periods of its
/// budget instead of all of it.
pub const HAND_OVER: usize = 100;

/// Half-width of a design point's 95 % interval, relative to its statistic, at which its
/// measurement ends (the report's sweeps use 1 %): a design compares layouts whose objectives
/// differ by more, and says where two are equal within their intervals.
pub const INTERVAL_TOL: f64 = 0.05;

/// What a design file asks (`[design]`, validated): see docs/design.md.
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    /// 0-based masses that may carry a container.
    pub candidates: Vec<usize>,
    /// Most containers of a layout.
    pub max_beds: usize,
    /// Total shot mass, kg.
    pub shot_kg: f64,
    /// Bounds of the clearance, mm.
    pub clearance_mm: (f64, f64),
    /// One clearance for every container (else one each).
    pub shared_clearance: bool,
    /// The direction every container's bed moves in (vertical: the paper's).
    pub direction: crate::model::Direction,
    /// Forces (N) at which the best layout and the cases are evaluated after the search, for
    /// the reduction against the drive level (not part of the objective); empty: the file gave
    /// none, and [`Spec::drive_levels`] chooses them (none against records).
    pub drive_levels_n: Vec<f64>,
    /// The bands whose response is lowered.
    pub bands: Vec<Band>,
    /// What is measured over a band (peak or RMS compliance).
    pub measure: Measure,
    /// How each band is swept (from rest, up, down).
    pub sweeps: Vec<Sweep>,
    /// The search's settings.
    pub search: search::Options,
    /// Total shot mass ratios of the Pareto front (may be empty).
    pub pareto_mass_ratios: Vec<f64>,
    /// Modal damping ratios (every mode) and force amplitudes (N) of the scenarios: every
    /// combination, the nominal value where a list is empty; no scenarios when both are.
    pub scenario_damping: Vec<f64>,
    /// Force amplitudes of the scenarios, N.
    pub scenario_force_n: Vec<f64>,
    /// How the scenarios' objectives combine.
    pub combine: Combine,
    /// The paper's SDOF technique beside the search: the 0-based mode and the candidate
    /// clearances (mm) of its rule (Fig. 9).
    pub sdof: Option<(usize, Vec<f64>)>,
    /// `report = true`: `shotdamp report` shows this design.
    pub report: bool,
    /// `[design.scenarios] models = true`: the file's models are scenarios of one search.
    pub scenario_models: bool,
    /// With `scenario_models`, each model's label, structure and force (filled when the file
    /// is loaded).
    pub model_structures: Vec<(String, Structure, f64)>,
    /// Evaluate the layouts a search stored ([`stored`]) instead of searching (what
    /// `shotdamp report` does; never from the file).
    pub replay: bool,
    /// When the searches end early, each placement keeping its best layout so far
    /// (`shotdamp design --time-limit`, Ctrl-C; never from the file, not part of the
    /// fingerprint).
    pub halt: halt::Halt,
    /// What every search ended with, gathered from a sharded search's parts (`shotdamp
    /// design --merge`): per search (the main one, then one per Pareto budget) and
    /// placement. The design then searches nothing and reports the unsharded answer.
    /// `None`: search.
    pub merged: Option<std::sync::Arc<Vec<Vec<search::Searched>>>>,
    /// `[design.screen]`: the searches evaluate layouts on this coarser model of the
    /// structure; each placement's best, and everything after the search, is evaluated on the
    /// file's own (`None`: everything on the file's).
    pub screen: Option<Screen>,
    /// `[design] ground_motions`: the layouts are judged under these records instead of over
    /// frequency bands (`bands`, `sweeps` and the drive levels are then empty;
    /// [`seismic`]).
    pub suite: Option<seismic::Suite>,
}

/// A coarser model of a finite-element structure that a design searches on (fewer
/// fixed-interface modes: every steady state cheaper).
#[derive(Debug, Clone, PartialEq)]
pub struct Screen {
    /// The structure reduced with the screen's modes.
    pub structure: Structure,
    /// What was kept, in words (e.g. "fixed-interface modes below 1000 Hz").
    pub kept: String,
    /// The forcing periods a steady state of the search may run, where not the design's
    /// `steady.max_periods` (at least its `min_periods`).
    pub max_periods: Option<usize>,
}

/// What a design search costs at most, known before it runs (printed by `shotdamp design`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Placements searched (each search).
    pub placements: usize,
    /// Searches: the best layout's, then one per Pareto ratio.
    pub searches: usize,
    /// Most layout evaluations, over every search and what follows it (the experiment's
    /// cases, the clearance profile, the SDOF rule's layouts).
    pub evaluations: u64,
    /// Steady-state points of one layout evaluation (bands x sweeps x scenarios).
    pub points: u64,
    /// How much dearer a point is than on the paper's structure because the structure's
    /// fastest mode oscillates many times per forcing period (the event search steps through
    /// each): the highest natural frequency over the lowest band frequency, over
    /// [`Budget::FAST_RATIO`], at least 1.
    pub fast: f64,
    /// Of `evaluations`, those on the coarser model of `[design.screen]` (the searches and
    /// the maps near the optimum; 0 without a screen), that model's `fast` and its size.
    pub screened: (u64, f64, usize),
    /// The evaluations a design like it usually makes, and of them those on the screen's
    /// model: low and high when its starts converge (the searches at the low and high
    /// [`search::EXPECTED_C`], the rest as `evaluations` counts it), then low and high when
    /// they spend their iterations ([`search::spent_evaluations`]). What the estimates
    /// ([`Budget::expected_seconds`]) count.
    pub expected: [(u64, u64); 4],
}

impl Budget {
    /// Fastest-mode oscillations per forcing period that the nominal cost covers (the
    /// five-storey example's 43 Hz top mode over its 5 Hz band edge is 8.6).
    pub const FAST_RATIO: f64 = 10.0;

    /// Nominal CPU seconds of one steady-state point of a structure of `n` masses on one
    /// core: 150 us on the paper's three masses (BENCHMARKS.md: 49 us a followed point, 147
    /// us from rest), growing as `n^2` above three.
    pub fn seconds_per_point(n: usize) -> f64 {
        let r = (n as f64 / 3.0).max(1.0);
        1.5e-4 * r * r
    }

    /// Wall seconds of the most evaluations on `threads` threads for a structure of `n`
    /// masses at the nominal cost of a point ([`Budget::seconds_per_point`]): a point of
    /// violent motion (many impacts a period, a transient that settles late) costs more, so
    /// this is an estimate, not a bound; the number of evaluations is a bound.
    pub fn nominal_seconds(&self, n: usize, threads: usize) -> f64 {
        let screen = Self::seconds_per_point(self.screened.2) * Self::stepping(self.screened.1, self.screened.2);
        self.seconds_at(Self::seconds_per_point(n) * Self::stepping(self.fast, n), screen, threads)
    }

    /// How many times dearer an evaluation on the file's model of `n` masses is than one on the
    /// model the searches run on (1 without a screen), by the nominal rule.
    pub fn judged_over_searched(&self, n: usize) -> f64 {
        if self.screened.0 == 0 {
            return 1.0;
        }
        let judged = Self::seconds_per_point(n) * Self::stepping(self.fast, n);
        let screen = Self::seconds_per_point(self.screened.2) * Self::stepping(self.screened.1, self.screened.2);
        (judged / screen).max(1.0)
    }

    /// How much a structure of `n` masses whose fastest mode makes it `fast` times dearer
    /// ([`Budget::fast`]) costs above the nominal point: `fast` up to
    /// [`LARGE_ABOVE`](crate::sim::motion::system::LARGE_ABOVE) degrees of freedom, 1 above,
    /// where the event search skips the fastest modes' oscillations in coarse windows (on the
    /// reduced plate of 47 coordinates, whose fastest kept mode oscillates 322 times a period,
    /// a judged steady state costs 67-80 ms against the 37 ms of the `n^2` rule; with the
    /// factor the estimate read 1.2 s).
    pub fn stepping(fast: f64, n: usize) -> f64 {
        if n > crate::sim::motion::system::LARGE_ABOVE {
            1.0
        } else {
            fast
        }
    }

    /// How far the mean cost of a layout evaluation over a whole design may fall below and rise
    /// above the one the dry run's probe measures on the layouts of the coarse scans (the
    /// search's simplexes close in on layouts whose points may settle sooner or later).
    pub const EVALUATION_SPREAD: (f64, f64) = (0.5, 2.0);

    /// Of the threads' time, the share a design keeps busy at the least (the last rounds of
    /// its searches hold fewer runs than threads).
    pub const THREAD_USE: f64 = 0.75;

    /// Wall seconds a design usually takes on `threads` threads at `searched` seconds a layout
    /// evaluation on the model its searches run on and `judged` on the file's model (the same
    /// without a screen), each measured on one thread: low (the low evaluation count, cheaper
    /// evaluations, every thread busy) and high. An estimate: a search may still stop sooner or
    /// later; [`Budget::evaluations`] bounds.
    /// `spent`: the design's starts are expected to spend their iterations (its objective is
    /// noisy and it has no `step_tolerance`).
    pub fn expected_seconds(&self, searched: f64, judged: f64, threads: usize, spent: bool) -> (f64, f64) {
        let at = |(all, screened): (u64, u64), f: f64, threads: f64| {
            let on_file = all.saturating_sub(screened);
            let (searched_n, judged_n) = if self.screened.0 == 0 { (all, 0) } else { (screened, on_file) };
            (searched_n as f64 * searched + judged_n as f64 * judged) * f / threads
        };
        let t = threads.max(1) as f64;
        let (lo, hi) = Self::EVALUATION_SPREAD;
        let k = if spent { 2 } else { 0 };
        (at(self.expected[k], lo, t), at(self.expected[k + 1], hi, (t * Self::THREAD_USE).max(1.0)))
    }

    /// Wall seconds of the most evaluations on `threads` threads at `point` seconds a steady
    /// state on the file's model and `screen_point` on the screen's (the searches of a
    /// screened design).
    pub fn seconds_at(&self, point: f64, screen_point: f64, threads: usize) -> f64 {
        let screened = self.screened.0;
        let judged = self.evaluations.saturating_sub(screened);
        (judged as f64 * point + screened as f64 * screen_point) * self.points as f64 / threads.max(1) as f64
    }
}

/// A design's drive levels relative to its nominal force when its file gives no
/// `drive_levels_n` and its scenarios do not vary the force: from a quarter to four times the
/// force the design is made for (docs/design.md, "Drive level").
pub const DEFAULT_DRIVE_LEVELS: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

impl Spec {
    /// The forces (N, or m/s^2 for moving supports) the best layout and the cases are evaluated
    /// at again after the search: the file's `drive_levels_n`; without them, `nominal` times
    /// [`DEFAULT_DRIVE_LEVELS`], unless the scenarios already vary the force (then none: the
    /// search's own evaluations give the levels).
    pub fn drive_levels(&self, nominal: f64) -> Vec<f64> {
        if !self.drive_levels_n.is_empty() {
            self.drive_levels_n.clone()
        } else if self.scenario_force_n.len() > 1 || self.suite.is_some() {
            Vec::new()
        } else {
            DEFAULT_DRIVE_LEVELS.iter().map(|k| k * nominal).collect()
        }
    }

    /// What a layout's objective is a share of, in words: "the bare structure's worst band",
    /// or against records the bare building's response over the suite.
    pub fn objective_words(&self) -> String {
        match &self.suite {
            None => "the bare structure's worst band".into(),
            Some(s) => format!("the bare building's {} ({})", s.response.words(), s.over.words()),
        }
    }

    /// What one layout evaluation computes, in words: "steady states", or "record runs".
    pub fn point_words(&self) -> &'static str {
        if self.suite.is_some() {
            "record runs"
        } else {
            "steady states"
        }
    }

    /// How many forces [`Spec::drive_levels`] gives.
    pub fn drive_level_count(&self) -> usize {
        self.drive_levels(1.0).len()
    }

    /// Scenarios of one evaluation (1: the nominal structure and force).
    pub fn scenario_count(&self) -> usize {
        let models = if self.scenario_models { self.model_structures.len().max(1) } else { 1 };
        self.scenario_damping.len().max(1) * self.scenario_force_n.len().max(1) * models
    }

    /// Steady-state points of one layout evaluation.
    pub fn evaluation_points(&self) -> u64 {
        if let Some(suite) = &self.suite {
            return suite.records.len() as u64 * self.scenario_count() as u64;
        }
        let band: u64 = self.bands.iter().map(|b| b.freq_hz.len() as u64).sum();
        band * self.sweeps.len() as u64 * self.scenario_count() as u64
    }

    /// What a search of this design costs at most (a replay: the stored layouts only), on a
    /// structure whose highest natural frequency is `highest_hz`.
    pub fn budget(&self, cases: usize, highest_hz: f64) -> Budget {
        let lowest = self.bands.iter().flat_map(|b| b.freq_hz.first().copied()).fold(f64::INFINITY, f64::min);
        let placements = search::placements(&self.candidates, self.max_beds);
        let searches = 1 + self.pareto_mass_ratios.len();
        let space = search::Space {
            placements: placements.clone(),
            shot_kg: self.shot_kg,
            clearance_mm: self.clearance_mm,
            shared_clearance: self.shared_clearance,
        };
        let search = if self.replay { placements.len() as u64 } else { search::most_evaluations(&space, &self.search) };
        let usual = search::expected_evaluations(&space, &self.search);
        let spent = search::spent_evaluations(&space, &self.search);
        let usual = if self.replay { [search; 4] } else { [usual[0], usual[2], spent[0], spent[1]] };
        let sdof = if self.sdof.is_some() { placements.len() as u64 } else { 0 };
        // The drive levels evaluate the best layout and the cases once at each force.
        let levels = (self.drive_level_count() * (1 + cases)) as u64;
        let after = cases as u64 + PROFILE_POINTS as u64 + sdof + levels;
        let searched = search.saturating_mul(searches as u64);
        let fast = |hz: f64| (hz / lowest / Budget::FAST_RATIO).max(1.0);
        // A screened design searches (and maps the optimum) on the screen's model, then
        // evaluates each placement's best on the file's as well; its replay evaluates the
        // stored placements on the screen's model too and maps the optimum there. Per case:
        // the evaluations on the screen's model, and those added to the unscreened count.
        let map = PROFILE_POINTS as u64 + 1;
        let screened = match &self.screen {
            Some(_) if !self.replay => (searched.saturating_add(map), (placements.len() * searches) as u64 + 1),
            Some(_) => (placements.len() as u64 + map, placements.len() as u64 + 1),
            None => (0, 0),
        };
        // The same counts with the searches' usual evaluations.
        let expected = usual.map(|one| {
            let searched = one.saturating_mul(searches as u64);
            let screened_one = match &self.screen {
                Some(_) if !self.replay => searched.saturating_add(map),
                Some(_) => screened.0,
                None => 0,
            };
            (searched.saturating_add(after).saturating_add(screened.1), screened_one)
        });
        Budget {
            expected,
            placements: placements.len(),
            searches,
            evaluations: searched.saturating_add(after).saturating_add(screened.1),
            points: self.evaluation_points(),
            fast: fast(highest_hz),
            screened: (
                screened.0,
                fast(self.screen.as_ref().map_or(highest_hz, |sc| sc.structure.highest_natural_frequency_hz())),
                self.screen.as_ref().map_or(0, |sc| sc.structure.dof()),
            ),
        }
    }
}

/// Layouts of the clearance profile drawn after a search (the best layout at clearances
/// spread over the file's range).
pub const PROFILE_POINTS: usize = 11;

/// A frequency band and the masses whose compliance counts in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Name for tables, e.g. "mode 3".
    pub name: String,
    /// Frequencies, Hz, ascending.
    pub freq_hz: Vec<f64>,
    /// 0-based masses.
    pub masses: Vec<usize>,
}

/// How a band's compliances become one number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The largest compliance of the band's masses over its frequencies.
    Peak,
    /// The root mean square over the band's frequencies, the largest over its masses.
    Rms,
}

/// Which sweeps a band is computed by. Where stable motions coexist (Fig. 5's fold) the
/// compliance at a frequency is the largest over the sweeps: a real structure may sit on any.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Every frequency from rest.
    Rest,
    /// Continuation upward, each point from the previous one's final state.
    Up,
    /// Continuation downward.
    Down,
}

/// One scenario of the values a design must cope with (the paper leaves the damping and the
/// force that reaches m1 unstated): the structure and the force amplitude.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Name for tables, e.g. "damping 0.005, F 2.6 N".
    pub name: String,
    /// The structure of this scenario.
    pub structure: Structure,
    /// Force amplitude, N.
    pub force: f64,
}

/// How the objectives of the scenarios combine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Combine {
    /// The worst scenario counts.
    Worst,
    /// The mean over the scenarios.
    Mean,
}

/// What a design is asked to do: the structure, the force, the bands and how they count.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The nominal structure.
    pub structure: Structure,
    /// 0-based driven mass.
    pub driven: usize,
    /// The nominal force amplitude, N.
    pub force: f64,
    /// The bands whose response is lowered.
    pub bands: Vec<Band>,
    /// What is measured over a band.
    pub measure: Measure,
    /// How each band is swept.
    pub sweeps: Vec<Sweep>,
    /// Steady-state settings of the sweeps.
    pub steady: SteadyOptions,
    /// Scenarios the objective is taken over (empty: the nominal structure and force only).
    pub scenarios: Vec<Scenario>,
    /// How the scenarios' objectives combine.
    pub combine: Combine,
    /// The direction every container's bed moves in.
    pub direction: crate::model::Direction,
    /// The supports move (each scenario's `force` is their acceleration, m/s^2, and
    /// `driven` is unused) instead of a force on `driven`.
    pub supports: bool,
    /// Layouts judged under recorded ground motions instead of over `bands` ([`seismic`]).
    pub suite: Option<seismic::Suite>,
}

impl Problem {
    /// The system of scenario `sc` with `dampers`: driven by its force, or on its moving
    /// supports.
    pub fn system(&self, sc: &Scenario, dampers: Vec<crate::model::Damper>) -> System {
        let sys = System::plastic(sc.structure.clone(), dampers, self.driven, sc.force);
        if self.supports {
            sys.on_supports(sc.force)
        } else {
            sys
        }
    }

    /// What drives the structure, for words and units ([`crate::model::base::Drive`]).
    pub fn drive(&self) -> crate::model::base::Drive {
        crate::model::base::Drive::of(self.supports)
    }

    /// The scenarios evaluated: the given ones, or the nominal structure and force.
    pub fn cases(&self) -> Vec<Scenario> {
        if self.scenarios.is_empty() {
            vec![Scenario { name: "nominal".into(), structure: self.structure.clone(), force: self.force }]
        } else {
            self.scenarios.clone()
        }
    }
}

/// One design: the containers' hosts, their share of the shot and their clearances.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// 0-based host masses, distinct.
    pub hosts: Vec<usize>,
    /// Bed masses, kg (one per host).
    pub masses_kg: Vec<f64>,
    /// Clearances, mm (one per host; infinite: no top).
    pub clearances_mm: Vec<f64>,
}

impl Layout {
    /// The hosts in words: "m2 m3".
    pub fn hosts_words(&self) -> String {
        self.hosts.iter().map(|h| format!("m{}", h + 1)).collect::<Vec<_>>().join(" ")
    }

    /// The dampers of this layout (a bed of zero mass is no damper), moving along
    /// `direction`.
    pub fn dampers(&self, direction: crate::model::Direction) -> Vec<Damper> {
        self.hosts
            .iter()
            .zip(&self.masses_kg)
            .zip(&self.clearances_mm)
            .filter(|((_, m), _)| **m > 0.0)
            .map(|((&host, &mass), &d)| Damper::new(host, mass, Clearance::from_mm(d)).along(direction))
            .collect()
    }

    /// Total shot mass, kg.
    pub fn shot_kg(&self) -> f64 {
        self.masses_kg.iter().sum()
    }
}

/// Compliance of every mass at each frequency of `band` for `sys`, the largest over `sweeps`,
/// and the number of unsettled points.
pub fn band_compliance(sys: &System, band: &Band, sweeps: &[Sweep], steady: &SteadyOptions) -> (Vec<Vec<f64>>, usize) {
    let b = band::band_compliance_on(&Dynamics::unforced(sys), sys, band, sweeps, steady, false, None);
    (b.compliance, b.unsettled)
}

/// The half-width of a band's measure ([`measure`]) from its points' intervals: the peak's
/// own; for the RMS, the largest of the band's (the RMS moves by at most the largest shift).
/// NaN where a point it rests on has no known interval (a record too short for its batches):
/// not 0, which is a certified orbit's.
pub fn measure_half_width(band: &Band, points: &[Vec<Point>], at: (usize, usize), how: Measure) -> f64 {
    let hw = |p: &Point| p.half_width;
    match how {
        Measure::Peak => points.get(at.0).and_then(|r| r.get(at.1)).map_or(0.0, hw),
        Measure::Rms => points
            .iter()
            .flat_map(|r| band.masses.iter().filter_map(|&m| r.get(m)).map(hw))
            .fold(0.0, |a: f64, h| if a.is_nan() || h.is_nan() { f64::NAN } else { a.max(h) }),
    }
}

/// The measure of a band's compliances, and the frequency index and mass of its largest one.
pub fn measure(band: &Band, compliance: &[Vec<f64>], how: Measure) -> (f64, usize, usize) {
    let mut peak = (f64::NEG_INFINITY, 0, band.masses.first().copied().unwrap_or(0));
    for (i, row) in compliance.iter().enumerate() {
        for &m in &band.masses {
            if row[m] > peak.0 {
                peak = (row[m], i, m);
            }
        }
    }
    match how {
        Measure::Peak => peak,
        Measure::Rms => {
            let n = compliance.len().max(1) as f64;
            let (value, mass) = band
                .masses
                .iter()
                .map(|&m| ((compliance.iter().map(|r| r[m] * r[m]).sum::<f64>() / n).sqrt(), m))
                .fold((f64::NEG_INFINITY, 0), |a, b| if b.0 > a.0 { b } else { a });
            (value, peak.1, mass)
        }
    }
}

/// The measure of every band (every record of a suite) for the bare structure, per scenario
/// ([`Problem::cases`]).
pub fn bare(problem: &Problem) -> Vec<Vec<f64>> {
    if let Some(suite) = &problem.suite {
        return seismic::bare(problem, suite);
    }
    problem
        .cases()
        .iter()
        .map(|sc| {
            let sys = problem.system(sc, Vec::new());
            problem
                .bands
                .iter()
                .map(|b| measure(b, &band_compliance(&sys, b, &problem.sweeps, &problem.steady).0, problem.measure).0)
                .collect()
        })
        .collect()
}

/// Evaluates one layout (`bare`: per scenario, the bands' measures without dampers, from
/// [`bare`]).
pub fn evaluate(problem: &Problem, bare: &[Vec<f64>], layout: &Layout) -> Evaluation {
    if let Some(suite) = &problem.suite {
        return seismic::evaluate(problem, suite, bare, layout);
    }
    evaluated(problem, bare, layout, None)
}

/// [`evaluate`] where only an objective below `cap` matters (the comparison a Nelder-Mead step
/// makes with it): `None` when the objective is above `cap`, found as soon as a certified
/// periodic orbit of a band's mass has a compliance whose ratio to the band's bare measure is
/// above `cap` (the band's peak lies at least that high, so the objective, the worst band's
/// and scenario's peak relative to the bare structure's, does too), its sweeps then ended
/// there. Else the
/// evaluation [`evaluate`] gives, the same numbers: every point was computed. Where the
/// objective is not a largest of its parts (a mean over scenarios, an RMS measure, a suite of
/// records) or `cap` is not finite, always the whole evaluation.
pub fn evaluate_below(problem: &Problem, bare: &[Vec<f64>], layout: &Layout, cap: f64) -> Option<Evaluation> {
    let largest = problem.suite.is_none() && problem.combine == Combine::Worst && problem.measure == Measure::Peak;
    if !(largest && cap.is_finite()) {
        return Some(evaluate(problem, bare, layout));
    }
    let reached = std::sync::atomic::AtomicBool::new(false);
    let e = evaluated(problem, bare, layout, Some((cap, &reached)));
    (!reached.load(std::sync::atomic::Ordering::Relaxed)).then_some(e)
}

/// [`evaluate`] without a suite of records, its sweeps ended early where `over` says
/// ([`band::scenario`]).
fn evaluated(
    problem: &Problem,
    bare: &[Vec<f64>],
    layout: &Layout,
    over: Option<(f64, &std::sync::atomic::AtomicBool)>,
) -> Evaluation {
    // The scenarios side by side, gathered in order: the same numbers for any thread count.
    let mut runs: Vec<_> =
        problem.cases().par_iter().zip(bare).map(|(sc, b)| band::scenario(problem, sc, b, layout, over)).collect();
    let objectives: Vec<f64> = runs.iter().map(|r| r.relative).collect();
    let worst_scenario =
        objectives.iter().enumerate().fold(0, |w, (i, o)| if *o > objectives[w] || o.is_nan() { i } else { w });
    let (objective, half_width) = match problem.combine {
        Combine::Worst => (objectives[worst_scenario], runs[worst_scenario].half_width),
        // The mean moves by at most the mean of the shifts.
        Combine::Mean => {
            let k = objectives.len() as f64;
            (objectives.iter().sum::<f64>() / k, runs.iter().map(|r| r.half_width).sum::<f64>() / k)
        }
    };
    let mut classes = ClassCounts::default();
    for r in &runs {
        classes.iter_mut().zip(r.classes).for_each(|(a, b)| *a += b);
    }
    let w = &runs[worst_scenario];
    Evaluation {
        bands: w.bands.clone(),
        bare: bare[worst_scenario].clone(),
        objective,
        scenarios: objectives,
        worst_scenario,
        worst: w.worst,
        unsettled: runs.iter().map(|r| r.unsettled).sum(),
        points: runs.iter().map(|r| r.points).sum(),
        motion: runs[worst_scenario].motion.clone(),
        half_width,
        bands_half_width: runs[worst_scenario].bands_half_width.clone(),
        classes,
        measured: runs.iter().map(|r| r.measured).sum(),
        screened: runs.iter().map(|r| r.screened).sum(),
        curves: std::mem::take(&mut runs[0].curves),
        points_class: std::mem::take(&mut runs[0].point_classes),
    }
}

#[cfg(test)]
mod tests;
