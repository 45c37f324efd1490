//! Structures and dampers, built from the keys of an experiment file's `[structure]` table
//! and `dampers` entries, through the same validation (and messages) as the command line.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use shotdamp::experiment::parts;
use shotdamp::model::Structure as Bare;

use crate::compute::error;
use crate::convert::{array1, array2, floats, matrix, named, table};

/// Where a bad structure value came from, in messages.
const ORIGIN: &str = "shotdamp.Structure";

/// The bare primary structure: lumped masses or a full mass matrix, a stiffness and a fixed
/// damping matrix (docs/model.md sections 1 and 5).
#[pyclass(module = "shotdamp._native", frozen)]
pub struct Structure {
    pub bare: Bare,
    /// The finite-element model it was reduced from, if any.
    pub fe: Option<std::sync::Arc<shotdamp::model::fe::FeStructure>>,
}

#[pymethods]
impl Structure {
    /// The keys of an experiment file's `[structure]` table: `masses_kg` (lumped) or
    /// `mass_matrix_kg` (a symmetric positive definite mass matrix, rows), and exactly one of
    /// `chain_stiffness_n_per_m`, `stiffness_matrix_n_per_m` and `fit` (measured modes: a dict
    /// with `omegas_rad_per_s` and `shapes`); damping by `modal_ratios` or both `rayleigh_alpha`
    /// and `rayleigh_beta`; springs to ground by `ground_stiffness_n_per_m`. Or
    /// `finite_element`: a dict with the keys of `[structure.finite_element]` (a finite-element
    /// model's files, relative to the working directory, reduced at its points:
    /// docs/fe-models.md), the structure's coordinates then the points' followed by modal ones.
    #[new]
    #[pyo3(signature = (*, masses_kg=None, mass_matrix_kg=None, chain_stiffness_n_per_m=None, stiffness_matrix_n_per_m=None, fit=None, ground_stiffness_n_per_m=None, finite_element=None, modal_ratios=None, rayleigh_alpha=None, rayleigh_beta=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        masses_kg: Option<&Bound<'_, PyAny>>,
        mass_matrix_kg: Option<&Bound<'_, PyAny>>,
        chain_stiffness_n_per_m: Option<&Bound<'_, PyAny>>,
        stiffness_matrix_n_per_m: Option<&Bound<'_, PyAny>>,
        fit: Option<&Bound<'_, PyAny>>,
        ground_stiffness_n_per_m: Option<&Bound<'_, PyAny>>,
        finite_element: Option<&Bound<'_, PyAny>>,
        modal_ratios: Option<&Bound<'_, PyAny>>,
        rayleigh_alpha: Option<&Bound<'_, PyAny>>,
        rayleigh_beta: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Structure> {
        let mut t = named(&[
            ("masses_kg", masses_kg),
            ("mass_matrix_kg", mass_matrix_kg),
            ("chain_stiffness_n_per_m", chain_stiffness_n_per_m),
            ("stiffness_matrix_n_per_m", stiffness_matrix_n_per_m),
            ("fit", fit),
            ("ground_stiffness_n_per_m", ground_stiffness_n_per_m),
            ("finite_element", finite_element),
        ])?;
        let damping = named(&[
            ("modal_ratios", modal_ratios),
            ("rayleigh_alpha", rayleigh_alpha),
            ("rayleigh_beta", rayleigh_beta),
        ])?;
        t.insert("damping".into(), toml::Value::Table(damping));
        let (bare, fe) = parts::structure_and_model(ORIGIN, t).map_err(error)?;
        Ok(Structure { bare, fe })
    }

    /// How good a finite-element structure's reduction is: a dict of two `Table`s,
    /// `frequencies` (the full model's natural frequencies, the reduced model's, their relative
    /// difference) and, with `freq_hz`, `compliance` (the damped compliance's magnitude at every
    /// point for a unit force at `force_point`, 1-based, both models with the structure's
    /// damping: the full model's by a sparse direct solve with its lowest modes deflated, the
    /// reduced model's, their difference relative to each point's peak), and `largest`, the
    /// largest of those differences (the report's reduction check). A ValueError for a
    /// structure that was not reduced.
    #[pyo3(signature = (freq_hz=None, *, force_point=1))]
    fn reduction<'py>(
        &self,
        py: Python<'py>,
        freq_hz: Option<&Bound<'py, PyAny>>,
        force_point: i64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let origin = "shotdamp.Structure.reduction";
        let Some(fe) = &self.fe else {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{origin}: this structure was not reduced from a finite-element model (give finite_element)"
            )));
        };
        let points = fe.points.len();
        if !(1..=points as i64).contains(&force_point) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{origin}: force_point = {force_point}: the points are numbered 1 to {points}"
            )));
        }
        let mut f = match freq_hz {
            Some(f) => floats("freq_hz", f)?,
            None => Vec::new(),
        };
        if let Some(bad) = f.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{origin}: freq_hz: {bad}: frequencies must be positive and finite (Hz)"
            )));
        }
        f.sort_by(f64::total_cmp);
        f.dedup();
        let out = py.detach(|| {
            shotdamp::analysis::reduction::compare(
                fe,
                (force_point - 1) as usize,
                &[("freq_hz".to_string(), f)],
                Some(&self.bare),
            )
        });
        let d = PyDict::new(py);
        for t in &out.tables {
            let key = t.name.trim_start_matches("reduction_");
            d.set_item(key, crate::convert::columns(py, t)?)?;
        }
        d.set_item("largest", out.check.as_ref().map(|c| c.computed))?;
        Ok(d)
    }

    /// Number of masses.
    #[getter]
    fn dof(&self) -> usize {
        self.bare.dof()
    }

    /// Masses, kg (a full mass matrix's diagonal).
    #[getter]
    fn masses_kg<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.bare.masses.clone())
    }

    /// Mass matrix, kg (diagonal for lumped masses).
    #[getter]
    fn mass_matrix<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.bare.mass_matrix())
    }

    /// Stiffness matrix, N/m.
    #[getter]
    fn stiffness<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.bare.stiffness)
    }

    /// Damping matrix, N s/m.
    #[getter]
    fn damping<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.bare.damping)
    }

    /// The modes of the bare structure, with the mass ratios of the paper's Eq. 13 for
    /// `dampers` (on this structure): a dict of arrays, one entry per mode (`shape` is one
    /// row per mode, normalised to +1 at its largest element).
    #[pyo3(signature = (dampers=None))]
    fn modes<'py>(&self, py: Python<'py>, dampers: Option<&Bound<'py, PyAny>>) -> PyResult<Bound<'py, PyDict>> {
        let beds = match dampers {
            Some(d) => case(&self.bare, d, "shotdamp.Structure.modes")?.dampers(),
            None => Vec::new(),
        };
        let modes = shotdamp::model::modal::modal_summary(&self.bare, &beds);
        let d = PyDict::new(py);
        let col = |f: &dyn Fn(&shotdamp::model::modal::ModeSummary) -> f64| modes.iter().map(f).collect::<Vec<f64>>();
        d.set_item("mode", PyArray1::from_vec(py, modes.iter().map(|m| m.number as i64).collect()))?;
        d.set_item("freq_hz", array1(py, col(&|m| m.freq_hz)))?;
        d.set_item("omega_rad_s", array1(py, col(&|m| m.omega)))?;
        d.set_item("damping_ratio", array1(py, col(&|m| m.damping_ratio)))?;
        d.set_item("modal_mass_kg", array1(py, col(&|m| m.modal_mass)))?;
        d.set_item("modal_stiffness_n_per_m", array1(py, col(&|m| m.modal_stiffness)))?;
        d.set_item("mass_ratio", array1(py, col(&|m| m.mass_ratio)))?;
        d.set_item(
            "reference_mass",
            PyArray1::from_vec(py, modes.iter().map(|m| m.reference_mass as i64 + 1).collect()),
        )?;
        let shapes: Vec<Vec<f64>> = modes.iter().map(|m| m.shape.clone()).collect();
        d.set_item("shape", array2(py, &shapes, self.bare.dof())?)?;
        Ok(d)
    }

    /// Exact linear compliance |x_r / F| (m/N) of every mass (columns) at each frequency (rows)
    /// for a force on `force_mass` (1-based); with `dampers`, their masses rigidly added
    /// ("stuck"). Infinite where an undamped structure's response is unbounded.
    #[pyo3(signature = (freq_hz, *, force_mass=1, dampers=None))]
    fn frf<'py>(
        &self,
        py: Python<'py>,
        freq_hz: &Bound<'py, PyAny>,
        force_mass: i64,
        dampers: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let f = crate::convert::frequencies("shotdamp.Structure.frf", &floats("freq_hz", freq_hz)?)?;
        let driven = parts::excitation("shotdamp.Structure.frf", force_mass, 1.0, &self.bare).map_err(error)?.mass;
        let added = match dampers {
            Some(d) => shotdamp::model::damper::added_masses(&case(&self.bare, d, "shotdamp.Structure.frf")?.dampers()),
            None => Vec::new(),
        };
        let mass = self.bare.mass_matrix_with(&added);
        let omegas: Vec<f64> = f.iter().map(|f| 2.0 * std::f64::consts::PI * f).collect();
        let rows = shotdamp::model::frf::compliance_curve(&self.bare, &mass, driven, &omegas);
        array2(py, &rows, self.bare.dof())
    }

    fn __repr__(&self) -> String {
        format!("Structure(masses_kg={:?}, dof={})", self.bare.masses, self.bare.dof())
    }
}

/// One container of shot on a mass: the keys of an experiment file's `dampers` entries. It is
/// checked against the structure when a `System` (or `modes`, `frf`) takes it.
#[pyclass(module = "shotdamp._native", frozen)]
pub struct Damper {
    pub keys: toml::Table,
}

#[pymethods]
impl Damper {
    /// `mass` is the host mass, 1-based as in the paper; the shot's mass by `mass_ratio`
    /// (m_d / m_host) or `mass_kg`; `clearance_mm` a number or "inf" (no top); the bed
    /// `"plastic"` (the paper's), `"restitution"` (one mass bouncing with `restitution`) or
    /// `"column"` (`grains` equal grains), `stick_speed_m_s` ending chatter; `direction`
    /// `"vertical"` (the paper's) or `"horizontal"` (the bed flies between two walls).
    #[new]
    #[pyo3(signature = (*, mass, clearance_mm, mass_ratio=None, mass_kg=None, bed=None, grains=None, restitution=None, stick_speed_m_s=None, direction=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        mass: &Bound<'_, PyAny>,
        clearance_mm: &Bound<'_, PyAny>,
        mass_ratio: Option<&Bound<'_, PyAny>>,
        mass_kg: Option<&Bound<'_, PyAny>>,
        bed: Option<&Bound<'_, PyAny>>,
        grains: Option<&Bound<'_, PyAny>>,
        restitution: Option<&Bound<'_, PyAny>>,
        stick_speed_m_s: Option<&Bound<'_, PyAny>>,
        direction: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Damper> {
        let keys = named(&[
            ("mass", Some(mass)),
            ("mass_ratio", mass_ratio),
            ("mass_kg", mass_kg),
            ("clearance_mm", Some(clearance_mm)),
            ("bed", bed),
            ("grains", grains),
            ("restitution", restitution),
            ("stick_speed_m_s", stick_speed_m_s),
            ("direction", direction),
        ])?;
        parts::damper("shotdamp.Damper", keys.clone()).map_err(error)?;
        Ok(Damper { keys })
    }

    /// A damper from a dict with the keys of an experiment file's `dampers` entry.
    #[staticmethod]
    fn from_dict(keys: &Bound<'_, PyDict>) -> PyResult<Damper> {
        let keys = table("damper", keys)?;
        parts::damper("shotdamp.Damper.from_dict", keys.clone()).map_err(error)?;
        Ok(Damper { keys })
    }

    /// The keys given, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in &self.keys {
            match v {
                toml::Value::Integer(i) => d.set_item(k, i)?,
                toml::Value::Float(x) => d.set_item(k, x)?,
                toml::Value::String(s) => d.set_item(k, s)?,
                toml::Value::Boolean(b) => d.set_item(k, b)?,
                other => d.set_item(k, PyList::new(py, [other.to_string()])?)?,
            }
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let keys: Vec<String> = self.keys.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("Damper({})", keys.join(", "))
    }
}

/// The case of `dampers` (a sequence of `Damper`) on `structure`, validated as an experiment
/// file's case.
pub fn case(
    structure: &shotdamp::model::Structure,
    dampers: &Bound<'_, PyAny>,
    origin: &str,
) -> PyResult<shotdamp::experiment::Case> {
    let mut keys = Vec::new();
    for d in dampers.try_iter()? {
        let d = d?;
        let d = d.cast::<Damper>().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "{origin}: dampers must be shotdamp.Damper objects, not {}",
                d.get_type().name().map(|n| n.to_string()).unwrap_or_default()
            ))
        })?;
        keys.push(d.get().keys.clone());
    }
    parts::case(origin, "python", keys, structure).map_err(error)
}
