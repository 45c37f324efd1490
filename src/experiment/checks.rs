//! Validation of `[[checks]]`: kinds, the cases and masses they name, tolerances, and the
//! reference files and ids, which must exist.

use std::path::Path;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::reference::digitised::DigitisedFile;
use crate::reference::files::{Files, Loaded};

use super::fields::mass_index;
use super::file::raw::RawCheck;
use super::{Analysis, CheckKind, CheckSpec, CurveId, Start};
use crate::number::Tolerance;
use crate::sim::settle::sweep::Direction;

/// The largest relative tolerance a check may state.
pub const MAX_REL_TOL: f64 = 10.0;

/// The largest tolerance in pixels of a digitised figure (wider than any figure).
pub const MAX_PX: f64 = 1000.0;

/// The case a check names.
fn case_ref(path: &Path, key: String, v: &Option<String>, case_ids: &[String]) -> Result<String> {
    match v {
        Some(c) if case_ids.contains(c) => Ok(c.clone()),
        Some(c) => {
            Err(Error::invalid(path, key, format!("\"{c}\""), format!("no such case; the cases are {case_ids:?}")))
        }
        None => Err(Error::invalid(path, key, "(missing)", "this check needs the case it compares")),
    }
}

/// The check kinds of files (`[[checks]] kind`), for messages.
const CHECK_KINDS: &[&str] = &[
    "natural_frequency",
    "mode_shape",
    "paper_parameters",
    "curve",
    "tube",
    "peak",
    "peak_ratio",
    "ratio_order",
    "motion_types",
    "impulse_history",
    "decay_time",
    "decay_ratio",
    "orbit_vs_simulation",
    "sdof_vs_simulation",
    "design_conclusion",
];

/// Where a check is read: its file, its index, and what it may name.
struct At<'a> {
    path: &'a Path,
    i: usize,
    n: usize,
    case_ids: &'a [String],
    analysis: &'a Analysis,
}

impl At<'_> {
    fn key(&self, k: &str) -> String {
        format!("checks[{}].{k}", self.i)
    }

    fn case(&self, field: &str, v: &Option<String>) -> Result<String> {
        case_ref(self.path, self.key(field), v, self.case_ids)
    }

    fn mode(&self, m: Option<i64>) -> Result<usize> {
        let n = self.n;
        let Some(m) = m else {
            return Err(Error::invalid(
                self.path,
                self.key("mode"),
                "(missing)",
                format!("this check needs mode = 1..{n}"),
            ));
        };
        if m < 1 || m as usize > n {
            return Err(Error::invalid(self.path, self.key("mode"), m, format!("modes are numbered 1 to {n}")));
        }
        Ok(m as usize - 1)
    }

    /// An input error unless `ok`: check `kind` needs an analysis that `has` (what it reads).
    fn only(&self, ok: bool, kind: &str, has: &str) -> Result<()> {
        if ok {
            return Ok(());
        }
        Err(Error::invalid(
            self.path,
            self.key("kind"),
            format!("\"{kind}\""),
            format!("only {has} (this one is \"{}\")", self.analysis.kind()),
        ))
    }
}

/// Validates one check; reference files and ids must exist.
pub fn check(
    path: &Path,
    i: usize,
    c: RawCheck,
    n: usize,
    case_ids: &[String],
    analysis: &Analysis,
    files: &Files,
) -> Result<CheckSpec> {
    let at = At { path, i, n, case_ids, analysis };
    if let Some(id) = &c.id {
        if !super::fields::is_identifier(id) {
            return Err(Error::invalid(path, at.key("id"), format!("\"{id}\""), "letters, digits, '_' and '-' only"));
        }
    }
    tolerances(&at, &c)?;
    let (kind, loaded) = kind_of(&at, &c, files)?;
    // Tolerances in pixels, or none at all (a set of motion types).
    let own_tolerance = matches!(kind, CheckKind::Tube { .. } | CheckKind::Peak { .. } | CheckKind::MotionTypes { .. });
    if c.rel_tol.is_none() && c.abs_tol.is_none() && !own_tolerance {
        return Err(Error::invalid(
            path,
            at.key("rel_tol"),
            "(missing)",
            "a check needs a tolerance: rel_tol and/or abs_tol",
        ));
    }
    let tolerance = Tolerance { rel: c.rel_tol.unwrap_or(0.0), abs: c.abs_tol.unwrap_or(0.0) };
    let (reference_file, reference_id, loaded) = reference_of(&at, &c, &kind, loaded, files)?;
    Ok(CheckSpec {
        kind,
        id: c.id,
        reference_file,
        reference_id,
        tolerance,
        known_deviation: c.known_deviation,
        loaded,
    })
}

/// Tolerances are finite and >= 0, relative ones at most [`MAX_REL_TOL`].
fn tolerances(at: &At, c: &RawCheck) -> Result<()> {
    for (k, v) in [("rel_tol", c.rel_tol), ("abs_tol", c.abs_tol), ("rel_tol_all", c.rel_tol_all)] {
        if let Some(v) = v {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(at.path, at.key(k), v, "a tolerance must be >= 0 and finite"));
            }
        }
    }
    // A relative tolerance above 10 (1000 %) accepts any value of the same sign; the plots
    // draw it on a log axis of residuals, which it would stretch over hundreds of decades.
    for (k, v) in [("rel_tol", c.rel_tol), ("rel_tol_all", c.rel_tol_all)] {
        if let Some(v) = v.filter(|v| *v > MAX_REL_TOL) {
            return Err(Error::invalid(
                at.path,
                at.key(k),
                crate::number::fmt_num(v),
                format!("a relative tolerance lies in [0, {MAX_REL_TOL}] (1000 %); to drop a check, delete it"),
            ));
        }
    }
    Ok(())
}

/// What the check compares, by its kind, and the reference file parsed for it (a digitised
/// file: parsed once, kept for the checks).
fn kind_of(at: &At, c: &RawCheck, files: &Files) -> Result<(CheckKind, Option<Loaded>)> {
    let (path, i, n, analysis) = (at.path, at.i, at.n, at.analysis);
    let kind = match c.kind.as_str() {
        "natural_frequency" => CheckKind::NaturalFrequency { mode: at.mode(c.mode)? },
        "mode_shape" => CheckKind::ModeShape {
            mode: at.mode(c.mode)?,
            elements: match &c.elements {
                Some(list) => list
                    .iter()
                    .enumerate()
                    .map(|(j, &m)| mass_index(path, &format!("checks[{i}].elements[{j}]"), m, n))
                    .collect::<Result<Vec<_>>>()?,
                None => (0..n).collect(),
            },
        },
        "paper_parameters" => CheckKind::PaperParameters,
        "curve" => curve(at, c)?,
        "peak_ratio" | "ratio_order" => claim(path, i, c, n, at.case_ids)?,
        "tube" | "peak" => {
            let (kind, file) = digitised(path, i, c, n, at.case_ids, files)?;
            return Ok((kind, Some(Loaded::Digitised(file))));
        }
        "motion_types" => {
            at.only(matches!(analysis, Analysis::Waveform { .. }), &c.kind, "a waveform analysis reads motion types")?;
            motion_types(at, c)?
        }
        "orbit_vs_simulation" | "sdof_vs_simulation" => {
            let has = "an sdof_periodic analysis has periodic orbits";
            at.only(matches!(analysis, Analysis::SdofPeriodic { .. }), &c.kind, has)?;
            if c.kind == "orbit_vs_simulation" {
                CheckKind::OrbitVsSimulation
            } else {
                CheckKind::SdofVsSimulation
            }
        }
        "impulse_history" | "decay_time" | "decay_ratio" => {
            let levels = match analysis {
                Analysis::Impulse { levels, .. } => &levels[..],
                _ => &[],
            };
            at.only(matches!(analysis, Analysis::Impulse { .. }), &c.kind, "an impulse analysis has decay histories")?;
            impulse_check(path, i, c, n, at.case_ids, levels)?
        }
        "design_conclusion" => {
            let has = "a design analysis has layouts to read the conclusion on";
            at.only(analysis.design().is_some(), &c.kind, has)?;
            CheckKind::DesignConclusion
        }
        other => {
            let allowed = CHECK_KINDS.iter().map(|k| format!("\"{k}\"")).collect::<Vec<_>>().join(", ");
            return Err(Error::invalid(
                path,
                at.key("kind"),
                format!("\"{other}\""),
                format!("allowed kinds: {allowed}"),
            ));
        }
    };
    Ok((kind, None))
}

/// A curve check: the case's curve the analysis computes (a continuation's direction, a
/// clearance study's clearance).
fn curve(at: &At, c: &RawCheck) -> Result<CheckKind> {
    let path = at.path;
    let fraction = c.fraction.unwrap_or(1.0);
    if !(fraction > 0.0 && fraction <= 1.0) {
        return Err(Error::invalid(path, at.key("fraction"), fraction, "a fraction of the points in (0, 1]"));
    }
    let rel = c.rel_tol.unwrap_or(0.0);
    let id = at.case("case", &c.case)?;
    let curve = match (at.analysis, c.direction.as_deref(), c.clearance_mm) {
        (Analysis::Sweep { start: Start::Continuation, .. }, Some("up"), None) => {
            CurveId::continued(&id, Direction::Up)
        }
        (Analysis::Sweep { start: Start::Continuation, .. }, Some("down"), None) => {
            CurveId::continued(&id, Direction::Down)
        }
        (Analysis::Sweep { start: Start::Continuation, .. }, _, _) => {
            return Err(Error::invalid(
                path,
                at.key("direction"),
                c.direction.as_deref().map_or_else(|| "(missing)".to_string(), |d| format!("\"{d}\"")),
                "a continuation sweep has an \"up\" and a \"down\" curve: give direction",
            ));
        }
        (Analysis::ClearanceStudy { clearances_mm: Some(list), .. }, None, Some(mm))
            if list.iter().any(|x| (x - mm).abs() < 1e-12) =>
        {
            CurveId::clearance(&id, mm)
        }
        (Analysis::ClearanceStudy { .. }, _, _) => {
            return Err(Error::invalid(
                path,
                at.key("clearance_mm"),
                c.clearance_mm.map_or_else(|| "(missing)".to_string(), crate::number::fmt_num),
                "name one of the clearances the study scans (analysis.clearances_mm)",
            ));
        }
        (_, None, None) => CurveId::whole(&id),
        _ => {
            return Err(Error::invalid(
                path,
                at.key("direction"),
                "(given)",
                "direction and clearance_mm only apply to continuation sweeps and clearance studies",
            ))
        }
    };
    Ok(CheckKind::Curve {
        curve,
        columns: c.columns.clone().unwrap_or_default(),
        fraction,
        rel_tol_all: c.rel_tol_all.unwrap_or(rel),
    })
}

/// A motion-type check: the types a case's beds show and do not show.
fn motion_types(at: &At, c: &RawCheck) -> Result<CheckKind> {
    let list = |field: &str, v: &Option<Vec<String>>| -> Result<Vec<String>> {
        let v = v.clone().unwrap_or_default();
        for (j, t) in v.iter().enumerate() {
            if !["I", "II", "III", "rests"].contains(&t.as_str()) {
                return Err(Error::invalid(
                    at.path,
                    format!("checks[{}].{field}[{j}]", at.i),
                    format!("\"{t}\""),
                    "allowed: \"I\", \"II\", \"III\", \"rests\"",
                ));
            }
        }
        Ok(v)
    };
    Ok(CheckKind::MotionTypes {
        case: at.case("case", &c.case)?,
        present: list("present", &c.present)?,
        absent: list("absent", &c.absent)?,
    })
}

/// The check's reference: its file and id (which must exist), and the file parsed (a value
/// file is parsed here whether or not the check names a value in it; a digitised one arrives
/// parsed). A check of two computations of one run takes none.
fn reference_of(
    at: &At,
    c: &RawCheck,
    kind: &CheckKind,
    mut loaded: Option<Loaded>,
    files: &Files,
) -> Result<(String, Option<String>, Option<Loaded>)> {
    let path = at.path;
    let reference = match (kind, &c.reference) {
        (CheckKind::OrbitVsSimulation, None) => return Ok((String::new(), None, None)),
        (CheckKind::OrbitVsSimulation, Some(r)) => {
            return Err(Error::invalid(
                path,
                at.key("reference"),
                format!("\"{r}\""),
                "this check compares two computations of the same run: it takes no reference",
            ))
        }
        (_, None) => {
            return Err(Error::invalid(
                path,
                at.key("reference"),
                "(missing)",
                "name the reference: FILE or FILE#ID under reference/",
            ))
        }
        (_, Some(r)) => r.clone(),
    };
    let (file, id) = match reference.split_once('#') {
        Some((f, id)) => (f.to_string(), Some(id.to_string())),
        None => (reference.clone(), None),
    };
    let ref_path = files.dir().join(&file);
    if !ref_path.is_file() {
        return Err(Error::invalid(
            path,
            at.key("reference"),
            format!("\"{reference}\""),
            format!("no such reference file: {}", ref_path.display()),
        ));
    }
    // Checks of values name one (a range: two) in the file: FILE#ID.
    let what = match kind {
        CheckKind::NaturalFrequency { .. } | CheckKind::ModeShape { .. } => Some("the value"),
        CheckKind::PeakRatio { bound: super::Bound::Within { .. }, .. } => Some("the lower bound"),
        CheckKind::PeakRatio { .. } | CheckKind::DecayRatio { .. } | CheckKind::DesignConclusion => Some("the bound"),
        CheckKind::SdofVsSimulation | CheckKind::RatioOrder { .. } | CheckKind::MotionTypes { .. } => Some("the claim"),
        _ => None,
    };
    let mut ids: Vec<&str> = Vec::new();
    if let Some(what) = what {
        let Some(id) = &id else {
            return Err(Error::invalid(
                path,
                at.key("reference"),
                format!("\"{reference}\""),
                format!("name {what}: FILE#ID"),
            ));
        };
        ids.push(id);
        if let CheckKind::PeakRatio { bound: super::Bound::Within { upper_id }, .. } = kind {
            ids.push(upper_id);
        }
    }
    let curve =
        matches!(kind, CheckKind::Curve { .. } | CheckKind::ImpulseHistory { .. } | CheckKind::DecayTime { .. });
    if curve && !file.ends_with(".csv") {
        return Err(Error::invalid(
            path,
            at.key("reference"),
            format!("\"{reference}\""),
            "a curve reference is a CSV file",
        ));
    }
    if !ids.is_empty() || (loaded.is_none() && file.ends_with(".toml")) {
        let values = files.values(&file)?;
        loaded = Some(Loaded::Values(Arc::clone(&values)));
        for id in ids {
            if values.get(id).is_none() {
                return Err(Error::invalid(
                    path,
                    at.key("reference"),
                    format!("\"{reference}\""),
                    format!("{} has no quantity with id \"{id}\"", ref_path.display()),
                ));
            }
        }
    }
    Ok((file, id, loaded))
}

/// The checks of an impulse analysis: `impulse_history`, `decay_time`, `decay_ratio`.
fn impulse_check(
    path: &Path,
    i: usize,
    c: &RawCheck,
    n: usize,
    case_ids: &[String],
    levels: &[f64],
) -> Result<CheckKind> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let case = |field: &str, v: &Option<String>| case_ref(path, key(field), v, case_ids);
    let mass = || match c.mass {
        Some(m) => mass_index(path, &key("mass"), m, n),
        None => Err(Error::invalid(path, key("mass"), "(missing)", format!("name the mass (1 to {n})"))),
    };
    let level = |l: f64| -> Result<f64> {
        if l > 0.0 && l < 1.0 {
            Ok(l)
        } else {
            Err(Error::invalid(path, key("level"), l, "a fraction of the first envelope peak in (0, 1)"))
        }
    };
    Ok(match c.kind.as_str() {
        "impulse_history" => {
            let window = c.window_s.unwrap_or(0.02);
            if !(window.is_finite() && window > 0.0) {
                return Err(Error::invalid(path, key("window_s"), window, "a positive window (s)"));
            }
            CheckKind::ImpulseHistory { case: case("case", &c.case)?, window }
        }
        "decay_time" => CheckKind::DecayTime {
            case: case("case", &c.case)?,
            mass: mass()?,
            levels: match c.level {
                Some(l) => vec![level(l)?],
                None => levels.to_vec(),
            },
        },
        _ => CheckKind::DecayRatio {
            case: case("case", &c.case)?,
            over_case: case("over_case", &c.over_case)?,
            mass: mass()?,
            level: level(c.level.unwrap_or(0.1))?,
        },
    })
}

/// A frequency window `[from, to]` in Hz.
fn window(path: &Path, key: String, v: &Option<Vec<f64>>) -> Result<Option<(f64, f64)>> {
    match v.as_deref() {
        None => Ok(None),
        Some(&[a, b]) if a.is_finite() && b.is_finite() && a < b => Ok(Some((a, b))),
        Some(w) => Err(Error::invalid(path, key, crate::number::fmt_list(w), "give [from, to] in Hz with from < to")),
    }
}

/// The claims about peak ratios: `peak_ratio` and `ratio_order`.
fn claim(path: &Path, i: usize, c: &RawCheck, n: usize, case_ids: &[String]) -> Result<CheckKind> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let mass = match c.mass {
        Some(m) => mass_index(path, &key("mass"), m, n)?,
        None => return Err(Error::invalid(path, key("mass"), "(missing)", format!("name the mass (1 to {n})"))),
    };
    let case = case_ref(path, key("case"), &c.case, case_ids)?;
    let over_case = case_ref(path, key("over_case"), &c.over_case, case_ids)?;
    let win = window(path, key("window_hz"), &c.window_hz)?;
    if c.kind == "ratio_order" {
        if let Some(r) = &c.reading {
            return Err(Error::invalid(
                path,
                key("reading"),
                format!("\"{r}\""),
                "an ordering claim compares peaks: it takes no reading",
            ));
        }
        let (Some(window), Some(than_window)) = (win, window(path, key("than_window_hz"), &c.than_window_hz)?) else {
            return Err(Error::invalid(
                path,
                key("window_hz"),
                "(missing)",
                "an ordering claim compares two windows: give window_hz and than_window_hz",
            ));
        };
        return Ok(CheckKind::RatioOrder { case, over_case, mass, window, than_window });
    }
    let bound = match c.bound.as_deref() {
        None | Some("within") => match c.range_to.clone() {
            Some(upper_id) => super::Bound::Within { upper_id },
            None => {
                return Err(Error::invalid(
                    path,
                    key("range_to"),
                    "(missing)",
                    "a range needs the id of its upper bound (or give bound = \"at_most\" / \"at_least\")",
                ))
            }
        },
        Some("at_most") => super::Bound::AtMost,
        Some("at_least") => super::Bound::AtLeast,
        Some(other) => {
            return Err(Error::invalid(
                path,
                key("bound"),
                format!("\"{other}\""),
                "allowed: \"within\", \"at_most\", \"at_least\"",
            ))
        }
    };
    let reading = match c.reading.as_deref() {
        None | Some("peak_over_peak") => super::Reading::PeakOverPeak,
        Some("at_resonance") => super::Reading::AtResonance,
        Some("band_max") => super::Reading::BandMax,
        Some(other) => {
            return Err(Error::invalid(
                path,
                key("reading"),
                format!("\"{other}\""),
                "allowed: \"peak_over_peak\", \"at_resonance\", \"band_max\"",
            ))
        }
    };
    Ok(CheckKind::PeakRatio { case, over_case, mass, bound, window: win, reading })
}

/// Checks against a digitised curve: `tube` and `peak`. The reference file must hold the
/// curve; its case and mass come from the check or from the curve's mapping.
fn digitised(
    path: &Path,
    i: usize,
    c: &RawCheck,
    n: usize,
    case_ids: &[String],
    files: &Files,
) -> Result<(CheckKind, Arc<DigitisedFile>)> {
    let key = |k: &str| format!("checks[{i}].{k}");
    let Some(reference) = c.reference.as_deref() else {
        return Err(Error::invalid(path, key("reference"), "(missing)", "name the digitised file under reference/"));
    };
    let file = files.digitised(reference).map_err(|e| {
        Error::invalid(
            path,
            key("reference"),
            format!("\"{reference}\""),
            format!("not a readable digitised file: {e}"),
        )
    })?;
    let Some(name) = c.curve.clone() else {
        return Err(Error::invalid(path, key("curve"), "(missing)", "name the digitised curve (its dataset name)"));
    };
    let Some(curve) = file.get(&name) else {
        let names: Vec<&String> = file.curve.iter().map(|c| &c.name).collect();
        return Err(Error::invalid(
            path,
            key("curve"),
            format!("\"{name}\""),
            format!("the file's curves are {names:?}"),
        ));
    };
    let case = case_ref(path, key("case"), &c.case.clone().or(curve.case.clone()), case_ids)?;
    let mass = match c.mass.or(curve.mass) {
        Some(m) => mass_index(path, &key("mass"), m, n)?,
        None => return Err(Error::invalid(path, key("mass"), "(missing)", format!("name the mass (1 to {n})"))),
    };
    // A tube wider than a whole figure says nothing and would stretch the plot's axes.
    let px = |k: &str, v: Option<f64>| -> Result<f64> {
        let v = v.unwrap_or(2.0);
        if v.is_finite() && (0.0..=MAX_PX).contains(&v) {
            Ok(v)
        } else {
            Err(Error::invalid(path, key(k), crate::number::fmt_num(v), format!("a number of pixels in [0, {MAX_PX}]")))
        }
    };
    let (x_px, y_px) = (px("x_tol_px", c.x_tol_px)?, px("y_tol_px", c.y_tol_px)?);
    if c.kind == "tube" {
        return Ok((CheckKind::Tube { case, mass, curve: name, x_px, y_px }, file));
    }
    let Some(window) = window(path, key("window_hz"), &c.window_hz)? else {
        return Err(Error::invalid(
            path,
            key("window_hz"),
            "(missing)",
            "a peak check needs the window of the resonance, [from, to] Hz",
        ));
    };
    Ok((CheckKind::Peak { case, mass, curve: name, window, x_px, y_px }, file))
}

#[cfg(test)]
mod tests;
