//! References drawn over computed compliance curves: the reference's points as markers, and
//! the relative difference at each of them for a residual panel with the tolerance.

use crate::checks::reference::ReferenceStore;
use crate::experiment::{CheckKind, CurveId, Experiment};

use super::curves::Curve;

/// One reference of one computed curve.
#[derive(Debug, Clone)]
pub struct Overlay {
    /// The computed curve it belongs to.
    pub curve: CurveId,
    /// E.g. "independent solver" or "digitised Fig. 8".
    pub source: String,
    /// Per mass: the reference's (frequency, compliance) points (empty for masses it lacks).
    pub points: Vec<Vec<(f64, f64)>>,
    /// Per mass: (frequency, |computed - reference| / reference) where both are settled and
    /// period-1.
    pub residual: Vec<Vec<(f64, f64)>>,
    /// The tolerances of the check (relative), drawn as lines.
    pub tolerances: Vec<f64>,
}

/// Linear interpolation of a computed curve's mass at `f` between settled points.
fn at(c: &Curve, mass: usize, f: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> =
        (0..c.freq_hz.len()).filter(|&i| c.regular(i)).map(|i| (c.freq_hz[i], c.compliance[i][mass])).collect();
    let k = pts.partition_point(|p| p.0 < f);
    if k < pts.len() && (pts[k].0 - f).abs() < 1e-9 {
        return Some(pts[k].1);
    }
    if k == 0 || k == pts.len() {
        return None;
    }
    let (a, b) = (pts[k - 1], pts[k]);
    Some(a.1 + (b.1 - a.1) * (f - a.0) / (b.0 - a.0))
}

/// The overlays of an experiment's curve and tube checks, for the curves computed.
pub fn overlays(exp: &Experiment, refs: &ReferenceStore, curves: &[Curve]) -> Vec<Overlay> {
    let n = exp.structure.dof();
    let mut out = Vec::new();
    for spec in &exp.checks {
        match &spec.kind {
            CheckKind::Curve { curve, columns, rel_tol_all, .. } => {
                let (Some(r), Some(c)) = (refs.curve(&spec.reference_file), curves.iter().find(|c| &c.id == curve))
                else {
                    continue;
                };
                let freq = r.column("freq_hz").unwrap_or(&[]);
                let ok = |k: usize| {
                    r.column("converged").is_none_or(|v| v[k] == 1.0) && r.column("period").is_none_or(|v| v[k] == 1.0)
                };
                let mut o = Overlay {
                    curve: curve.clone(),
                    source: "independent solver".into(),
                    points: vec![Vec::new(); n],
                    residual: vec![Vec::new(); n],
                    tolerances: vec![spec.tolerance.rel, *rel_tol_all],
                };
                for m in 0..n {
                    let Some(col) = r.column(&format!("{columns}c{}", m + 1)) else { continue };
                    for (k, &f) in freq.iter().enumerate() {
                        o.points[m].push((f, col[k]));
                        if let (true, Some(i)) = (ok(k), c.index_of(f)) {
                            if c.regular(i) {
                                o.residual[m].push((f, (c.compliance[i][m] - col[k]).abs() / col[k].abs()));
                            }
                        }
                    }
                }
                out.push(o);
            }
            CheckKind::Tube { case, mass, curve, .. } => {
                let (Some(file), Some(c)) =
                    (refs.digitised(&spec.reference_file), curves.iter().find(|c| c.id == CurveId::whole(case)))
                else {
                    continue;
                };
                let Some(d) = file.get(curve) else { continue };
                let mut o = Overlay {
                    curve: CurveId::whole(case),
                    source: format!("digitised {}", file.meta.figure),
                    points: vec![Vec::new(); n],
                    residual: vec![Vec::new(); n],
                    tolerances: vec![spec.tolerance.rel].into_iter().filter(|t| *t > 0.0).collect(),
                };
                for (&f, &y) in d.x.iter().zip(&d.y) {
                    o.points[*mass].push((f, y));
                    if let Some(v) = at(c, *mass, f) {
                        o.residual[*mass].push((f, (v - y).abs() / y.abs()));
                    }
                }
                out.push(o);
            }
            _ => {}
        }
    }
    out
}
