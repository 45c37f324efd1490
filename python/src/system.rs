//! A structure with its dampers, driven by a force: steady states with their certificates,
//! sweeps (the command line's compliance table, column for column) and impulse responses.

use num_complex::Complex64;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use shotdamp::analysis::curves;
use shotdamp::experiment::{parts, Case};
use shotdamp::sim::settle::steady::{Certificate, Observe, Steady as Found};
use shotdamp::sim::settle::sweep::{self, Direction, SweepPoint};
use shotdamp::sim::{SteadyOptions, System as Sim};

use crate::compute::{self, error};
use crate::convert::{array1, array2, floats, frequencies, table};
use crate::structure::{case, Structure};

/// Forcing frequencies to simulate on `structure`, Hz: at most [`MAX_FREQUENCIES`], each as
/// an experiment file's ([`parts::check_frequencies`]).
fn simulated(origin: &str, f: &[f64], structure: &shotdamp::model::Structure) -> PyResult<Vec<f64>> {
    let f = frequencies(origin, f)?;
    parts::check_frequencies(origin, "freq_hz", &f, structure).map_err(error)?;
    Ok(f)
}

/// Steady-state settings from a dict with the keys of `[analysis.steady]`.
fn steady_options(origin: &str, steady: Option<&Bound<'_, PyDict>>) -> PyResult<SteadyOptions> {
    let t = match steady {
        Some(d) => table("steady", d)?,
        None => toml::Table::new(),
    };
    parts::steady(origin, t).map_err(error)
}

/// A structure with dampers, driven by `force_n` sin(omega t) on `force_mass`, or by its
/// supports accelerating as `base_acceleration_m_s2` sin(omega t).
#[pyclass(module = "shotdamp._native", frozen)]
pub struct System {
    sim: Sim,
    case: Case,
    force: f64,
}

impl System {
    /// A system built by the library (an experiment's case).
    pub fn from_parts(sim: Sim, case: Case, force: f64) -> System {
        System { sim, case, force }
    }
}

#[pymethods]
impl System {
    /// `dampers`: a sequence of `Damper` (none: the bare structure); `force_mass` 1-based (1
    /// when not given); `base_acceleration_m_s2` instead of a force moves the supports.
    #[new]
    #[pyo3(signature = (structure, dampers=None, *, force_mass=None, force_n=None, base_acceleration_m_s2=None))]
    fn new(
        structure: &Bound<'_, Structure>,
        dampers: Option<&Bound<'_, PyAny>>,
        force_mass: Option<i64>,
        force_n: Option<f64>,
        base_acceleration_m_s2: Option<f64>,
    ) -> PyResult<System> {
        let origin = "shotdamp.System";
        let bare = &structure.get().bare;
        parts::simulated_structure(origin, bare, structure.get().fe.as_deref()).map_err(error)?;
        let force_mass = force_mass.or(force_n.map(|_| 1));
        let excitation = parts::drive(origin, force_mass, force_n, base_acceleration_m_s2, bare).map_err(error)?;
        let case = match dampers {
            Some(d) => case(bare, d, origin)?,
            None => parts::case(origin, "python", Vec::new(), bare).map_err(error)?,
        };
        parts::simulated_case(origin, &case, bare).map_err(error)?;
        let sim = parts::system(bare, &excitation, &case);
        Ok(System { sim, case, force: excitation.force })
    }

    /// Number of masses of the structure.
    #[getter]
    fn dof(&self) -> usize {
        self.sim.dof()
    }

    /// Number of containers.
    #[getter]
    fn containers(&self) -> usize {
        self.case.beds.len()
    }

    /// The steady state at `freq_hz` from rest (the same computation as one point of a sweep
    /// from rest): a `Steady`, with its certificate (`orbit`) when it is a periodic orbit.
    /// `steady`: a dict with the keys of an experiment file's `[analysis.steady]`.
    #[pyo3(signature = (freq_hz, *, steady=None))]
    fn steady_state(&self, py: Python<'_>, freq_hz: f64, steady: Option<&Bound<'_, PyDict>>) -> PyResult<Steady> {
        let origin = "shotdamp.System.steady_state";
        let f = simulated(origin, &[freq_hz], &self.sim.structure)?;
        let opts = steady_options(origin, steady)?;
        let sim = &self.sim;
        let mut points = compute::run(py, Some(1), None, |t| Ok(sweep::from_rest(sim, &f, &opts, &|| t.tick())))?;
        let p = points.pop().ok_or_else(|| pyo3::exceptions::PyRuntimeError::new_err("no point computed"))?;
        match p.result {
            Ok(s) => Steady::of(py, p.freq_hz, s, self.force, &self.case.grains()),
            Err(e) => Err(pyo3::exceptions::PyValueError::new_err(format!("{origin}: {e}"))),
        }
    }

    /// A sweep: every frequency from rest (`start="rest"`, in parallel on `jobs` threads, the
    /// same numbers for any number), or by continuation upward or downward (`"up"`, `"down"`).
    /// Returns the columns of the command line's `compliance` table (curve, freq_hz, c1..cn in
    /// m/N, converged, period, impacts per period and highest flight per container,
    /// transient_periods, orbit_residual, max_multiplier, stop), rows in order of frequency
    /// (continuation: in the order computed). On a finite-element structure `c1..cn` are its
    /// points only, as on the command line: its modal coordinates are no displacement of any
    /// point, and the records do not follow them (docs/fe-models.md). `progress(done, total)`
    /// is called as points finish.
    #[pyo3(signature = (freq_hz, *, start="rest", steady=None, curve="sweep", jobs=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        freq_hz: &Bound<'py, PyAny>,
        start: &str,
        steady: Option<&Bound<'py, PyDict>>,
        curve: &str,
        jobs: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let jobs = compute::jobs(jobs)?;
        let origin = "shotdamp.System.sweep";
        let f = simulated(origin, &floats("freq_hz", freq_hz)?, &self.sim.structure)?;
        let mut opts = steady_options(origin, steady)?;
        let (n, shown) = (self.sim.dof(), self.sim.structure.physical());
        if shown < n {
            opts.observe = Observe::only(0..shown);
        }
        let dir = match start {
            "rest" => None,
            "up" => Some(Direction::Up),
            "down" => Some(Direction::Down),
            other => {
                return Err(error(shotdamp::Error::invalid(
                    origin,
                    "start",
                    format!("\"{other}\""),
                    "\"rest\" (every point from rest), \"up\" or \"down\" (continuation)",
                )))
            }
        };
        let sim = &self.sim;
        let points: Vec<SweepPoint> = compute::run(py, jobs, progress, |t| {
            t.expect(f.len() as u64);
            Ok(match dir {
                None => sweep::from_rest(sim, &f, &opts, &|| t.tick()),
                Some(d) => sweep::continued(sim, &f, d, &opts, &|| t.tick()),
            })
        })?;
        let c = curves::from_sweep(
            shotdamp::experiment::CurveId::whole(curve),
            curve,
            points,
            self.force,
            &self.case.grains(),
            n,
        );
        let t = curves::table("compliance", "", &[&c], shown, self.case.beds.len());
        crate::convert::columns(py, &t)
    }

    /// The free response after a kick (no force): the keys of an impulse experiment's
    /// `[analysis]` (`struck_mass` 1-based, `initial_velocity_m_s` or `impulse_n_s`,
    /// `duration_s`, `sample_rate_hz`). Returns a dict: `t_s`, `x_m` and `v_m_s` (samples x
    /// masses, from the static rest), `y_m` (samples x beds, bed positions), the energy
    /// given, left and lost (J), `events` and the energy residual.
    #[pyo3(signature = (*, struck_mass=1, initial_velocity_m_s=None, impulse_n_s=None, duration_s=None, sample_rate_hz=None))]
    fn impulse<'py>(
        &self,
        py: Python<'py>,
        struck_mass: i64,
        initial_velocity_m_s: Option<&Bound<'py, PyAny>>,
        impulse_n_s: Option<&Bound<'py, PyAny>>,
        duration_s: Option<&Bound<'py, PyAny>>,
        sample_rate_hz: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let origin = "shotdamp.System.impulse";
        let mut t = crate::convert::named(&[
            ("initial_velocity_m_s", initial_velocity_m_s),
            ("impulse_n_s", impulse_n_s),
            ("duration_s", duration_s),
            ("sample_rate_hz", sample_rate_hz),
        ])?;
        t.insert("struck_mass".into(), toml::Value::Integer(struck_mass));
        let opts = parts::impulse(origin, t, &self.sim.structure).map_err(error)?;
        parts::kick(origin, &opts, &self.sim.structure, &self.case).map_err(error)?;
        let sim = &self.sim;
        let run = compute::run(py, Some(1), None, |_| {
            shotdamp::sim::motion::impulse::free_response(sim, &opts)
                .map_err(|e| shotdamp::Error::invalid(origin, "system", "(setup)", e.to_string()))
        })?;
        let s = &run.samples;
        let d = PyDict::new(py);
        d.set_item("t_s", array1(py, s.times.clone()))?;
        d.set_item("x_m", array2(py, &s.x, self.sim.dof())?)?;
        d.set_item("v_m_s", array2(py, &s.v, self.sim.dof())?)?;
        d.set_item("y_m", array2(py, &s.y, self.sim.dampers.len())?)?;
        d.set_item("rest_m", array1(py, run.rest.clone()))?;
        d.set_item("initial_velocity_m_s", run.initial_velocity)?;
        d.set_item("initial_energy_j", run.initial_energy)?;
        d.set_item("remaining_energy_j", array1(py, run.remaining.clone()))?;
        d.set_item("impact_loss_until_j", array1(py, run.impact_loss_until.clone()))?;
        d.set_item("viscous_loss_j", run.viscous_loss)?;
        d.set_item("impact_loss_j", run.impact_loss)?;
        d.set_item("final_energy_j", run.final_energy)?;
        d.set_item("energy_residual", run.energy_residual())?;
        d.set_item("events", s.events.len())?;
        d.set_item("stop", run.stop.as_ref().map(|s| format!("{s:?}")))?;
        Ok(d)
    }

    /// The structure with its beds under a recorded ground motion, exact between samples
    /// (docs/model.md section 5; the command line's `kind = "time_history"`): `accel_m_s2` the
    /// ground's acceleration at `t = k dt_s`, linear between samples, along the structure's
    /// supports; from rest with every bed on its container's bottom (the system's force or
    /// harmonic base motion is not used). Returns a dict: `t_s` and, samples x coordinates,
    /// `u_m` (relative to the supports) and `accel_m_s2` (absolute), every `max_history`-th
    /// sample at most; over every sample and between them: `peak_displacement_m`,
    /// `peak_drift_m` (a chain's storeys, else empty), `peak_accel_m_s2` and their `rms_`
    /// values; the energies (J) `energy_input_j`, `energy_viscous_j`, `energy_impacts_j`,
    /// `energy_stored_j`, `energy_balance_j`; per bed `impacts` and `lift_offs`; `events`;
    /// `completed` (false when the run stopped at its event limit).
    #[pyo3(signature = (accel_m_s2, dt_s, *, max_history=20000))]
    fn ground_motion<'py>(
        &self,
        py: Python<'py>,
        accel_m_s2: &Bound<'py, PyAny>,
        dt_s: f64,
        max_history: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let origin = "shotdamp.System.ground_motion";
        let accel = floats("accel_m_s2", accel_m_s2)?;
        let bad =
            |key: &str, value: String, allowed: &str| error(shotdamp::Error::invalid(origin, key, value, allowed));
        if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= 10.0) {
            return Err(bad("dt_s", dt_s.to_string(), "a sampling step in s, above 0 and at most 10"));
        }
        let most = shotdamp::experiment::ground::MAX_SAMPLES;
        if accel.len() < 2 || accel.len() > most {
            return Err(bad("accel_m_s2", format!("{} samples", accel.len()), &format!("2 to {most} samples")));
        }
        if let Some((k, a)) = accel.iter().enumerate().find(|(_, a)| !(a.is_finite() && a.abs() <= 1e3)) {
            return Err(bad(&format!("accel_m_s2[{k}]"), a.to_string(), "a finite acceleration of at most 1000 m/s^2"));
        }
        if max_history < 2 {
            return Err(bad("max_history", max_history.to_string(), "2 samples or more"));
        }
        let record = shotdamp::model::ground::GroundMotion { name: "python".into(), dt_s, accel_m_s2: accel };
        let options = shotdamp::sim::record::RecordOptions { max_history, ..Default::default() };
        let sim = &self.sim;
        let r = compute::run(py, Some(1), None, |_| {
            shotdamp::sim::record::respond(sim, &record, options)
                .map_err(|e| shotdamp::Error::invalid(origin, "system", "(this structure and its beds)", e.to_string()))
        })?;
        let n = r.peak_displacement.len();
        let d = PyDict::new(py);
        d.set_item("t_s", array1(py, r.t.clone()))?;
        d.set_item("u_m", array2(py, &r.u, n)?)?;
        d.set_item("accel_m_s2", array2(py, &r.accel, n)?)?;
        d.set_item("peak_displacement_m", array1(py, r.peak_displacement.clone()))?;
        d.set_item("peak_drift_m", array1(py, r.peak_drift.clone()))?;
        d.set_item("peak_accel_m_s2", array1(py, r.peak_accel.clone()))?;
        d.set_item("rms_displacement_m", array1(py, r.rms_displacement.clone()))?;
        d.set_item("rms_drift_m", array1(py, r.rms_drift.clone()))?;
        d.set_item("rms_accel_m_s2", array1(py, r.rms_accel.clone()))?;
        d.set_item("energy_input_j", r.energy_input)?;
        d.set_item("energy_viscous_j", r.energy_viscous)?;
        d.set_item("energy_impacts_j", r.energy_impacts)?;
        d.set_item("energy_stored_j", r.energy_stored)?;
        d.set_item("energy_balance_j", r.balance())?;
        d.set_item("impacts", r.beds.iter().map(|b| b.impacts).collect::<Vec<_>>())?;
        d.set_item("lift_offs", r.beds.iter().map(|b| b.lift_offs).collect::<Vec<_>>())?;
        d.set_item("events", r.events)?;
        d.set_item("completed", r.stop == shotdamp::sim::record::RecordStop::Completed)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let drive = if self.sim.base.is_some() { "base_acceleration_m_s2" } else { "force_n" };
        format!("System(dof={}, containers={}, {drive}={})", self.sim.dof(), self.case.beds.len(), self.force)
    }
}

/// The steady state of one frequency.
#[pyclass(module = "shotdamp._native", frozen)]
pub struct Steady {
    /// Forcing frequency, Hz.
    #[pyo3(get)]
    freq_hz: f64,
    /// Settled (a stable orbit found, or the transient died out).
    #[pyo3(get)]
    converged: bool,
    /// Period of the motion in forcing periods (0: none found).
    #[pyo3(get)]
    period: usize,
    /// Periods simulated before recording.
    #[pyo3(get)]
    transient_periods: usize,
    /// Why the point has no steady state, or stopped early ("" when it has one).
    #[pyo3(get)]
    stop: String,
    /// The certificate of a periodic orbit (None when the point is not one).
    #[pyo3(get)]
    orbit: Option<Py<Orbit>>,
    /// What the motion is: "periodic", "quasi-periodic", "chaotic", "transient", "unclassified", "chatter"
    /// or "aperiodic".
    #[pyo3(get)]
    motion: String,
    /// A point with no certified orbit: its largest Lyapunov exponent, 1/s (None otherwise).
    #[pyo3(get)]
    lyapunov_per_s: Option<f64>,
    /// The half-width of the exponent's 95 % interval, 1/s (None without a measurement).
    #[pyo3(get)]
    lyapunov_half_width: Option<f64>,
    /// Periods of the measured record after its start was cut (0 without a measurement).
    #[pyo3(get)]
    measured_periods: usize,
    /// The compliance's interval met its tolerance (False without a measurement).
    #[pyo3(get)]
    interval_met: bool,
    half_width: Vec<f64>,
    compliance: Vec<f64>,
    amplitude: Vec<f64>,
    bottom: Vec<f64>,
    top: Vec<f64>,
    flight: Vec<f64>,
}

impl Steady {
    fn of(py: Python<'_>, freq_hz: f64, s: Found, force: f64, grains: &[usize]) -> PyResult<Steady> {
        let stop = curves::stop_text(&s);
        let orbit = s.certificate.as_ref().map(|c| Orbit::of(freq_hz, s.period, c));
        let m = s.measured.as_ref();
        Ok(Steady {
            freq_hz,
            converged: s.converged,
            period: s.period,
            transient_periods: s.transient_periods,
            stop,
            orbit: orbit.map(|o| Py::new(py, o)).transpose()?,
            motion: s.motion.name().to_string(),
            lyapunov_per_s: m.map(|m| m.lyapunov),
            lyapunov_half_width: m.map(|m| m.lyapunov_half_width),
            measured_periods: m.map_or(0, |m| m.periods),
            interval_met: m.is_some_and(|m| m.met),
            half_width: m
                .map_or(vec![f64::NAN; s.amplitude.len()], |m| m.half_width.iter().map(|h| h / force).collect()),
            compliance: s.amplitude.iter().map(|a| a / force).collect(),
            amplitude: s.amplitude.clone(),
            bottom: curves::per_container(s.bottom_impacts, grains, false),
            top: curves::per_container(s.top_impacts, grains, false),
            flight: curves::per_container(s.max_flight, grains, true),
        })
    }
}

#[pymethods]
impl Steady {
    /// Compliance of each mass, m/N: half peak-to-peak displacement over the force.
    #[getter(compliance)]
    fn compliance_array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.compliance.clone())
    }

    /// Half-width of each mass's compliance 95 % interval, m/N (NaN without a measurement:
    /// a certified orbit is exact).
    #[getter(compliance_half_width)]
    fn half_width_array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.half_width.clone())
    }

    /// Half peak-to-peak displacement of each mass, m.
    #[getter(amplitude_m)]
    fn amplitude_array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.amplitude.clone())
    }

    /// Impacts per forcing period on the bottom of each container.
    #[getter]
    fn bottom_impacts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.bottom.clone())
    }

    /// Impacts per forcing period on the top of each container.
    #[getter]
    fn top_impacts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.top.clone())
    }

    /// Highest flight above the bottom in each container, m.
    #[getter]
    fn max_flight_m<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.flight.clone())
    }

    fn __repr__(&self) -> String {
        format!(
            "Steady(freq_hz={}, converged={}, period={}, compliance={:?}{})",
            self.freq_hz,
            if self.converged { "True" } else { "False" },
            self.period,
            self.compliance,
            if self.stop.is_empty() { String::new() } else { format!(", stop={:?}", self.stop) }
        )
    }
}

/// A periodic orbit with its certificate: the fixed-point residual and the Floquet
/// multipliers of the stroboscopic map.
#[pyclass(module = "shotdamp._native", frozen)]
pub struct Orbit {
    /// Forcing frequency, Hz.
    #[pyo3(get)]
    freq_hz: f64,
    /// Period in forcing periods.
    #[pyo3(get)]
    period: usize,
    /// Max-norm of P(u) - u, relative to the amplitude scale.
    #[pyo3(get)]
    residual: f64,
    /// Every multiplier inside the unit circle.
    #[pyo3(get)]
    stable: bool,
    /// No graze and no simultaneous impacts on the orbit.
    #[pyo3(get)]
    smooth: bool,
    /// The largest multiplier modulus.
    #[pyo3(get)]
    spectral_radius: f64,
    /// Forcing phase of the section, rad.
    #[pyo3(get)]
    phase: f64,
    /// Newton iterations of the successful attempt, and attempts made.
    #[pyo3(get)]
    iterations: usize,
    #[pyo3(get)]
    attempts: usize,
    multipliers_: Vec<Complex64>,
    x: Vec<f64>,
    v: Vec<f64>,
}

impl Orbit {
    fn of(freq_hz: f64, period: usize, c: &Certificate) -> Orbit {
        Orbit {
            freq_hz,
            period,
            residual: c.residual,
            stable: c.stable,
            smooth: c.smooth,
            spectral_radius: c.spectral_radius(),
            phase: c.phase,
            iterations: c.iterations,
            attempts: c.attempts,
            multipliers_: c.multipliers.clone(),
            x: c.section.x.iter().copied().collect(),
            v: c.section.v.iter().copied().collect(),
        }
    }
}

#[pymethods]
impl Orbit {
    /// Floquet multipliers, largest modulus first (complex).
    #[getter]
    fn multipliers<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<Complex64>> {
        PyArray1::from_slice(py, &self.multipliers_)
    }

    /// Displacements (m) and velocities (m/s) of the masses at the section.
    #[getter]
    fn section<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, [array1(py, self.x.clone()), array1(py, self.v.clone())])
    }

    fn __repr__(&self) -> String {
        format!(
            "Orbit(freq_hz={}, period={}, stable={}, spectral_radius={:.6}, residual={:.3e})",
            self.freq_hz,
            self.period,
            if self.stable { "True" } else { "False" },
            self.spectral_radius,
            self.residual
        )
    }
}
