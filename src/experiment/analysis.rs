//! Validation of the `[analysis]` table: kinds, frequency grids, steady-state settings.

use std::path::Path;

use crate::error::{Error, Result};
use crate::sim::motion::impulse::{ImpulseOptions, Kick};
use crate::sim::settle::steady::SteadyMethod;
use crate::sim::SteadyOptions;

use super::file::grid::RawGrid;
use super::file::raw::{RawAnalysis, RawSteady};
use super::{Analysis, Number, Start};

/// Most grid points a frequency axis may have.
const MAX_GRID_POINTS: usize = 100_000;

/// A frequency grid in Hz, validated.
pub fn grid(path: &Path, key: &str, g: &RawGrid) -> Result<Vec<f64>> {
    let g = match g {
        RawGrid::Range(r) => r,
        RawGrid::List(list) => return listed(path, key, list),
    };
    let bad = |k: &str, v: &dyn std::fmt::Display, msg: &str| Error::invalid(path, format!("{key}.{k}"), v, msg);
    if !(g.start.is_finite() && g.start > 0.0) {
        return Err(bad("start", &g.start, "frequencies must be positive and finite (Hz)"));
    }
    if !(g.stop.is_finite() && g.stop > g.start) {
        return Err(bad("stop", &g.stop, &format!("stop must be greater than start = {}", g.start)));
    }
    let span = g.stop - g.start;
    match (g.points, g.step) {
        (Some(p), None) => {
            if p < 2 || p as usize > MAX_GRID_POINTS {
                return Err(bad("points", &p, &format!("give 2 to {MAX_GRID_POINTS} points")));
            }
            let n = p as usize;
            Ok((0..n).map(|i| g.start + span * i as f64 / (n - 1) as f64).collect())
        }
        (None, Some(s)) => {
            if !(s.is_finite() && s > 0.0 && span / s < MAX_GRID_POINTS as f64) {
                return Err(bad(
                    "step",
                    &s,
                    &format!("the step must be positive and give at most {MAX_GRID_POINTS} points"),
                ));
            }
            // 8..60 step 0.1 includes 60 despite rounding; values print as written.
            let n = (span / s + 1e-9).floor() as usize + 1;
            Ok((0..n).map(|i| round_hz(g.start + s * i as f64)).collect())
        }
        _ => Err(Error::invalid(path, key, "(grid)", "give exactly one of points and step")),
    }
}

/// Frequencies listed one by one: 2 to [`MAX_GRID_POINTS`] of them, positive, finite and
/// ascending.
fn listed(path: &Path, key: &str, list: &[f64]) -> Result<Vec<f64>> {
    if list.len() < 2 || list.len() > MAX_GRID_POINTS {
        return Err(Error::invalid(
            path,
            key,
            format!("{} frequenc{}", list.len(), if list.len() == 1 { "y" } else { "ies" }),
            format!("list 2 to {MAX_GRID_POINTS} frequencies (Hz), or give a grid {{ start, stop, points or step }}"),
        ));
    }
    for (i, &f) in list.iter().enumerate() {
        if !(f.is_finite() && f > 0.0) {
            return Err(Error::invalid(path, format!("{key}[{i}]"), f, "frequencies must be positive and finite (Hz)"));
        }
        if i > 0 && f <= list[i - 1] {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                f,
                format!("list the frequencies in ascending order, each once (the one before is {})", list[i - 1]),
            ));
        }
    }
    Ok(list.to_vec())
}

/// Grid values from a step are rounded to 1e-9 Hz.
pub fn round_hz(f: f64) -> f64 {
    (f * 1e9).round() / 1e9
}

fn require_grid(path: &Path, a: &RawAnalysis) -> Result<Vec<f64>> {
    match &a.freq_hz {
        Some(g) => grid(path, "analysis.freq_hz", g),
        None => Err(Error::invalid(
            path,
            "analysis.freq_hz",
            "(missing)",
            format!("analysis kind \"{}\" needs a grid: freq_hz = {{ start, stop, points | step }}", a.kind),
        )),
    }
}

fn positive_int(path: &Path, key: &str, v: Option<i64>, default: usize, max: usize) -> Result<usize> {
    match v {
        None => Ok(default),
        Some(x) if x >= 1 && x as usize <= max => Ok(x as usize),
        Some(x) => Err(Error::invalid(path, key, x, format!("give a whole number from 1 to {max}"))),
    }
}

/// Steady-state settings: the defaults of [`SteadyOptions`] with the file's overrides.
pub(super) fn steady(path: &Path, s: Option<&RawSteady>) -> Result<SteadyOptions> {
    steady_at(path, "analysis.steady.", s)
}

/// [`steady`] with its keys named `{prefix}KEY`.
pub(super) fn steady_at(path: &Path, prefix: &str, s: Option<&RawSteady>) -> Result<SteadyOptions> {
    let mut o = SteadyOptions::default();
    let Some(s) = s else { return Ok(o) };
    if let Some(m) = &s.method {
        o.method = match m.as_str() {
            "orbit" => SteadyMethod::Orbit,
            "transient" => SteadyMethod::Transient,
            "certify" => SteadyMethod::Certify,
            other => {
                return Err(Error::invalid(
                    path,
                    format!("{prefix}method"),
                    format!("\"{other}\""),
                    "\"orbit\" (solve for the periodic orbit, the default), \"transient\" (wait for the transient to die out) or \"certify\" (the transient, then its settled motion certified as a periodic orbit)",
                ))
            }
        };
    }
    if let Some(tol) = s.orbit_tol {
        if !(tol.is_finite() && tol > 0.0 && tol < 1e-3) {
            return Err(Error::invalid(path, format!("{prefix}orbit_tol"), tol, "a relative residual in (0, 1e-3)"));
        }
        o.orbit_tol = tol;
    }
    o.max_newton = positive_int(path, &format!("{prefix}max_newton"), s.max_newton, o.max_newton, 100)?;
    if let Some(tol) = s.tol {
        if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
            return Err(Error::invalid(path, format!("{prefix}tol"), tol, "a relative tolerance in (0, 1)"));
        }
        o.tol = tol;
    }
    o.consecutive = positive_int(path, &format!("{prefix}consecutive"), s.consecutive, o.consecutive, 1000)?;
    o.min_periods = positive_int(path, &format!("{prefix}min_periods"), s.min_periods, o.min_periods, 1_000_000)?;
    o.max_periods = positive_int(path, &format!("{prefix}max_periods"), s.max_periods, o.max_periods, 1_000_000)?;
    o.record_periods =
        positive_int(path, &format!("{prefix}record_periods"), s.record_periods, o.record_periods, 10_000)?;
    if let Some(f) = s.follow {
        o.follow = f;
    }
    match s.torus_attempts {
        None => {}
        Some(x) if (0..=100).contains(&x) => o.torus_attempts = x as usize,
        Some(x) => {
            return Err(Error::invalid(
                path,
                format!("{prefix}torus_attempts"),
                x,
                "give a whole number from 0 (never stop early on a torus) to 100",
            ))
        }
    }
    if o.min_periods > o.max_periods {
        return Err(Error::invalid(
            path,
            format!("{prefix}min_periods"),
            o.min_periods,
            format!("must not exceed max_periods = {}", o.max_periods),
        ));
    }
    Ok(o)
}

/// The default `steady.max_periods` of design files (elsewhere 1500).
pub const DESIGN_MAX_PERIODS: usize = 500;

/// Parses `"@EXPERIMENT.KEY"`.
pub fn export_ref(s: &str) -> Option<super::ExportRef> {
    let rest = s.strip_prefix('@')?;
    let (experiment, key) = rest.split_once('.')?;
    if experiment.is_empty() || key.is_empty() {
        return None;
    }
    Some(super::ExportRef { experiment: experiment.to_string(), key: key.to_string() })
}

fn number(path: &Path, key: &str, v: &toml::Value) -> Result<Number> {
    match v {
        toml::Value::Float(f) if f.is_finite() && *f > 0.0 => Ok(Number::Value(*f)),
        toml::Value::Integer(i) if *i > 0 => Ok(Number::Value(*i as f64)),
        toml::Value::String(s) => export_ref(s).map(Number::Export).ok_or_else(|| {
            Error::invalid(
                path,
                key,
                v,
                "a positive number, or \"@EXPERIMENT.KEY\" for a value another experiment exports",
            )
        }),
        other => Err(Error::invalid(path, key, other, "a positive number, or \"@EXPERIMENT.KEY\"")),
    }
}

/// Validates `[analysis]`; `n` is the number of masses, `case_ids` the cases of the file.
pub fn analysis(
    path: &Path,
    a: RawAnalysis,
    n: usize,
    case_ids: &[String],
    design: Option<crate::design::Spec>,
) -> Result<Analysis> {
    let mut steady = steady(path, a.steady.as_ref())?;
    // Designs sweep thousands of bands by continuation: they follow certified orbits unless
    // the file says otherwise (docs/design.md).
    if design.is_some() && a.steady.as_ref().and_then(|s| s.follow).is_none() {
        steady.follow = true;
    }
    // ... and a point without a stable orbit costs its whole budget, in every layout that
    // has it: designs give up after DESIGN_MAX_PERIODS unless the file says otherwise.
    if design.is_some() && a.steady.as_ref().and_then(|s| s.max_periods).is_none() {
        steady.max_periods = DESIGN_MAX_PERIODS.max(steady.min_periods);
    }
    // Keys of [analysis] that each kind reads; any other key given is an error.
    let given: [(&str, bool); 20] = [
        ("mode", a.mode.is_some()),
        ("freq_hz", a.freq_hz.is_some()),
        ("start", a.start.is_some()),
        ("steady", a.steady.is_some()),
        ("clearances_mm", a.clearances_mm.is_some()),
        ("clearance_points", a.clearance_points.is_some()),
        ("objective_mass", a.objective_mass.is_some()),
        ("objective_case", a.objective_case.is_some()),
        ("frequencies_hz", a.frequencies_hz.is_some()),
        ("labels", a.labels.is_some()),
        ("periods", a.periods.is_some()),
        ("struck_mass", a.struck_mass.is_some()),
        ("initial_velocity_m_s", a.initial_velocity_m_s.is_some()),
        ("impulse_n_s", a.impulse_n_s.is_some()),
        ("duration_s", a.duration_s.is_some()),
        ("sample_rate_hz", a.sample_rate_hz.is_some()),
        ("spectrum_hz", a.spectrum_hz.is_some()),
        ("decay_levels", a.decay_levels.is_some()),
        ("ground_motions", a.ground_motions.is_some()),
        ("storey_height_m", a.storey_height_m.is_some()),
    ];
    // The table of kinds first: a kind without its line there is unknown.
    let Some(spec) = super::kind::kind_spec(&a.kind) else {
        return Err(Error::invalid(
            path,
            "analysis.kind",
            format!("\"{}\"", a.kind),
            format!("allowed kinds: {}", super::kind::kind_names()),
        ));
    };
    if let Some((key, _)) = given.iter().find(|(k, present)| *present && !spec.reads.contains(k)) {
        return Err(Error::invalid(
            path,
            format!("analysis.{key}"),
            "(given)",
            format!("not used by analysis kind \"{}\", which reads: {}", a.kind, spec.reads.join(", ")),
        ));
    }
    match a.kind.as_str() {
        "modal" => Ok(Analysis::Modal),
        "linear_frf" => Ok(Analysis::LinearFrf { freq_hz: require_grid(path, &a)? }),
        "sweep" => sweep(path, &a, steady),
        "clearance_study" => clearance_study(path, &a, n, case_ids, steady),
        "waveform" => waveform(path, &a, steady),
        "impulse" => impulse(path, &a, n),
        "design" => match design {
            Some(spec) => Ok(Analysis::Design { spec: Box::new(spec), steady }),
            None => Err(Error::invalid(path, "design", "(missing)", "analysis kind \"design\" needs a [design] table")),
        },
        "sdof_periodic" => sdof_periodic(path, &a, n, steady),
        "time_history" => time_history(path, &a, n),
        other => Err(Error::invalid(
            path,
            "analysis.kind",
            format!("\"{other}\""),
            format!("allowed kinds: {}", super::kind::kind_names()),
        )),
    }
}

/// `kind = "sweep"`: the grid and its start.
fn sweep(path: &Path, a: &RawAnalysis, steady: SteadyOptions) -> Result<Analysis> {
    let start = match a.start.as_deref() {
        None | Some("rest") => Start::Rest,
        Some("continuation") => Start::Continuation,
        Some(other) => {
            return Err(Error::invalid(
                path,
                "analysis.start",
                format!("\"{other}\""),
                "allowed: \"rest\", \"continuation\"",
            ));
        }
    };
    Ok(Analysis::Sweep { freq_hz: require_grid(path, a)?, start, steady })
}

/// `kind = "clearance_study"`: the grid, the clearances, the mass and the case compared.
fn clearance_study(
    path: &Path,
    a: &RawAnalysis,
    n: usize,
    case_ids: &[String],
    steady: SteadyOptions,
) -> Result<Analysis> {
    let clearances_mm = clearance_list(path, a.clearances_mm.as_deref())?;
    let points = positive_int(path, "analysis.clearance_points", a.clearance_points, 12, 200)?;
    let objective_mass = match a.objective_mass {
        Some(m) if m >= 1 && m as usize <= n => m as usize - 1,
        Some(m) => {
            return Err(Error::invalid(path, "analysis.objective_mass", m, format!("masses are numbered 1 to {n}")))
        }
        None => {
            return Err(Error::invalid(
                path,
                "analysis.objective_mass",
                "(missing)",
                "name the mass whose peak compliance is compared (1-based)",
            ))
        }
    };
    let objective_case = match &a.objective_case {
        Some(c) if case_ids.contains(c) => c.clone(),
        Some(c) => {
            return Err(Error::invalid(
                path,
                "analysis.objective_case",
                format!("\"{c}\""),
                format!("no such case; the cases are {case_ids:?}"),
            ))
        }
        None => {
            return Err(Error::invalid(
                path,
                "analysis.objective_case",
                "(missing)",
                "name the case whose peak decides the best clearance",
            ))
        }
    };
    Ok(Analysis::ClearanceStudy {
        freq_hz: require_grid(path, a)?,
        clearances_mm,
        points,
        objective_mass,
        objective_case,
        steady,
    })
}

/// `kind = "waveform"`: the frequencies, their labels and the periods drawn.
fn waveform(path: &Path, a: &RawAnalysis, steady: SteadyOptions) -> Result<Analysis> {
    let Some(list) = &a.frequencies_hz else {
        return Err(Error::invalid(path, "analysis.frequencies_hz", "(missing)", "list the forcing frequencies (Hz)"));
    };
    let frequencies = list
        .iter()
        .enumerate()
        .map(|(i, v)| number(path, &format!("analysis.frequencies_hz[{i}]"), v))
        .collect::<Result<Vec<_>>>()?;
    let labels = match &a.labels {
        Some(l) if l.len() == frequencies.len() => l.clone(),
        Some(l) => {
            return Err(Error::invalid(
                path,
                "analysis.labels",
                format!("{} labels", l.len()),
                format!("give one label per frequency ({})", frequencies.len()),
            ));
        }
        None => (1..=frequencies.len()).map(|i| i.to_string()).collect(),
    };
    let periods = positive_int(path, "analysis.periods", a.periods, 2, 100)?;
    Ok(Analysis::Waveform { frequencies, labels, periods, steady })
}

/// `kind = "sdof_periodic"`: the mode, its band and the candidate clearances.
fn sdof_periodic(path: &Path, a: &RawAnalysis, n: usize, steady: SteadyOptions) -> Result<Analysis> {
    let mode = match a.mode {
        Some(m) if m >= 1 && m as usize <= n => m as usize - 1,
        Some(m) => return Err(Error::invalid(path, "analysis.mode", m, format!("modes are numbered 1 to {n}"))),
        None => return Err(Error::invalid(path, "analysis.mode", "(missing)", format!("name the mode (1 to {n})"))),
    };
    let clearances_mm = clearance_list(path, a.clearances_mm.as_deref())?;
    Ok(Analysis::SdofPeriodic { mode, freq_hz: require_grid(path, a)?, clearances_mm, steady })
}

/// The range of the struck mass's initial speed, m/s (given, or an impulse shared by the
/// mass and the beds resting on it): from 1 um/s (a motion of nanometres) to 100 m/s (far
/// beyond any hammer blow on a bench structure). Outside it the decay's amplitudes, and so
/// its axes, span no physical range.
pub const KICK_SPEED_M_S: (f64, f64) = (1e-6, 100.0);

/// Refuses a kick whose initial speed of the struck mass lies outside [`KICK_SPEED_M_S`]:
/// `moving` is the mass that shares it (the struck mass and the beds resting on it, kg).
pub fn kick_speed_fits(path: &Path, kick: Kick, moving: f64) -> Result<()> {
    let (lo, hi) = KICK_SPEED_M_S;
    let (key, value, speed) = match kick {
        Kick::Velocity(v) => ("analysis.initial_velocity_m_s", v, v),
        Kick::Impulse(i) => ("analysis.impulse_n_s", i, i / moving),
    };
    if (lo..=hi).contains(&speed) {
        return Ok(());
    }
    let speed_words = match kick {
        Kick::Velocity(_) => String::new(),
        Kick::Impulse(_) => format!(
            "it gives the struck mass and the beds resting on it ({} kg) {} m/s; ",
            crate::number::fmt_num(moving),
            crate::number::fmt_num(speed)
        ),
    };
    Err(Error::invalid(
        path,
        key,
        crate::number::fmt_num(value),
        format!("{speed_words}the struck mass's initial speed must lie in [{lo:e}, {hi}] m/s"),
    ))
}

/// Validates an impulse analysis.
pub(super) fn impulse(path: &Path, a: &RawAnalysis, n: usize) -> Result<Analysis> {
    let key = |k: &str| format!("analysis.{k}");
    let mass = match a.struck_mass {
        Some(m) => super::fields::mass_index(path, &key("struck_mass"), m, n)?,
        None => {
            return Err(Error::invalid(
                path,
                key("struck_mass"),
                "(missing)",
                format!("name the struck mass (1 to {n})"),
            ))
        }
    };
    let positive = |k: &str, v: f64, what: &str| -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::invalid(path, key(k), v, format!("{what} must be positive and finite")))
        }
    };
    let kick = match (a.initial_velocity_m_s, a.impulse_n_s) {
        (Some(v), None) => Kick::Velocity(positive("initial_velocity_m_s", v, "the initial velocity (m/s)")?),
        (None, Some(i)) => Kick::Impulse(positive("impulse_n_s", i, "the impulse (N s)")?),
        _ => {
            return Err(Error::invalid(
                path,
                key("initial_velocity_m_s"),
                "(missing or both)",
                "give exactly one of initial_velocity_m_s and impulse_n_s",
            ))
        }
    };
    let duration = positive("duration_s", a.duration_s.unwrap_or(1.0), "the duration (s)")?;
    let rate = positive("sample_rate_hz", a.sample_rate_hz.unwrap_or(10_000.0), "the sample rate (Hz)")?;
    if duration * rate > 2e6 {
        return Err(Error::invalid(
            path,
            key("sample_rate_hz"),
            rate,
            format!("duration_s x sample_rate_hz = {:.0} samples; at most 2e6", duration * rate),
        ));
    }
    let spectrum_hz = match &a.spectrum_hz {
        Some(g) => grid(path, "analysis.spectrum_hz", g)?,
        None => (1..=800).map(|i| round_hz(0.1 * i as f64)).collect(),
    };
    if let Some(f) = spectrum_hz.iter().find(|f| **f > 0.5 * rate) {
        return Err(Error::invalid(
            path,
            "analysis.spectrum_hz.stop",
            f,
            format!("the spectrum ends at the Nyquist frequency, sample_rate_hz / 2 = {}", 0.5 * rate),
        ));
    }
    let levels = a.decay_levels.clone().unwrap_or_else(|| vec![0.5, 0.1, 0.01]);
    for (i, l) in levels.iter().enumerate() {
        if !(*l > 0.0 && *l < 1.0) {
            return Err(Error::invalid(
                path,
                format!("analysis.decay_levels[{i}]"),
                l,
                "a fraction of the first peak in (0, 1)",
            ));
        }
    }
    Ok(Analysis::Impulse { options: ImpulseOptions { mass, kick, duration, dt: 1.0 / rate }, spectrum_hz, levels })
}

/// The most clearances a clearance study or an SDOF analysis lists (each is a sweep).
pub const MAX_CLEARANCES: usize = 100;

/// A list of positive clearances in mm, each once, at most [`MAX_CLEARANCES`].
fn clearance_list(path: &Path, list: Option<&[f64]>) -> Result<Option<Vec<f64>>> {
    let Some(list) = list else { return Ok(None) };
    for (i, c) in list.iter().enumerate() {
        if !(c.is_finite() && *c > 0.0) {
            return Err(Error::invalid(
                path,
                format!("analysis.clearances_mm[{i}]"),
                c,
                "clearances must be positive and finite (mm)",
            ));
        }
    }
    if list.is_empty() {
        return Err(Error::invalid(path, "analysis.clearances_mm", "[]", "give at least one clearance"));
    }
    super::fields::distinct(path, "analysis.clearances_mm", list, MAX_CLEARANCES, "clearances")?;
    Ok(Some(list.to_vec()))
}

/// Validates a time history: its records (read and scaled) and the storeys' heights.
fn time_history(path: &Path, a: &RawAnalysis, n: usize) -> Result<Analysis> {
    let Some(raw) = &a.ground_motions else {
        return Err(Error::invalid(
            path,
            "analysis.ground_motions",
            "(missing)",
            "analysis kind \"time_history\" needs its records: ground_motions = [{ file = \"...\", peak_g = ... }]",
        ));
    };
    let records = super::ground::records(path, "analysis.ground_motions", raw)?;
    let storey_heights_m = super::ground::heights(path, "analysis.storey_height_m", a.storey_height_m.as_ref(), n)?;
    Ok(Analysis::TimeHistory { records, storey_heights_m })
}
