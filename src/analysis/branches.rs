//! Branches of periodic orbits of the full structure with any number of beds, continued in
//! frequency by pseudo-arclength through folds, with the stability of every point: what a
//! continuation sweep draws beside its points (docs/periodic.md, "Continuation").

use std::f64::consts::PI;

use crate::experiment::CurveId;
use crate::figure::{Dash, Marker, Series};
use crate::sim::orbits::continuation::{continue_branch, BranchEnd, ContinuationOptions, Parameter, Special};
use crate::sim::orbits::periodic::NewtonOptions;
use crate::sim::{Dynamics, Steady, System};
use crate::table::Table;

/// Most times a branch is moved to a new section when an event reaches the old one.
const MAX_SECTIONS: usize = 6;

/// A continued branch of orbits, as compliances.
#[derive(Debug, Clone, Default)]
pub struct OrbitCurve {
    /// Which branch, e.g. "single:orbits-up".
    pub id: CurveId,
    /// Legend label.
    pub label: String,
    /// Forcing frequency of each point, Hz.
    pub freq_hz: Vec<f64>,
    /// Per point, per mass, m/N.
    pub compliance: Vec<Vec<f64>>,
    /// Per point: the orbit is stable.
    pub stable: Vec<bool>,
    /// Largest Floquet multiplier modulus per point.
    pub radius: Vec<f64>,
    /// Folds, period doublings and grazings on the branch.
    pub special: Vec<Special>,
    /// How the branch ended, in words.
    pub end: String,
}

/// Continues the orbit of the steady state `seed` (found at `seed_hz`) upward (`up`) or
/// downward over `range` (Hz).
pub fn continue_orbit(
    id: CurveId,
    label: &str,
    sys: &System,
    seed_hz: f64,
    seed: &Steady,
    up: bool,
    range: (f64, f64),
) -> OrbitCurve {
    let mut out = OrbitCurve { id, label: label.into(), ..OrbitCurve::default() };
    // Decomposed once; each frequency adds only its forced response.
    let base = Dynamics::unforced(sys);
    let family = |f: f64| base.as_ref().map_err(Clone::clone).and_then(|b| b.at_omega(2.0 * PI * f));
    let Some((mut strobe, mut u)) = family(seed_hz).ok().and_then(|d| seed.section(&d)) else {
        out.end = "no seed: the point did not end on a certified orbit".into();
        return out;
    };
    let opts = ContinuationOptions {
        p_min: range.0,
        p_max: range.1,
        p_scale: 1.0,
        ds: 0.02,
        ds_min: 1e-6,
        ds_max: 0.05,
        max_points: 600,
        newton: NewtonOptions { tol: 1e-10, ..NewtonOptions::default() },
        parameter: Parameter::FrequencyHz,
    };
    let (mut p0, mut dir) = (seed_hz, up);
    let mut ends = Vec::new();
    for section in 0..MAX_SECTIONS {
        let branch = match continue_branch(&family, strobe.clone(), p0, &u, dir, &opts) {
            Ok(b) => b,
            Err(e) => {
                ends.push(format!("no start at {p0:.4} Hz: {e}"));
                break;
            }
        };
        for bp in branch.points.iter().skip(usize::from(section > 0)) {
            let Some(amp) = family(bp.p).ok().and_then(|d| strobe.amplitudes(&d, &bp.orbit.u)) else { continue };
            out.freq_hz.push(bp.p);
            out.compliance.push(amp.iter().map(|a| a / sys.drive()).collect());
            out.stable.push(bp.orbit.stable);
            out.radius.push(bp.orbit.spectral_radius());
        }
        out.special.extend(branch.special.iter().copied());
        let last = branch.points.last().filter(|_| branch.points.len() > 1);
        match (&branch.end, last) {
            (BranchEnd::Failed(why), Some(last)) => {
                ends.push(format!("at {:.4} Hz: {why}; moved to a new section", last.p));
                let Some(next) =
                    family(last.p).ok().and_then(|d| strobe.resection(&d, &last.orbit.u, &last.orbit.events))
                else {
                    break;
                };
                (strobe, u) = next;
                p0 = last.p;
                dir = last.dp_ds > 0.0;
            }
            (BranchEnd::Failed(why), None) => {
                ends.push(format!("ended at {p0:.4} Hz: {why}"));
                break;
            }
            (BranchEnd::Range, _) => {
                ends.push("reached the end of the band".into());
                break;
            }
            (BranchEnd::Budget, _) => {
                ends.push("point budget used up".into());
                break;
            }
        }
    }
    out.end = ends.join("; ");
    out
}

/// The branches in one long table, and their special points in another.
pub fn tables(branches: &[OrbitCurve], n: usize) -> Vec<Table> {
    let rows: Vec<(&OrbitCurve, usize)> =
        branches.iter().flat_map(|b| (0..b.freq_hz.len()).map(move |i| (b, i))).collect();
    let mut t = Table::new(
        "branches",
        "Periodic orbits continued in frequency by pseudo-arclength (branch points in the order continued): compliance of each mass (m/N), stability, largest Floquet multiplier modulus",
    )
    .str("branch", rows.iter().map(|(b, _)| b.id.to_string()).collect())
    .f64("freq_hz", rows.iter().map(|(b, i)| b.freq_hz[*i]).collect());
    for r in 0..n {
        t = t.f64(format!("c{}", r + 1), rows.iter().map(|(b, i)| b.compliance[*i][r]).collect());
    }
    t = t
        .i64("stable", rows.iter().map(|(b, i)| b.stable[*i] as i64).collect())
        .f64("max_multiplier", rows.iter().map(|(b, i)| b.radius[*i]).collect());
    let specials: Vec<(&OrbitCurve, &Special)> =
        branches.iter().flat_map(|b| b.special.iter().map(move |s| (b, s))).collect();
    let s = Table::new(
        "branch_special_points",
        "Folds, turns at a graze (non-smooth: between two branch points, the outer one given) and period doublings on each branch, Hz; and how each branch ended",
    )
    .str("branch", specials.iter().map(|(b, _)| b.id.to_string()).chain(branches.iter().map(|b| b.id.to_string())).collect())
    .str("kind", specials.iter().map(|(_, s)| s.name().to_string()).chain(branches.iter().map(|_| "end".to_string())).collect())
    .f64("freq_hz", specials.iter().map(|(_, s)| s.p()).chain(branches.iter().map(|_| f64::NAN)).collect())
    .str("note", specials.iter().map(|_| String::new()).chain(branches.iter().map(|b| b.end.clone())).collect());
    vec![t, s]
}

/// The series of a branch for one mass: stable runs solid, unstable runs dashed, special
/// points as filled markers at the nearest branch point. `labelled` puts its names in the
/// legend.
pub fn series(b: &OrbitCurve, mass: usize, color: usize, labelled: bool) -> Vec<Series> {
    let mut out = Vec::new();
    let mut named = [false; 2];
    let mut i = 0;
    while i < b.freq_hz.len() {
        let stable = b.stable[i];
        let mut j = i;
        while j + 1 < b.freq_hz.len() && b.stable[j + 1] == stable {
            j += 1;
        }
        // Runs share their end points so that the line has no gaps.
        let end = (j + 1).min(b.freq_hz.len() - 1);
        let label = if labelled && !named[stable as usize] {
            named[stable as usize] = true;
            format!("{} ({})", b.label, if stable { "stable" } else { "unstable" })
        } else {
            String::new()
        };
        let x = b.freq_hz[i..=end].to_vec();
        let y = b.compliance[i..=end].iter().map(|c| c[mass]).collect();
        let s = Series::line(label, x, y, color);
        out.push(if stable { s } else { s.dashed(Dash::Dashed) });
        i = j + 1;
    }
    let nearest =
        |p: f64| (0..b.freq_hz.len()).min_by(|&a, &c| (b.freq_hz[a] - p).abs().total_cmp(&(b.freq_hz[c] - p).abs()));
    let mut marks = (Vec::new(), Vec::new());
    for s in &b.special {
        if let Some(k) = nearest(s.p()) {
            marks.0.push(b.freq_hz[k]);
            marks.1.push(b.compliance[k][mass]);
        }
    }
    if !marks.0.is_empty() {
        let label =
            if labelled { format!("{}: folds, turns at a graze, period doublings", b.label) } else { String::new() };
        out.push(Series::points(label, marks.0, marks.1, color, Marker::Square).filled());
    }
    out
}
