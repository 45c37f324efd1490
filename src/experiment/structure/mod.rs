//! Where a structure's matrices come from: the seam every structure source plugs into
//! ([`Source`]), the sources in one list ([`SOURCES`]) and what every structure gets whatever
//! its source (springs to ground, damping, the model's [`Structure`]). A source is one file
//! of this folder: a lumped chain (`chain.rs`), matrices given (`matrix.rs`), a chain fitted
//! to measured modes (`fitted.rs`), a reduced finite-element model (`finite_element.rs`). A
//! new one (a measured modal model, another finite-element format) is a file here and one
//! line in [`SOURCES`] (docs/extending.md, "A structure source").

mod chain;
mod finite_element;
mod fitted;
mod matrix;

use std::path::Path;
use std::sync::Arc;

use nalgebra::DMatrix;

use super::file::raw::RawStructure;
use crate::error::{Error, Result};
use crate::model::fe::FeStructure;
use crate::model::fit::StiffnessFit;
use crate::model::{Damping, Structure};

/// The most coordinates a reduced model may keep, and who needs the limit (for its message).
pub type Limit<'a> = Option<(usize, &'a str)>;

/// One source of a structure's mass and stiffness.
pub trait Source: Sync {
    /// The key of `[structure]` that selects it.
    fn key(&self) -> &'static str;

    /// Whether `s` asks for it (has its key).
    fn given(&self, s: &RawStructure) -> bool;

    /// Its mass and stiffness from `s`, checked: every message names the file, the key, the
    /// value and what is allowed.
    fn build(&self, path: &Path, s: &RawStructure, limit: Limit<'_>) -> Result<Matrices>;
}

/// Every source, in the order messages list them.
pub const SOURCES: [&dyn Source; 4] = [&finite_element::FiniteElement, &chain::Chain, &matrix::Matrix, &fitted::Fitted];

/// What a source gives.
pub struct Matrices {
    /// Lumped masses, kg (a full mass matrix's diagonal stands for them elsewhere).
    pub masses: Vec<f64>,
    /// The full mass matrix, kg, where there is one.
    pub full_mass: Option<DMatrix<f64>>,
    /// The stiffness matrix, N/m (springs to ground not yet added).
    pub stiffness: DMatrix<f64>,
    /// The fit to measured modes, where the stiffness was fitted.
    pub fit: Option<StiffnessFit>,
    /// The finite-element model and how its coordinates follow moving supports, where it was
    /// reduced from one.
    pub fe: Option<(FeStructure, crate::model::base::Supports)>,
}

/// A validated structure with where its numbers come from.
#[derive(Clone)]
pub(super) struct Built {
    pub(super) structure: Structure,
    pub(super) source: Option<String>,
    pub(super) damping_assumption: Option<String>,
    pub(super) fit: Option<StiffnessFit>,
    pub(super) fe: Option<Arc<FeStructure>>,
}

/// What validation built from a `[structure]` table, kept with the table (as validated)
/// and the coordinate limit it was built under: the same table gives the same matrices, so a
/// setup varied in other keys takes them from here, and one varied in its damping alone
/// computes only the damping (docs/extending.md, "One setup, built once").
#[derive(Clone)]
pub struct Kept {
    path: std::path::PathBuf,
    raw: RawStructure,
    limit: Option<usize>,
    built: Built,
}

/// [`structure`], taking what `kept` holds where `s` and `limit` are those it was built from
/// (the damping aside: a new damping is computed on the kept matrices), and what it built,
/// kept.
pub(super) fn structure_kept(path: &Path, s: RawStructure, limit: Limit<'_>, kept: Option<&Kept>) -> Result<Kept> {
    let limit_n = limit.map(|l| l.0);
    let built = match kept.filter(|k| k.path == path && k.limit == limit_n && k.raw.same_matrices(&s)) {
        Some(k) if k.raw.damping == s.damping => k.built.clone(),
        Some(k) => {
            let d = damping(path, &s, k.built.structure.dof())?;
            Built {
                structure: k.built.structure.with_damping(d),
                damping_assumption: s.damping.assumption.clone(),
                ..k.built.clone()
            }
        }
        None => structure(path, s.clone(), limit)?,
    };
    Ok(Kept { path: path.to_path_buf(), raw: s, limit: limit_n, built })
}

impl Kept {
    /// What it built.
    pub(super) fn built(&self) -> &Built {
        &self.built
    }
}

/// The structure of `[structure]` (`s`), from the one source it names.
pub(super) fn structure(path: &Path, s: RawStructure, limit: Limit<'_>) -> Result<Built> {
    let given: Vec<&dyn Source> = SOURCES.iter().copied().filter(|x| x.given(&s)).collect();
    let made = match given.as_slice() {
        [one] => one.build(path, &s, limit)?,
        // A finite-element model with other keys: it names the first of them.
        _ if finite_element::FiniteElement.given(&s) => finite_element::FiniteElement.build(path, &s, limit)?,
        _ => {
            // The masses are checked first, as a source would.
            lumped_or_full(path, &s)?;
            return Err(Error::invalid(
                path,
                "structure",
                // The keys of the sources beside a finite-element model's.
                SOURCES.iter().map(|x| x.key()).filter(|k| *k != "finite_element").collect::<Vec<_>>().join(" / "),
                "give exactly one of chain_stiffness_n_per_m, stiffness_matrix_n_per_m and fit (measured modes)",
            ));
        }
    };
    let Matrices { masses, full_mass, mut stiffness, fit, fe } = made;
    ground_springs(path, &s, &mut stiffness)?;
    let damping = damping(path, &s, masses.len())?;
    let supports = fe.as_ref().map(|f| std::sync::Arc::new(f.1.clone()));
    let points = fe.as_ref().map(|f| f.0.points.len());
    let structure = match full_mass {
        Some(m) => Structure::from_mass_matrix(m, stiffness, damping),
        None => Structure::from_matrices(&masses, stiffness, damping),
    };
    Ok(Built {
        structure: Structure { supports, points, ..structure },
        source: s.source,
        damping_assumption: s.damping.assumption,
        fit,
        fe: fe.map(|f| Arc::new(f.0)),
    })
}

/// Lumped masses (`masses_kg`) or a full mass matrix (`mass_matrix_kg`): exactly one. Returns
/// the masses (a full matrix's diagonal) and the full matrix where given.
pub(super) fn lumped_or_full(path: &Path, s: &RawStructure) -> Result<(Vec<f64>, Option<DMatrix<f64>>)> {
    match (&s.masses_kg, &s.mass_matrix_kg) {
        (Some(m), None) => {
            positive_list(path, "structure.masses_kg", m, "mass")?;
            Ok((m.clone(), None))
        }
        (None, Some(rows)) => {
            let m = symmetric_positive(path, "structure.mass_matrix_kg", rows, rows.len(), "mass")?;
            Ok((m.diagonal().iter().copied().collect(), Some(m)))
        }
        _ => Err(Error::invalid(
            path,
            "structure",
            "masses_kg / mass_matrix_kg",
            "give exactly one of masses_kg (lumped masses) and mass_matrix_kg (a symmetric positive definite mass matrix, rows)",
        )),
    }
}

/// Springs to ground (`ground_stiffness_n_per_m`) added to the stiffness's diagonal.
fn ground_springs(path: &Path, s: &RawStructure, k: &mut DMatrix<f64>) -> Result<()> {
    let Some(g) = &s.ground_stiffness_n_per_m else { return Ok(()) };
    let (key, n) = ("structure.ground_stiffness_n_per_m", k.nrows());
    if g.len() != n {
        return Err(Error::invalid(
            path,
            key,
            format!("{} values", g.len()),
            format!("expected {n} springs to ground, one per mass (0: none)"),
        ));
    }
    for (i, v) in g.iter().enumerate() {
        if !(v.is_finite() && *v >= 0.0) {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                v,
                "a spring to ground must be non-negative and finite (N/m)",
            ));
        }
        k[(i, i)] += v;
    }
    Ok(())
}

/// The damping of `[structure.damping]` for `n` coordinates: modal ratios or Rayleigh.
fn damping(path: &Path, s: &RawStructure, n: usize) -> Result<Damping> {
    let d = &s.damping;
    match (&d.modal_ratios, d.rayleigh_alpha, d.rayleigh_beta) {
        (Some(z), None, None) => {
            // One ratio for every mode (a reduced model's modes are not known before it is
            // reduced; a long chain's are many), or one per mode.
            let z = if z.len() == 1 { vec![z[0]; n] } else { z.clone() };
            if z.len() != n {
                return Err(Error::invalid(
                    path,
                    "structure.damping.modal_ratios",
                    format!("{} values", z.len()),
                    format!("expected one ratio for every mode, or {n}, one per mode"),
                ));
            }
            for (i, v) in z.iter().enumerate() {
                if !(v.is_finite() && *v >= 0.0 && *v < 1.0) {
                    return Err(Error::invalid(
                        path,
                        format!("structure.damping.modal_ratios[{i}]"),
                        v,
                        "a modal damping ratio must lie in [0, 1)",
                    ));
                }
            }
            Ok(Damping::ModalRatios(z))
        }
        (None, Some(alpha), Some(beta)) => {
            for (key, v) in [("rayleigh_alpha", alpha), ("rayleigh_beta", beta)] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(Error::invalid(
                        path,
                        format!("structure.damping.{key}"),
                        v,
                        "Rayleigh coefficients must be non-negative and finite",
                    ));
                }
            }
            Ok(Damping::Rayleigh { alpha, beta })
        }
        _ => Err(Error::invalid(
            path,
            "structure.damping",
            "(incomplete)",
            "give either modal_ratios = [...] or both rayleigh_alpha and rayleigh_beta",
        )),
    }
}

/// Every value of `key` positive and finite (a `what`).
pub(super) fn positive_list(path: &Path, key: &str, values: &[f64], what: &str) -> Result<()> {
    if values.is_empty() {
        return Err(Error::invalid(path, key, "[]", format!("give at least one {what}")));
    }
    for (i, v) in values.iter().enumerate() {
        if !(v.is_finite() && *v > 0.0) {
            return Err(Error::invalid(
                path,
                format!("{key}[{i}]"),
                v,
                format!("a {what} must be positive and finite"),
            ));
        }
    }
    Ok(())
}

/// A symmetric positive definite `n` x `n` matrix from `rows` (the `what` matrix of `key`).
pub(super) fn symmetric_positive(
    path: &Path,
    key: &str,
    rows: &[Vec<f64>],
    n: usize,
    what: &str,
) -> Result<DMatrix<f64>> {
    if n == 0 || rows.len() != n || rows.iter().any(|r| r.len() != n) {
        let shape = rows.iter().map(|r| r.len().to_string()).collect::<Vec<_>>().join(", ");
        return Err(Error::invalid(
            path,
            key,
            format!("{} rows of [{shape}] values", rows.len()),
            format!("expected {} rows of {} values", n.max(1), n.max(1)),
        ));
    }
    let k = DMatrix::from_fn(n, n, |i, j| rows[i][j]);
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (k[(i, j)], k[(j, i)]);
            if !a.is_finite() || (a - b).abs() > 1e-12 * a.abs().max(b.abs()) {
                return Err(Error::invalid(
                    path,
                    format!("{key}[{i}][{j}]"),
                    a,
                    format!("the {what} matrix must be symmetric and finite"),
                ));
            }
        }
    }
    if k.clone().cholesky().is_none() {
        return Err(Error::invalid(path, key, "(matrix)", format!("the {what} matrix must be positive definite")));
    }
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(text: &str) -> RawStructure {
        toml::from_str(text).expect("a structure table")
    }

    /// The paper's chain as a chain and as the stiffness matrix it stands for: the same
    /// structure; each source's key is one of `[structure]`'s and selects only it.
    #[test]
    fn a_chain_and_its_matrix_are_the_same_structure() {
        let damping = "[damping]\nmodal_ratios = [0.01]\n";
        let chain = raw(&format!("masses_kg = [1.5, 1.2, 1.0]\nchain_stiffness_n_per_m = [3e4, 2e4, 1e4]\n{damping}"));
        let matrix = raw(&format!(
            "masses_kg = [1.5, 1.2, 1.0]\nstiffness_matrix_n_per_m = [[5e4, -2e4, 0.0], [-2e4, 3e4, -1e4], [0.0, -1e4, 1e4]]\n{damping}"
        ));
        let (a, b) =
            (structure(Path::new("a.toml"), chain, None).ok(), structure(Path::new("b.toml"), matrix, None).ok());
        let (a, b) = (a.expect("the chain builds"), b.expect("the matrix builds"));
        assert_eq!(a.structure.stiffness, b.structure.stiffness);
        assert_eq!(a.structure, b.structure);
        for (i, s) in SOURCES.iter().enumerate() {
            assert!(SOURCES[..i].iter().all(|o| o.key() != s.key()), "{} twice", s.key());
        }
        let given = |t: &RawStructure| SOURCES.iter().filter(|s| s.given(t)).map(|s| s.key()).collect::<Vec<_>>();
        let chain = raw(&format!("masses_kg = [1.0]\nchain_stiffness_n_per_m = [1e4]\n{damping}"));
        assert_eq!(given(&chain), ["chain_stiffness_n_per_m"]);
    }
}
