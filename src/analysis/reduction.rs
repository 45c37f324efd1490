//! How good a finite-element structure's reduction is (docs/fe-models.md): its natural
//! frequencies against the full model's, and its damped compliance at every point, for a
//! force at the driven point, against the full model's (a sparse direct solve at each
//! frequency, damped in its lowest modes as the reduced model is in its own) over the
//! frequencies the analysis simulates. The largest difference, relative to the full
//! compliance's peak at that point, is checked against the tolerance of
//! `[structure.finite_element]`.

use crate::checks::{compare_scalar, CheckOutcome, Source, Subject};
use crate::experiment::{Analysis, Experiment};
use crate::figure::{Dash, Figure, Panel, Series};
use crate::model::fe::FeStructure;
use crate::model::lanczos::{lowest, Want};
use crate::model::modes::symmetric_modes;
use crate::model::reduction::{compliance_pairs, largest_difference, peaks, CompliancePair, Damped};
use crate::model::sparse::{rcm, Skyline};
use crate::model::{Damping, Structure};
use crate::number::Tolerance;
use crate::table::Table;

/// Frequencies compared at most (picked evenly from the analysis' own): each costs a
/// factorisation of the full model.
pub const MAX_FREQUENCIES: usize = 200;

/// What the comparison gives the report.
pub struct Outcome {
    /// `reduction_frequencies` and, when the analysis simulates frequencies,
    /// `reduction_compliance`.
    pub tables: Vec<Table>,
    /// The check of the largest difference (none without frequencies).
    pub check: Option<CheckOutcome>,
    /// The compliance of both models and their difference at each point.
    pub figure: Option<Figure>,
}

/// The frequencies compared, Hz: the analysis' own, ascending, at most [`MAX_FREQUENCIES`].
fn frequencies(exp: &Experiment) -> Vec<f64> {
    let mut f: Vec<f64> = exp.analysis.simulated_frequencies().into_iter().flat_map(|(_, v)| v).collect();
    if let Analysis::LinearFrf { freq_hz } = &exp.analysis {
        f.extend(freq_hz.iter().copied());
    }
    f.sort_by(f64::total_cmp);
    f.dedup();
    if f.len() > MAX_FREQUENCIES {
        let step = (f.len() - 1) as f64 / (MAX_FREQUENCIES - 1) as f64;
        f = (0..MAX_FREQUENCIES).map(|i| f[((i as f64 * step).round() as usize).min(f.len() - 1)]).collect();
    }
    f
}

/// Runs the comparison for `exp`'s structure, reduced from `fe`, over the frequencies its
/// analysis simulates, for a force at its driven point.
pub fn run(exp: &Experiment, fe: &FeStructure) -> Outcome {
    compare(fe, exp.excitation.mass, &frequencies(exp), Some(&exp.structure))
}

/// The comparison of `fe`'s reduced model with its full model: natural frequencies, and the
/// compliance at every point for a unit force at point `force` (0-based) over `freqs` (Hz,
/// ascending; none: the frequencies only), checked against `fe`'s tolerance. With `damped`
/// (the reduced structure, its damping) both models are damped: the reduced one by its own
/// damping matrix, the full one in its lowest modes (as many as the reduced model has) with
/// the ratios the structure's damping gives them (modal ratios by mode number; Rayleigh
/// `alpha / (2 omega) + beta omega / 2` at the full model's own frequency); undamped without.
/// (Undamped, a frequency a hair from a resonance compares two near-infinities: a shift of the
/// resonance by 6e-5 of its frequency reads as a 55 % difference 0.01 Hz from it.)
pub fn compare(fe: &FeStructure, force: usize, freqs: &[f64], damped: Option<&Structure>) -> Outcome {
    let full = &fe.full;
    let reduced_modes = symmetric_modes(&fe.reduced.mass, &fe.reduced.stiffness);
    // The full model's lowest modes, as many as the reduced model has.
    let mut factor = Skyline::pattern(&full.stiffness, Some(&full.mass), rcm(&full.stiffness));
    let full_modes = match factor.factor(&full.stiffness, None) {
        Ok(0) => lowest(&full.stiffness, &full.mass, &factor, Want::Count(reduced_modes.omegas.len())).ok(),
        _ => None,
    };
    let full_hz: Vec<f64> = full_modes
        .as_ref()
        .map(|e| e.values.iter().map(|l| l.sqrt() / (2.0 * std::f64::consts::PI)).collect())
        .unwrap_or_default();
    let red_hz: Vec<f64> = reduced_modes.omegas.iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect();
    let count = red_hz.len().min(full_hz.len());
    let freq_table = Table::new(
        "reduction_frequencies",
        "Natural frequencies of the full finite-element model (shift-invert Lanczos, certified by inertia counts) and of the reduced model (Hz), and their relative difference",
    )
    .i64("mode", (1..=count as i64).collect())
    .f64("full_hz", full_hz[..count].to_vec())
    .f64("reduced_hz", red_hz[..count].to_vec())
    .f64("rel_diff", (0..count).map(|i| (red_hz[i] - full_hz[i]) / full_hz[i]).collect());
    let mut tables = vec![freq_table];
    if freqs.is_empty() {
        return Outcome { tables, check: None, figure: None };
    }
    let omegas: Vec<f64> = freqs.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    // The full model's compliance in the reduced model's coordinates (points whose
    // direction points down are measured upward there).
    let zetas: Vec<f64> = match damped.map(|s| &s.damping_spec) {
        Some(Damping::ModalRatios(z)) => {
            (0..full_hz.len()).map(|k| z.get(k).or(z.last()).copied().unwrap_or(0.0)).collect()
        }
        Some(Damping::Rayleigh { alpha, beta }) => full_hz
            .iter()
            .map(|f| {
                let w = 2.0 * std::f64::consts::PI * f;
                alpha / (2.0 * w) + beta * w / 2.0
            })
            .collect(),
        None => Vec::new(),
    };
    let damping = match (damped, &full_modes) {
        (Some(s), Some(modes)) => Some(Damped { full_modes: modes, zetas: &zetas, reduced: &s.damping }),
        _ => None,
    };
    let state = if damping.is_some() { "Damped" } else { "Undamped" };
    let pairs: Vec<CompliancePair> =
        compliance_pairs(&full.mass, &full.stiffness, &fe.reduced, force, &omegas, damping.as_ref())
            .into_iter()
            .flatten()
            .map(|mut p| {
                for (v, pt) in p.full.iter_mut().zip(&fe.points) {
                    *v *= pt.sign * fe.points[force].sign;
                }
                p
            })
            .collect();
    let diffs = largest_difference(&pairs);
    let (mut f, mut point, mut full_c, mut red_c, mut rel) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let peak = peaks(&pairs);
    for p in &pairs {
        for (i, pt) in fe.points.iter().enumerate() {
            let peak = peak[i];
            f.push(p.omega / (2.0 * std::f64::consts::PI));
            point.push(pt.name.clone());
            full_c.push(p.full[i].norm());
            red_c.push(p.reduced[i].norm());
            rel.push(if peak > 0.0 { (p.reduced[i] - p.full[i]).norm() / peak } else { 0.0 });
        }
    }
    let figure = figure(fe, &pairs, freqs, state);
    tables.push(
        Table::new(
            "reduction_compliance",
            format!(
                "{state} compliance magnitude (m/N) at each point for a unit force at \"{}\": the full finite-element model's (sparse direct solve{}) and the reduced model's, and the magnitude of their difference relative to the full compliance's largest magnitude at that point over these frequencies",
                fe.points[force].name,
                if damping.is_some() { format!(", damped in its lowest {} modes with the reduced model's ratios", full_hz.len()) } else { String::new() }
            ),
        )
        .f64("freq_hz", f)
        .str("point", point)
        .f64("full_m_per_n", full_c)
        .f64("reduced_m_per_n", red_c)
        .f64("rel_diff", rel),
    );
    let (worst, at) =
        diffs.iter().enumerate().fold((0.0_f64, 0), |(w, a), (i, &d)| if d > w { (d, i) } else { (w, a) });
    let subject = Subject::new(
        "reduction",
        format!(
            "the reduced model's compliance against the full finite-element model's ({} degrees of freedom) at {} frequencies {:.4}-{:.4} Hz: the largest difference relative to the peak, at \"{}\"",
            full.mass.n(),
            pairs.len(),
            freqs[0],
            freqs[freqs.len() - 1],
            fe.points[at].name
        ),
        "",
        "the full model (sparse direct solve)",
        Source::Internal,
    );
    let mut check = compare_scalar(subject, worst, 0.0, Tolerance { rel: 0.0, abs: fe.tolerance }, None);
    if pairs.len() < freqs.len() {
        check.detail =
            Some(format!("{} frequencies fell on a natural frequency and were skipped", freqs.len() - pairs.len()));
    }
    Outcome { tables, check: Some(check), figure: Some(figure) }
}

/// Two panels: the magnitude of each point's compliance, full model (solid) and reduced
/// (dashed), and their difference relative to the full compliance's peak at that point.
fn figure(fe: &FeStructure, pairs: &[CompliancePair], freqs: &[f64], state: &str) -> Figure {
    let hz: Vec<f64> = pairs.iter().map(|p| p.omega / (2.0 * std::f64::consts::PI)).collect();
    let range = (freqs[0], freqs[freqs.len() - 1].max(freqs[0] * (1.0 + 1e-9)));
    let mut magnitude = Panel::new(
        "Compliance at each point: full model (solid) and reduced (dashed)",
        "frequency (Hz)",
        format!("|x / F| (m/N), {}", state.to_lowercase()),
        range,
    )
    .log_y();
    let mut difference = Panel::new(
        format!("Difference relative to each point's peak (the check allows {})", fe.tolerance),
        "frequency (Hz)",
        "|reduced - full| / peak",
        range,
    )
    .log_y();
    let peak = peaks(pairs);
    for (i, pt) in fe.points.iter().enumerate() {
        let full: Vec<f64> = pairs.iter().map(|p| p.full[i].norm()).collect();
        let red: Vec<f64> = pairs.iter().map(|p| p.reduced[i].norm()).collect();
        let peak = peak[i];
        magnitude.series.push(Series::line(format!("{} (full)", pt.name), hz.clone(), full, i));
        magnitude.series.push(Series::line("", hz.clone(), red, i).dashed(Dash::Dashed));
        let rel =
            pairs.iter().map(|p| if peak > 0.0 { (p.reduced[i] - p.full[i]).norm() / peak } else { 0.0 }).collect();
        difference.series.push(Series::line(pt.name.clone(), hz.clone(), rel, i));
    }
    Figure {
        id: "reduction".into(),
        title: format!(
            "The reduced model ({} coordinates) against the full finite-element model ({} degrees of freedom)",
            fe.reduced.mass.nrows(),
            fe.full.mass.n()
        ),
        caption: format!(
            "{state} compliance for a unit force at the driven point, the full model by a sparse direct solve at each frequency{}; the check reads the largest difference.",
            if state == "Damped" { " (damped in its lowest modes as the reduced model is)" } else { "" }
        ),
        panels: vec![magnitude, difference],
    }
}
