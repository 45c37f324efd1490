//! How good a finite-element structure's reduction is (docs/fe-models.md): its natural
//! frequencies against the full model's, and its damped compliance at every point, for a
//! force at the driven point, against the full model's (a sparse direct solve at each
//! frequency, damped in its lowest modes as the reduced model is in its own) over the
//! frequencies the analysis simulates. The largest difference, relative to the full
//! compliance's peak at that point, is checked against the tolerance of
//! `[structure.finite_element]`.

use crate::checks::{compare_scalar, CheckOutcome, Source, Subject};
use crate::experiment::{Analysis, Experiment};
use crate::figure::{Figure, Marker, Panel, Series};
use crate::model::fe::FeStructure;
use crate::model::lanczos::{lowest, Eigen, Failure, Want};
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
    /// Why the full model's modes are missing, when they are (its frequency table is then
    /// empty and its compliance undamped): said, never an empty table in silence.
    pub warning: Option<String>,
}

/// The bands compared, each named, its frequencies in Hz ascending: a design's bands, else the
/// frequencies the analysis simulates (or its linear grid) as one band; at most
/// [`MAX_FREQUENCIES`] in all (picked evenly in each band).
fn bands(exp: &Experiment) -> Vec<(String, Vec<f64>)> {
    let design = exp.analysis.design().map(|(spec, _)| spec);
    let mut bands: Vec<(String, Vec<f64>)> = match &exp.analysis {
        _ if design.is_some() => {
            design.iter().flat_map(|s| &s.bands).map(|b| (b.name.clone(), b.freq_hz.clone())).collect()
        }
        Analysis::LinearFrf { freq_hz } => vec![("the analysis' grid".into(), freq_hz.clone())],
        a => {
            let f: Vec<f64> = a.simulated_frequencies().into_iter().flat_map(|(_, v)| v).collect();
            vec![("the analysis' frequencies".into(), f)]
        }
    };
    bands.retain(|(_, f)| !f.is_empty());
    let most = (MAX_FREQUENCIES / bands.len().max(1)).max(2);
    for (_, f) in &mut bands {
        f.sort_by(f64::total_cmp);
        f.dedup();
        if f.len() > most {
            let step = (f.len() - 1) as f64 / (most - 1) as f64;
            *f = (0..most).map(|i| f[((i as f64 * step).round() as usize).min(f.len() - 1)]).collect();
        }
    }
    bands
}

/// Runs the comparison for `exp`'s structure, reduced from `fe`, over the bands its analysis
/// simulates, for a force at its driven point, both models with its damping.
pub fn run(exp: &Experiment, fe: &FeStructure) -> Outcome {
    compare(fe, exp.excitation.mass, &bands(exp), Some(&exp.structure))
}

/// The comparison of `fe`'s reduced model with its full model: natural frequencies, and the
/// compliance at every point for a unit force at point `force` (0-based) over each band of
/// `bands` (named, Hz ascending; none: the frequencies only), each difference relative to the
/// full compliance's largest magnitude at that point in its band, the largest checked against
/// `fe`'s tolerance. With `damped`
/// (the reduced structure, its damping) both models are damped: the reduced one by its own
/// damping matrix, the full one in its lowest modes (as many as the reduced model has) with
/// the ratios the structure's damping gives them (modal ratios by mode number; Rayleigh
/// `alpha / (2 omega) + beta omega / 2` at the full model's own frequency); undamped without.
/// (Undamped, a frequency a hair from a resonance compares two near-infinities: a shift of the
/// resonance by 6e-5 of its frequency reads as a 55 % difference 0.01 Hz from it.)
pub fn compare(fe: &FeStructure, force: usize, bands: &[(String, Vec<f64>)], damped: Option<&Structure>) -> Outcome {
    let mut freqs: Vec<f64> = bands.iter().flat_map(|(_, f)| f.iter().copied()).collect();
    freqs.sort_by(f64::total_cmp);
    freqs.dedup();
    let full = &fe.full;
    let reduced_modes = symmetric_modes(&fe.reduced.mass, &fe.reduced.stiffness);
    let (full_modes, warning) = full_modes(fe, reduced_modes.omegas.len());
    let full_hz: Vec<f64> = full_modes
        .as_ref()
        .map(|e| e.values.iter().map(|l| l.sqrt() / (2.0 * std::f64::consts::PI)).collect())
        .unwrap_or_default();
    let red_hz: Vec<f64> = reduced_modes.omegas.iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect();
    let freq_table = frequency_table(&full_hz, &red_hz);
    let mut tables = vec![freq_table];
    if freqs.is_empty() {
        return Outcome { tables, check: None, figure: None, warning };
    }
    let omegas: Vec<f64> = freqs.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
    // The full model's compliance in the reduced model's coordinates (points whose
    // direction points down are measured upward there).
    let zetas = full_zetas(damped, &full_hz);
    let damping = match (damped, &full_modes) {
        (Some(s), Some(modes)) => Some(Damped { full_modes: modes, zetas: &zetas, reduced: &s.damping }),
        _ => None,
    };
    let state = if damping.is_some() { "Damped" } else { "Undamped" };
    let computed = compliance_pairs(&full.mass, &full.stiffness, &fe.reduced, force, &omegas, damping.as_ref());
    // By frequency (a frequency on a natural frequency of either model is skipped).
    let at: Vec<Option<CompliancePair>> = computed
        .into_iter()
        .map(|p| {
            p.map(|mut p| {
                for (v, pt) in p.full.iter_mut().zip(&fe.points) {
                    *v *= pt.sign * fe.points[force].sign;
                }
                p
            })
        })
        .collect();
    let index = |f: f64| freqs.binary_search_by(|x| x.total_cmp(&f)).ok();
    let (mut band_c, mut f, mut point, mut full_c, mut red_c, mut rel) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // The worst difference: (value, band, point); and each frequency's differences relative
    // to the peaks of the first band holding it (for the figure).
    let mut worst = (0.0_f64, 0, 0);
    let mut shown: Vec<Option<Vec<f64>>> = vec![None; freqs.len()];
    for (bi, (name, band)) in bands.iter().enumerate() {
        let (ks, only): (Vec<usize>, Vec<CompliancePair>) =
            band.iter().filter_map(|&x| index(x)).filter_map(|k| at[k].clone().map(|p| (k, p))).unzip();
        let peak = peaks(&only);
        for (i, d) in largest_difference(&only).into_iter().enumerate() {
            if d > worst.0 {
                worst = (d, bi, i);
            }
        }
        for (k, p) in ks.iter().zip(&only) {
            let mut row = Vec::with_capacity(fe.points.len());
            for (i, pt) in fe.points.iter().enumerate() {
                let r = if peak[i] > 0.0 { (p.reduced[i] - p.full[i]).norm() / peak[i] } else { 0.0 };
                band_c.push(name.clone());
                f.push(p.omega / (2.0 * std::f64::consts::PI));
                point.push(pt.name.clone());
                full_c.push(p.full[i].norm());
                red_c.push(p.reduced[i].norm());
                rel.push(r);
                row.push(r);
            }
            if shown[*k].is_none() {
                shown[*k] = Some(row);
            }
        }
    }
    let pairs: Vec<CompliancePair> = at.iter().flatten().cloned().collect();
    let shown: Vec<Vec<f64>> = shown.into_iter().flatten().collect();
    let figure = figure(fe, &pairs, &shown, &freqs, bands, state);
    tables.push(
        Table::new(
            "reduction_compliance",
            format!(
                "{state} compliance magnitude (m/N) at each point for a unit force at \"{}\", in each band: the full finite-element model's (sparse direct solve{}) and the reduced model's, and the magnitude of their difference relative to the full compliance's largest magnitude at that point in that band",
                fe.points[force].name,
                if damping.is_some() { format!(", damped in its lowest {} modes with the reduced model's ratios", full_hz.len()) } else { String::new() }
            ),
        )
        .str("band", band_c)
        .f64("freq_hz", f)
        .str("point", point)
        .f64("full_m_per_n", full_c)
        .f64("reduced_m_per_n", red_c)
        .f64("rel_diff", rel),
    );
    let (worst, band, at_point) = worst;
    let subject = Subject::new(
        "reduction",
        format!(
            "the reduced model's compliance against the full finite-element model's ({} degrees of freedom) at {} frequencies {:.4}-{:.4} Hz in {} band{}: the largest difference relative to the peak in its band, at \"{}\" in {}",
            full.mass.n(),
            pairs.len(),
            freqs[0],
            freqs[freqs.len() - 1],
            bands.len(),
            if bands.len() == 1 { "" } else { "s" },
            fe.points[at_point].name,
            bands[band].0
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
    Outcome { tables, check: Some(check), figure: Some(figure), warning }
}

/// The natural frequencies of both models side by side, and their relative difference.
fn frequency_table(full_hz: &[f64], red_hz: &[f64]) -> Table {
    let count = red_hz.len().min(full_hz.len());
    Table::new(
        "reduction_frequencies",
        "Natural frequencies of the full finite-element model (shift-invert Lanczos, certified by inertia counts) and of the reduced model (Hz), and their relative difference",
    )
    .i64("mode", (1..=count as i64).collect())
    .f64("full_hz", full_hz[..count].to_vec())
    .f64("reduced_hz", red_hz[..count].to_vec())
    .f64("rel_diff", (0..count).map(|i| (red_hz[i] - full_hz[i]) / full_hz[i]).collect())
}

/// The full model's lowest modes, as many as the reduced model has (shift-invert Lanczos,
/// certified by inertia counts), or the warning saying why they could not be computed.
fn full_modes(fe: &FeStructure, count: usize) -> (Option<Eigen>, Option<String>) {
    let full = &fe.full;
    let mut factor = Skyline::pattern(&full.stiffness, Some(&full.mass), rcm(&full.stiffness));
    let found = match factor.factor(&full.stiffness, None) {
        Ok(0) => lowest(&full.stiffness, &full.mass, &factor, Want::Count(count)).map_err(|e| match e {
            Failure::Singular(s) => format!("a shift fell on an eigenvalue at row {}", s.row + 1),
            Failure::Missed { found, counted } => {
                format!("shift-invert Lanczos found {found} modes where the inertia counts {counted}")
            }
        }),
        Ok(n) => Err(format!("the stiffness matrix has {n} negative pivots (it is not positive definite)")),
        Err(e) => Err(format!("the stiffness matrix is singular at row {}", e.row + 1)),
    };
    let warning = found.as_ref().err().map(|why| {
        format!(
            "{}: the full model's natural frequencies could not be computed ({why}): the reduction's frequency table is empty and its compliance comparison undamped",
            full.files
        )
    });
    (found.ok(), warning)
}

/// The modal damping ratio of each of the full model's modes (at `full_hz`) under the reduced
/// model's damping: its ratios (the last for modes beyond them), or Rayleigh's at each
/// frequency; none undamped.
fn full_zetas(damped: Option<&Structure>, full_hz: &[f64]) -> Vec<f64> {
    match damped.map(|s| &s.damping_spec) {
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
    }
}

/// Two panels: the magnitude of each point's compliance, full model (lines) and reduced
/// (circles), and their difference relative to the full compliance's peak at that point.
/// The figure of the comparison; the curves are broken between bands (no line drawn across
/// frequencies that were not computed).
fn figure(
    fe: &FeStructure,
    pairs: &[CompliancePair],
    rel: &[Vec<f64>],
    freqs: &[f64],
    bands: &[(String, Vec<f64>)],
    state: &str,
) -> Figure {
    let hz: Vec<f64> = pairs.iter().map(|p| p.omega / (2.0 * std::f64::consts::PI)).collect();
    // Each curve's x and y with a gap (y NaN) between two frequencies no band spans (to the
    // rounding of `omega / 2 pi`).
    let spanned = |a: f64, b: f64| {
        let slack = 1e-9 * b.abs();
        bands
            .iter()
            .any(|(_, f)| f.first().is_some_and(|lo| *lo <= a + slack) && f.last().is_some_and(|hi| b <= *hi + slack))
    };
    let gapped = |y: Vec<f64>| -> (Vec<f64>, Vec<f64>) {
        let (mut xs, mut ys) = (Vec::with_capacity(hz.len() + bands.len()), Vec::with_capacity(y.len() + bands.len()));
        for (k, (&x, v)) in hz.iter().zip(y).enumerate() {
            if k > 0 && !spanned(hz[k - 1], x) {
                xs.push(0.5 * (hz[k - 1] + x));
                ys.push(f64::NAN);
            }
            xs.push(x);
            ys.push(v);
        }
        (xs, ys)
    };
    let range = (freqs[0], freqs[freqs.len() - 1].max(freqs[0] * (1.0 + 1e-9)));
    let mut magnitude = Panel::new(
        "Compliance at each point: full model (lines) and reduced (circles)",
        "frequency (Hz)",
        format!("|x / F| (m/N), {}", state.to_lowercase()),
        range,
    )
    .log_y();
    let mut difference = Panel::new(
        format!("Difference relative to each point's peak in its band (the check allows {})", fe.tolerance),
        "frequency (Hz)",
        "|reduced - full| / peak",
        range,
    )
    .log_y();
    for (i, pt) in fe.points.iter().enumerate() {
        let (x, full) = gapped(pairs.iter().map(|p| p.full[i].norm()).collect());
        magnitude.series.push(Series::line(format!("{} (full)", pt.name), x, full, i));
        // The reduced model as circles over the full model's line (a dashed line lies hidden
        // under it where the two agree to the check's tolerance): about 30 a curve.
        let (x, red) = gapped(pairs.iter().map(|p| p.reduced[i].norm()).collect());
        let every = (x.len() / 30).max(1);
        let (x, red): (Vec<f64>, Vec<f64>) = x.iter().zip(&red).step_by(every).map(|(a, b)| (*a, *b)).unzip();
        magnitude.series.push(Series::points(format!("{} (reduced)", pt.name), x, red, i, Marker::Circle).sized(3));
        let (x, r) = gapped(rel.iter().map(|r| r[i]).collect());
        difference.series.push(Series::line(pt.name.clone(), x, r, i));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::reduction::{craig_bampton_sparse, Keep};
    use crate::model::sparse::SymSparse;
    use nalgebra::{DMatrix, DVector};
    use std::sync::Arc;

    fn sparse(a: &DMatrix<f64>) -> SymSparse {
        let n = a.nrows();
        let e = (0..n).flat_map(|i| (0..=i).map(move |j| (i, j))).filter(|&(i, j)| a[(i, j)] != 0.0);
        SymSparse::from_entries(n, e.map(|(i, j)| (i, j, a[(i, j)])).collect::<Vec<_>>(), true).unwrap()
    }

    /// A chain of 14 masses reduced at its ends with two interior modes (a reduction that is
    /// good at the first mode, worse higher up).
    fn chain() -> (FeStructure, Structure) {
        let n = 14;
        let m = DMatrix::from_diagonal(&DVector::from_fn(n, |i, _| 0.5 + 0.1 * (i % 3) as f64));
        let k =
            crate::model::structure::chain_stiffness(&(0..n).map(|i| 2e4 + 1e3 * (i % 4) as f64).collect::<Vec<_>>());
        let b = [0, 11, 12, 13];
        let reduced = craig_bampton_sparse(&sparse(&m), &sparse(&k), &b, Keep::Count(2), None).unwrap();
        let point = |row: usize| crate::model::fe::Point {
            name: format!("row {row}"),
            row,
            label: None,
            vertical: true,
            horizontal: false,
            sign: 1.0,
        };
        let structure = Structure::from_mass_matrix(
            reduced.mass.clone(),
            reduced.stiffness.clone(),
            Damping::ModalRatios(vec![0.02; reduced.mass.nrows()]),
        );
        let full =
            crate::model::fe::FullModel { stiffness: sparse(&k), mass: sparse(&m), labels: None, files: "test".into() };
        let fe = FeStructure {
            full: Arc::new(full),
            points: b.iter().map(|&r| point(r)).collect(),
            reduced,
            up: "z".into(),
            tolerance: 1e-3,
            mass_along_up: m.sum(),
            mass_stated: None,
        };
        (fe, structure)
    }

    /// Each band's differences are relative to its own peaks: two bands checked together give
    /// the worse of the two checked alone, and more than the same frequencies as one band
    /// (where the first mode's larger peak dilutes the higher band's difference).
    /// A full model whose modes cannot be computed (its stiffness made singular after the
    /// reduction) is said, with the cause, not left as an empty table.
    #[test]
    fn a_full_model_without_modes_is_said() {
        let (mut fe, structure) = chain();
        let (good, _) = chain();
        assert!(compare(&good, 0, &[], Some(&structure)).warning.is_none());
        let n = fe.full.stiffness.n();
        let loose = DMatrix::from_fn(n, n, |i, j| if i == 5 || j == 5 { 0.0 } else { 1.0 });
        let k = fe.full.stiffness.to_dense().component_mul(&loose);
        let full = crate::model::fe::FullModel { stiffness: sparse(&k), ..(*fe.full).clone() };
        fe.full = Arc::new(full);
        let out = compare(&fe, 0, &[], Some(&structure));
        let said = out.warning.expect("a warning");
        assert!(said.contains("test: the full model's natural frequencies could not be computed"), "{said}");
        assert!(said.contains("singular at row 6") || said.contains("negative pivots"), "{said}");
        assert_eq!(out.tables[0].height(), 0);
    }

    #[test]
    fn each_band_is_measured_against_its_own_peak() {
        let (fe, s) = chain();
        let omegas = symmetric_modes(&s.mass_matrix(), &s.stiffness).omegas;
        let around =
            |w: f64| (0..21).map(|i| w / (2.0 * std::f64::consts::PI) * (0.9 + 0.01 * i as f64)).collect::<Vec<_>>();
        let (low, high) = (around(omegas[0]), around(omegas[3]));
        let worst = |bands: &[(String, Vec<f64>)]| compare(&fe, 0, bands, Some(&s)).check.map(|c| c.computed).unwrap();
        let (a, b) = (worst(&[("low".into(), low.clone())]), worst(&[("high".into(), high.clone())]));
        let both = worst(&[("low".into(), low.clone()), ("high".into(), high.clone())]);
        let merged = worst(&[("all".into(), low.iter().chain(&high).copied().collect())]);
        assert_eq!(both, a.max(b));
        assert!(b > a && merged < b, "low {a}, high {b}, merged {merged}");
    }
}
