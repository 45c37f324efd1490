//! Where the time and the memory go as a structure grows (docs/simulator.md, "Cost per degree
//! of freedom", the scaling table): the size benchmarks' chains of n = 3, 8, 16, 32, 64, 128
//! masses (benches/common/size_family.rs) and the plate CalculiX meshed, reduced at the plate
//! design's five points with 15, 41 and 75 fixed-interface modes (20, 46 and 80 coordinates;
//! the design's stored answer, three containers, examples/plate/modes.toml). Per structure,
//! on one thread:
//!
//! - the decomposition of every configuration (`Dynamics::unforced`) and the memory it keeps;
//! - the forced responses of every configuration at one frequency (`Dynamics::at_omega`);
//! - on one certified orbit (the band's point with the most events a period): one return of
//!   the period map with its linearised flow and without it, an event (the return without the
//!   flow over its events), a Newton step (the LU solve of `J - I`) and the multipliers (the
//!   eigenvalues of the Jacobian);
//! - a point of the band from rest and followed (the band's mean; measuring every mass of a
//!   chain and the points of a reduced model, as a sweep does), and the memory a followed
//!   point allocates beyond what it keeps (the peak over the band) and the transfers between
//!   configurations it leaves formed.
//!
//! Every time is the median of repeated runs (at least three, at least half a second in all);
//! memory is counted by this program's allocator (bytes asked for, not pages). It then fits
//! each part's growth `t ~ n^p` on the chains of 16 masses and more, and on the plate's three
//! reductions, by least squares in logarithms. Prints a Markdown table.
//!
//! `cargo run --release --example scaling` (about ten minutes; `-- 64` stops at 64 masses)

use std::alloc::{GlobalAlloc, Layout, System as Heap};
use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

use nalgebra::DMatrix;
use shotdamp::sim::motion::observe::Observe;
use shotdamp::sim::orbits::periodic::{multipliers, Section};
use shotdamp::sim::settle::sweep::{self, Direction};
use shotdamp::sim::{Dynamics, SteadyOptions, System};

include!("../benches/common/size_family.rs");
include!("../benches/common/plate_answer.rs");

/// Counts the bytes live and their peak since the last [`reset_peak`].
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(l.size(), Relaxed) + l.size();
        PEAK.fetch_max(live, Relaxed);
        unsafe { Heap.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Relaxed);
        unsafe { Heap.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        if new >= l.size() {
            let live = LIVE.fetch_add(new - l.size(), Relaxed) + new - l.size();
            PEAK.fetch_max(live, Relaxed);
        } else {
            LIVE.fetch_sub(l.size() - new, Relaxed);
        }
        unsafe { Heap.realloc(p, l, new) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

fn live() -> usize {
    LIVE.load(Relaxed)
}

fn reset_peak() -> usize {
    let now = live();
    PEAK.store(now, Relaxed);
    now
}

/// The median time of `f`, s, over at least three runs and half a second.
fn median<T>(mut f: impl FnMut() -> T) -> f64 {
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 3 || (start.elapsed().as_secs_f64() < 0.5 && times.len() < 1000) {
        let t = Instant::now();
        std::hint::black_box(f());
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// One structure's measured parts (times in s, memory in bytes).
#[derive(Default)]
struct Row {
    name: String,
    size: usize,
    configurations: usize,
    highest_hz: f64,
    decompose: f64,
    decomposition_bytes: usize,
    forced: f64,
    orbit: String,
    events: usize,
    dim: usize,
    with_flow: f64,
    without_flow: f64,
    newton_step: f64,
    multipliers: f64,
    from_rest: f64,
    followed: f64,
    followed_peak_bytes: usize,
    transfer_bytes: usize,
    closed: bool,
    irregular: f64,
    irregular_what: String,
}

fn measure(name: String, size: usize, sys: &System, freqs: &[f64]) -> Row {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    one.install(|| {
        let mut row = Row { name, size, configurations: 1 << sys.dampers.len(), ..Row::default() };
        let before = live();
        let base = Dynamics::unforced(sys);
        row.decomposition_bytes = live().saturating_sub(before);
        let Ok(d0) = &base else {
            eprintln!("{}: not decomposed", row.name);
            return row;
        };
        row.highest_hz = 1.0 / d0.min_period;
        row.decompose = median(|| Dynamics::unforced(sys));
        let omega = 2.0 * PI * freqs[freqs.len() / 2];
        row.forced = median(|| d0.at_omega(omega));

        let opts = SteadyOptions { observe: observed(sys), ..SteadyOptions::default() };
        let follow = SteadyOptions { follow: true, ..opts };
        // The first run forms the transfers between configurations (kept in `base`).
        let before = live();
        drop(sweep::continued_on(&base, freqs, Direction::Up, &follow, &|| {}));
        row.transfer_bytes = live().saturating_sub(before);
        let kept = reset_peak();
        let points = sweep::continued_on(&base, freqs, Direction::Up, &follow, &|| {});
        row.followed_peak_bytes = PEAK.load(Relaxed).saturating_sub(kept);
        row.followed =
            median(|| sweep::continued_on(&base, freqs, Direction::Up, &follow, &|| {})) / freqs.len() as f64;
        row.from_rest = median(|| sweep::from_rest_on(&base, freqs, &opts, &|| {})) / freqs.len() as f64;

        // The certified orbit with the most events a period.
        let best = points
            .iter()
            .filter_map(|p| {
                let st = p.result.as_ref().ok()?;
                let d = d0.at_omega(2.0 * PI * p.freq_hz).ok()?;
                let (strobe, u) = st.section(&d)?;
                let ret = strobe.map(&d, &u).ok()?;
                Some((ret.events.len() as f64 / strobe.periods as f64, p.freq_hz, d, strobe, u))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((per_period, freq, d, strobe, u)) = best else {
            row.orbit = "none certified".into();
            return row;
        };
        let ret = strobe.map(&d, &u).expect("the orbit maps");
        row.events = ret.events.len();
        row.orbit = format!("{freq:.2} Hz, {per_period:.0} events a period");
        row.dim = u.len();
        row.with_flow = median(|| strobe.map(&d, &u));
        row.without_flow = median(|| strobe.image(&d, &u));
        let (j, _) = ret.jacobian.clone().expect("a Jacobian");
        let g = &ret.image - &u;
        row.newton_step = median(|| (&j - DMatrix::identity(j.nrows(), j.ncols())).lu().solve(&g));
        // As the solver takes them: in closed form where the beds ride without an event.
        row.closed = strobe.closed_multipliers(&d, &ret).is_some();
        row.multipliers = median(|| strobe.closed_multipliers(&d, &ret).map_or_else(|| multipliers(&j), Ok));
        row
    })
}

/// What a sweep measures: every mass of a chain, the points of a reduced model (its modal
/// coordinates are no displacement of a point).
fn observed(sys: &System) -> Observe {
    match sys.structure.points {
        Some(p) if p < sys.dof() => Observe::only(0..p),
        _ => Observe::ALL,
    }
}

/// A point from rest whose motion does not settle (the plate's answer above 35.5 Hz): its
/// time and what it was.
fn irregular(row: &mut Row, sys: &System, freq: f64) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool of one thread");
    one.install(|| {
        let base = Dynamics::unforced(sys);
        let opts = SteadyOptions { observe: observed(sys), ..SteadyOptions::default() };
        let point = sweep::from_rest_on(&base, &[freq], &opts, &|| {});
        row.irregular_what = match &point[0].result {
            Ok(st) => format!("{:?}, {} periods", st.motion, st.transient_periods + st.recorded_periods),
            Err(e) => format!("{e}"),
        };
        row.irregular = median(|| sweep::from_rest_on(&base, &[freq], &opts, &|| {}));
    })
}

/// The plate design's stored answer on the plate reduced with `modes` fixed-interface modes.
fn plate(modes: usize) -> (System, usize) {
    let sys = answer_system(&plate_answer(&format!("modes = {modes}")));
    let n = sys.dof();
    (sys, n)
}

/// The least-squares slope of `ln y` against `ln x`.
fn exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points.iter().filter(|p| p.1 > 0.0).map(|&(x, y)| (x.ln(), y.ln())).collect();
    if pts.len() < 2 {
        return None;
    }
    let m = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / m, pts.iter().map(|p| p.1).sum::<f64>() / m);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    Some(sxy / sxx)
}

fn ms(t: f64) -> String {
    if t == 0.0 {
        "-".into()
    } else if t < 1e-3 {
        format!("{:.1} us", t * 1e6)
    } else if t < 1.0 {
        format!("{:.2} ms", t * 1e3)
    } else {
        format!("{t:.2} s")
    }
}

fn mb(b: usize) -> String {
    format!("{:.2} MB", b as f64 / 1e6)
}

fn main() {
    let largest: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(128);
    let mut rows = Vec::new();
    for n in [3, 8, 16, 32, 64, 128].into_iter().filter(|&n| n <= largest) {
        let sys = refined(n);
        let freqs = band(&sys);
        eprintln!("chain n = {n} ...");
        rows.push(measure(format!("chain {n}"), n, &sys, &freqs));
    }
    let plate_band: Vec<f64> = (0..11).map(|i| 33.0 + 0.25 * i as f64).collect();
    for modes in [15, 41, 75] {
        let (sys, n) = plate(modes);
        eprintln!("plate, {n} coordinates ...");
        let mut row = measure(format!("plate {n}"), n, &sys, &plate_band);
        irregular(&mut row, &sys, 36.0);
        rows.push(row);
    }
    println!(
        "| structure | configurations | highest mode | decomposition, all | kept | forced responses, all | orbit measured | \
         section coordinates | return with flow | without | an event | Newton step | multipliers | \
         a point from rest | a followed point | a followed band's peak extra memory | transfers kept |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let event = if r.events > 0 { ms(r.without_flow / r.events as f64) } else { "-".into() };
        println!(
            "| {} | {} | {:.0} Hz | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.name,
            r.configurations,
            r.highest_hz,
            ms(r.decompose),
            mb(r.decomposition_bytes),
            ms(r.forced),
            r.orbit,
            r.dim,
            ms(r.with_flow),
            ms(r.without_flow),
            event,
            ms(r.newton_step),
            if r.closed { format!("{} (closed form)", ms(r.multipliers)) } else { ms(r.multipliers) },
            ms(r.from_rest),
            ms(r.followed),
            mb(r.followed_peak_bytes),
            mb(r.transfer_bytes),
        );
    }
    type Part = (&'static str, fn(&Row) -> f64);
    let parts: [Part; 12] = [
        ("decomposition", |r| r.decompose),
        ("decomposition's memory", |r| r.decomposition_bytes as f64),
        ("forced responses", |r| r.forced),
        ("return with flow", |r| r.with_flow),
        ("return without flow", |r| r.without_flow),
        ("an event", |r| if r.events > 0 { r.without_flow / r.events as f64 } else { 0.0 }),
        ("Newton step", |r| r.newton_step),
        ("multipliers", |r| r.multipliers),
        ("a point from rest", |r| r.from_rest),
        ("a followed point", |r| r.followed),
        ("followed band's peak memory", |r| r.followed_peak_bytes as f64),
        ("a point that does not settle", |r| r.irregular),
    ];
    println!();
    for r in rows.iter().filter(|r| r.irregular > 0.0) {
        println!(
            "{}: a point from rest at 36 Hz that does not settle ({}): {}",
            r.name,
            r.irregular_what,
            ms(r.irregular)
        );
    }
    println!();
    println!("| part | exponent, chains n >= 16 | exponent, plate 20-80 |");
    println!("|---|---|---|");
    for (name, get) in parts {
        let chains: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.name.starts_with("chain") && r.size >= 16)
            .map(|r| (r.size as f64, get(r)))
            .collect();
        let plates: Vec<(f64, f64)> =
            rows.iter().filter(|r| r.name.starts_with("plate")).map(|r| (r.size as f64, get(r))).collect();
        let f = |e: Option<f64>| e.map_or("-".to_string(), |p| format!("{p:.2}"));
        println!("| {name} | {} | {} |", f(exponent(&chains)), f(exponent(&plates)));
    }
}
