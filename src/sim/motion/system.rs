//! The structure with its dampers and forcing, and the closed-form dynamics of each of the
//! 2^N configurations (docs/model.md section 2).

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use crate::model::{BaseMotion, Damper, Structure};

use super::buf::Terms;
use super::eigen;
use super::forced::{forced_into, Drive, Forced, ModalParts};

mod forcing;

/// Most degrees of freedom (masses, or generalised coordinates) the closed form takes.
pub const MAX_DOF: usize = 256;

/// Most numbers the decompositions of one system may store, counted as configurations x
/// degrees of freedom x terms (each configuration keeps its eigenvectors' displacement rows
/// in [`ORDERS`] derivative orders, about 170 bytes a number): about 700 MB.
pub const MAX_STORED: usize = 1 << 22;

/// Highest derivative order of a host displacement the event functions need (contact
/// forces are second derivatives; their certified bounds need four more).
pub const ORDERS: usize = 7;

/// Largest condition number (max |V| max |V^-1|) of a configuration's eigenvectors.
const MAX_CONDITION: f64 = 1e12;

/// Most configurations one system may have: every one is decomposed up front. A single bed
/// doubles their number (attached or not); a column of `n` grains multiplies it by `n + 1`
/// (how many of its grains ride on the host), so 14 single beds, or three 20-grain columns.
/// A large structure allows fewer ([`config_limit`]).
pub const MAX_CONFIGS: usize = 1 << 14;

/// Most configurations a structure of `dof` degrees of freedom may have: [`MAX_CONFIGS`], or
/// fewer where their decompositions would store more than [`MAX_STORED`] numbers.
pub fn config_limit(dof: usize) -> usize {
    let per_config = (dof * 2 * dof).max(1);
    (MAX_STORED / per_config).min(MAX_CONFIGS)
}

/// The configurations of beds of `grains` each (1 a single bed, a column its grains): the
/// product of each one's grains + 1 (how many of them ride their host), `None` above `limit`.
/// The one count the simulator decomposes and every limit on it is checked with.
pub fn configurations(grains: impl IntoIterator<Item = usize>, limit: usize) -> Option<usize> {
    grains.into_iter().try_fold(1usize, |acc, g| acc.checked_mul(g.max(1) + 1).filter(|&c| c <= limit))
}

/// Most single beds one system may carry (`2^N <= MAX_CONFIGS`).
pub const MAX_BEDS: usize = 14;

/// Most beds counting every grain of every column (bits of a configuration mask).
pub const MAX_GRAINS: usize = 63;

/// What the simulator integrates: the structure, its dampers, the force or the supports'
/// motion.
#[derive(Debug, Clone)]
pub struct System {
    /// The bare structure.
    pub structure: Structure,
    /// The beds (a column's grains are beds of their own), in order.
    pub dampers: Vec<Damper>,
    /// 0-based driven mass.
    pub driven: usize,
    /// Force amplitude `F` of `F sin(omega t)`, N (0 for free motion or moving supports).
    pub force: f64,
    /// Harmonic motion of the supports, instead of the force (docs/model.md section 2.3): the
    /// simulator's coordinates then follow the supports at the hosts
    /// ([`crate::model::base`]).
    pub base: Option<BaseMotion>,
    /// Each bed's impact law, in the order of `dampers`; a bed without one is plastic (the
    /// paper's assumption), so an empty list is the paper's system.
    pub laws: Vec<super::bed::ImpactLaw>,
    /// Beds that are the grains of one column (docs/model.md, "Bed models"): consecutive,
    /// disjoint ranges of `dampers`, bottom grain first, each grain with the same host,
    /// clearance, mass and impact law. A bed in no range is a single bed. Empty: the paper's
    /// one mass per container.
    pub columns: Vec<std::ops::Range<usize>>,
}

impl System {
    /// A system with plastic impacts.
    pub fn plastic(structure: Structure, dampers: Vec<Damper>, driven: usize, force: f64) -> System {
        System { structure, dampers, driven, force, base: None, laws: Vec::new(), columns: Vec::new() }
    }

    /// The drive's amplitude that responses are given per: the force, N, or on moving
    /// supports their acceleration, m/s^2.
    pub fn drive(&self) -> f64 {
        self.base.as_ref().map_or(self.force, |b| b.accel)
    }

    /// The same system driven by its supports accelerating as `accel sin(omega t)` (m/s^2)
    /// instead of its force ([`BaseMotion::of`]: every coordinate translating with them, or as
    /// the structure's [`crate::model::base::Supports`] say).
    pub fn on_supports(mut self, accel: f64) -> System {
        self.force = 0.0;
        self.base = Some(BaseMotion::of(&self.structure, accel));
        self
    }

    /// The same system with bed `j` split into a column of `grains[j]` equal grains (total
    /// mass, host, clearance and law unchanged; 1 keeps a single bed). Columns already given
    /// are replaced.
    pub fn with_grains(mut self, grains: &[usize]) -> System {
        let mut dampers = Vec::new();
        let mut laws = Vec::new();
        let mut columns = Vec::new();
        for (j, d) in self.dampers.iter().enumerate() {
            let n = grains.get(j).copied().unwrap_or(1).max(1);
            let law = self.impact_law(j);
            if n > 1 {
                columns.push(dampers.len()..dampers.len() + n);
            }
            for _ in 0..n {
                dampers.push(Damper { mass: d.mass / n as f64, ..*d });
                laws.push(law);
            }
        }
        self.dampers = dampers;
        self.laws = laws;
        self.columns = columns;
        self
    }

    /// The column bed `j` is a grain of, if any.
    pub fn column_of(&self, j: usize) -> Option<std::ops::Range<usize>> {
        self.columns.iter().find(|c| c.contains(&j)).cloned()
    }

    /// The beds in groups that share a configuration count: each column, and each single bed
    /// alone, in bed order.
    pub fn groups(&self) -> Vec<std::ops::Range<usize>> {
        let mut out = Vec::new();
        let mut j = 0;
        while j < self.dampers.len() {
            let g = self.column_of(j).filter(|c| c.start == j).unwrap_or(j..j + 1);
            j = g.end.max(j + 1);
            out.push(g);
        }
        out
    }

    /// The same system with every bed under `law`.
    pub fn with_law(mut self, law: super::bed::ImpactLaw) -> System {
        self.laws = vec![law; self.dampers.len()];
        self
    }

    /// The impact law of bed `j`.
    pub fn impact_law(&self, j: usize) -> super::bed::ImpactLaw {
        self.laws.get(j).copied().unwrap_or(super::bed::ImpactLaw::PLASTIC)
    }

    /// Number of primary masses.
    pub fn dof(&self) -> usize {
        self.structure.dof()
    }

    /// Mass matrix with the dampers of `mask` attached.
    pub fn mass_matrix(&self, mask: usize) -> DMatrix<f64> {
        let added: Vec<(usize, f64)> = self
            .dampers
            .iter()
            .enumerate()
            .filter(|(j, _)| mask & (1 << j) != 0)
            .map(|(_, d)| (d.host, d.mass))
            .collect();
        self.structure.mass_matrix_with(&added)
    }

    /// Constant load of `mask`: the weights of the attached beds, `-sum m_dj g e_pj`.
    pub fn weight_load(&self, mask: usize) -> DVector<f64> {
        let mut w = DVector::zeros(self.dof());
        for (j, d) in self.dampers.iter().enumerate() {
            if mask & (1 << j) != 0 {
                w[d.host] -= d.mass * d.gravity();
            }
        }
        w
    }
}

/// A mask of configuration `slot`: in each group, its first beds attached.
fn representative(groups: &[std::ops::Range<usize>], slot: usize) -> usize {
    let mut rest = slot;
    let mut mask = 0;
    for g in groups {
        let count = rest % (g.len() + 1);
        rest /= g.len() + 1;
        mask |= ((1usize << count) - 1) << g.start;
    }
    mask
}

/// Columns are consecutive disjoint ranges of equal grains.
fn check_columns(system: &System) -> Result<(), SetupError> {
    let mut end = 0;
    let mut sorted: Vec<&std::ops::Range<usize>> = system.columns.iter().collect();
    sorted.sort_by_key(|c| c.start);
    for c in sorted {
        let bad = c.is_empty()
            || c.start < end
            || c.end > system.dampers.len()
            || system.dampers[c.clone()].iter().any(|d| *d != system.dampers[c.start])
            || c.clone().any(|j| system.impact_law(j) != system.impact_law(c.start));
        if bad {
            return Err(SetupError::Column { first: c.start });
        }
        end = c.end;
    }
    Ok(())
}

/// Why dynamics could not be set up.
#[derive(Debug, Clone, PartialEq)]
pub enum SetupError {
    /// A configuration's state matrix has no complete set of eigenvectors.
    Defective {
        /// The configuration.
        mask: usize,
    },
    /// The dynamic stiffness is singular at the forcing frequency (undamped resonance).
    Singular {
        /// The configuration.
        mask: usize,
    },
    /// More degrees of freedom than the closed form supports ([`MAX_DOF`]).
    TooLarge {
        /// Masses given.
        masses: usize,
    },
    /// More single beds than [`MAX_BEDS`], or more configurations than [`config_limit`].
    TooManyBeds {
        /// Beds given.
        beds: usize,
        /// Degrees of freedom of the structure.
        dof: usize,
    },
    /// A column whose grains differ (host, clearance, mass or law), overlap another, or leave
    /// the bed list.
    Column {
        /// First bed of the column.
        first: usize,
    },
    /// The decomposition cannot be trusted: an eigenvalue grows (a passive structure has
    /// none) or the eigenvectors are nearly dependent (condition number given).
    IllConditioned {
        /// The configuration.
        mask: usize,
        /// Condition number of the eigenvectors.
        condition: f64,
    },
}

impl std::fmt::Display for SetupError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SetupError::Defective { mask } => {
                write!(f, "configuration {mask:#b}: state matrix is defective")
            }
            SetupError::Singular { mask } => {
                write!(f, "configuration {mask:#b}: dynamic stiffness is singular at the forcing frequency")
            }
            SetupError::IllConditioned { mask, condition } => write!(
                f,
                "configuration {mask:#b}: numerically singular (eigenvector condition {condition:.1e}, or a growing mode): masses, stiffnesses or damping differ by too many orders of magnitude"
            ),
            SetupError::TooLarge { masses } => {
                write!(f, "{masses} degrees of freedom: the simulator supports at most {MAX_DOF}")
            }
            SetupError::TooManyBeds { beds, dof } => {
                write!(f, "{beds} beds on {dof} degrees of freedom: the simulator supports at most {MAX_BEDS} single beds and {} configurations (counting each column of grains as its grains + 1) on this many degrees of freedom (it decomposes every configuration)", config_limit(*dof))
            }
            SetupError::Column { first } => {
                write!(f, "the column starting at bed {first}: its grains must be consecutive beds with one host, clearance, mass and law, and columns may not overlap")
            }
        }
    }
}

impl std::error::Error for SetupError {}

/// The frequency-independent part of one configuration: its decomposition, shared by every
/// forcing frequency of a sweep (cloning [`Dynamics`] at another frequency copies a pointer).
#[derive(Debug)]
pub struct Modes {
    /// Representative eigenvalues of the first-order state matrix.
    pub lambda: Vec<Complex64>,
    /// `vl[p][m][r] = w_r V[p, r] lambda_r^m`: displacement rows of the eigenvectors.
    pub vl: Vec<[Vec<Complex64>; ORDERS]>,
    /// `|vl|`, for derivative bounds.
    pub vl_abs: Vec<[Vec<f64>; ORDERS]>,
    /// The displacement and velocity rows of `vl` by term: `by_term[order][part][r * n + p]`
    /// is the real (`part` 0) or imaginary (1) part of `vl[p][order][r]`, so that a point's
    /// every displacement or velocity is summed term by term for all masses at once
    /// ([`super::segment::Segment::state_into`]), each in the order [`super::segment::Segment::deriv`] sums.
    pub by_term: [[Vec<f64>; 2]; 2],
    /// The rows of `V^-1` of the representatives.
    pub inverse: DMatrix<Complex64>,
    /// Static offset under the attached beds' weights.
    pub offset: DVector<f64>,
    /// `M` and `M^-1` (accelerations at events).
    pub mass: DMatrix<f64>,
    /// `M^-1`.
    pub mass_inv: DMatrix<f64>,
    /// Largest `|Im lambda|`.
    pub max_rate: f64,
    /// Largest eigen-residual (diagnostics).
    pub residual: f64,
    /// `max |V| max |V^-1|` of the eigenvectors: how much rounding a round trip from a state
    /// to the terms' coefficients and back may grow by.
    pub condition: f64,
    /// Above [`LARGE_ABOVE`] degrees of freedom, each bed's host's rows of the state matrix's
    /// powers (contact decisions, [`super::contact`]); empty up to it.
    pub host_rows: Vec<super::host_rows::HostRow>,
    /// Above [`LARGE_ABOVE`] degrees of freedom, the real and imaginary parts of `inverse`
    /// (the linearised flow's blocked products, `sim::orbits::tangent`); empty up to it.
    pub inverse_parts: [DMatrix<f64>; 2],
}

impl Modes {
    /// What its real modal coordinates are made of ([`super::modal`]).
    pub fn coordinates(&self) -> super::modal::Coordinates<'_> {
        super::modal::Coordinates {
            n: self.vl.len(),
            terms: self.lambda.len(),
            by_term: &self.by_term,
            inverse_parts: &self.inverse_parts,
        }
    }
}

/// Closed-form dynamics of one configuration (its forced part at the dynamics' frequency is
/// [`Dynamics::forced`]):
/// `x(t) = sum_r w_r Re(V_r c_r e^{lambda_r (t - t0)}) + P cos(omega t) + Q sin(omega t) + s`,
/// summed over one eigenvalue of each conjugate pair (weight 2) and the real ones (weight 1).
#[derive(Debug, Clone)]
pub struct Config {
    /// The configuration: bit `j` set when bed `j` rides its host.
    pub mask: usize,
    /// The decomposition (does not depend on the forcing frequency).
    pub modes: Arc<Modes>,
}

/// Degrees of freedom above which the simulator runs its rules for large structures: contact
/// accelerations counted as zero up to the closed form's rounding, one contact decision per
/// event (`sim::motion::engine`) and the event search's coarse windows (`sim::motion::coarse`). Up to it the
/// paper's structures run the code they always ran, bit for bit.
pub const LARGE_ABOVE: usize = 8;

/// The event search's step as a fraction of [`Dynamics::min_period`] (the engine's default;
/// [`Dynamics::window_step`] holds the factors of this step).
pub const STEP_FRACTION: f64 = 0.125;

/// The factors `e^{lambda_r dt}` of one configuration and the forcing's rotation by `omega dt`,
/// which carry a point of a segment `dt` later by multiplication alone (no exponential, sine or
/// cosine): for runs of equally spaced points.
#[derive(Debug, Clone)]
pub struct Step {
    /// The spacing, s.
    pub dt: f64,
    /// Number of terms.
    pub len: usize,
    /// `e^{lambda_r dt}`.
    pub factor: Terms<Complex64>,
    /// `|e^{lambda_r dt}|`.
    pub decay: Terms<f64>,
    /// `sin(omega dt)`.
    pub sin: f64,
    /// `cos(omega dt)`.
    pub cos: f64,
}

/// Most coarse levels (windows of up to `2^MAX_LEVELS` ordinary steps).
pub const MAX_LEVELS: usize = 12;

/// The coarse windows of one configuration (the event search's, `sim::motion::coarse`).
#[derive(Debug, Clone, Default)]
pub struct Levels {
    /// Level `k + 1`'s window (`2^(k+1)` ordinary steps) and the factors that carry a point
    /// by it.
    pub steps: Vec<Step>,
    /// How many of the terms (ordered by `|lambda|`) are slow at level `k + 1`: `|lambda| <=
    /// max_rate / 2^(k+1)`, `max_rate` the fastest rate of every configuration.
    pub slow: Vec<usize>,
}

impl Levels {
    /// The levels of configuration `slot`: none up to [`LARGE_ABOVE`] degrees of freedom or
    /// where the forcing is the fastest rate; else every level whose window is at most an
    /// eighth of the forcing period (and at most [`MAX_LEVELS`]).
    fn of(d: &Dynamics, slot: usize) -> Levels {
        if d.dof <= LARGE_ABOVE {
            return Levels::default();
        }
        let max_rate = 2.0 * std::f64::consts::PI / d.min_period;
        let lambda = &d.configs[slot].modes.lambda;
        let mut levels = Levels::default();
        for k in 1..=MAX_LEVELS {
            let rate = max_rate / (1u64 << k) as f64;
            if rate < d.omega {
                break;
            }
            let slow = lambda.iter().take_while(|l| l.norm() <= rate).count();
            levels.steps.push(d.step(slot, d.min_period * STEP_FRACTION * (1u64 << k) as f64));
            levels.slow.push(slow);
        }
        levels
    }

    /// Whether there is no level.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }
}

/// What [`super::forced::forced_modal`] reads of a configuration's decomposition.
fn modal_parts(m: &Modes) -> ModalParts<'_> {
    ModalParts { lambda: &m.lambda, inverse: &m.inverse, rows: &m.by_term[0], mass: &m.mass, mass_inv: &m.mass_inv }
}

/// All configurations of a system at one forcing frequency.
#[derive(Debug, Clone)]
pub struct Dynamics {
    /// The system (shared by the dynamics at every frequency).
    pub system: Arc<System>,
    /// Forcing frequency, rad/s (any positive value for free motion).
    pub omega: f64,
    /// Every configuration, numbered by [`Dynamics::slot`].
    pub configs: Vec<Config>,
    /// Degrees of freedom.
    pub dof: usize,
    /// The forced response of every configuration at every mass, configuration by
    /// configuration ([`Dynamics::forced`]): one buffer for all, so that the dynamics at
    /// another frequency costs one allocation.
    forced: Vec<Forced>,
    /// Moving supports: the load's phasor on every coordinate (`f(t) = Im(F e^{i omega t})`,
    /// [`BaseMotion::load_phasor`]); empty under a force.
    pub(super) load: Vec<Complex64>,
    /// Moving supports: the amplitude `X_g` of their displacement `X_g sin(omega t)`, m (0
    /// under a force).
    pub support: f64,
    /// Stiffness and damping (shared by all configurations).
    pub k: Arc<DMatrix<f64>>,
    /// Damping matrix, N s/m.
    pub c: Arc<DMatrix<f64>>,
    /// Shortest natural or forcing period over all configurations, s.
    pub min_period: f64,
    /// `omega^m` for the derivative orders.
    pub omega_pow: [f64; ORDERS],
    /// The beds grouped as [`System::groups`]; a configuration is numbered by how many beds of
    /// each group are attached ([`Dynamics::slot`]).
    pub groups: Arc<Vec<std::ops::Range<usize>>>,
    /// Per configuration, the factors of the event search's default step
    /// (`STEP_FRACTION * min_period`), computed when first needed.
    window: Vec<std::sync::OnceLock<Step>>,
    /// Per configuration, the event search's coarse windows above [`LARGE_ABOVE`] degrees
    /// of freedom ([`Levels`]), computed when first needed.
    coarse: Vec<std::sync::OnceLock<Levels>>,
    /// The changes of modal coordinates between configurations (the linearised flow's,
    /// above [`LARGE_ABOVE`] degrees of freedom), shared by every forcing frequency.
    transfers: Arc<super::modal::Transfers>,
}

impl Dynamics {
    /// Decomposes all 2^N configurations and adds the forced response at `omega`.
    pub fn new(system: &System, omega: f64) -> Result<Dynamics, SetupError> {
        Dynamics::unforced(system)?.at_omega(omega)
    }

    /// The same system forced at another frequency: only the forced response is computed
    /// again (the decompositions do not depend on the frequency), so a sweep or a
    /// continuation in frequency decomposes once. Identical to [`Dynamics::new`] at `omega`.
    pub fn at_omega(&self, omega: f64) -> Result<Dynamics, SetupError> {
        let n = self.dof;
        let configs = self.configs.clone();
        let mut forced = vec![Forced::default(); n * configs.len()];
        let (load, d_load) = match &self.system.base {
            Some(b) => b.load_phasor(&self.k, &self.c, &self.system.structure.mass_matrix(), omega),
            None => (Vec::new(), Vec::new()),
        };
        let drive = match self.system.base {
            Some(_) => Some(Drive::Load(&load, &d_load)),
            None => (self.system.force != 0.0).then_some(Drive::Point(self.system.driven, self.system.force)),
        };
        if let Some(drive) = drive {
            for (cfg, out) in configs.iter().zip(forced.chunks_exact_mut(n.max(1))) {
                // Large structures from the decomposition (O(n^2)); the paper's by elimination.
                let done = match n > LARGE_ABOVE {
                    true => {
                        super::forced::forced_modal((&self.k, &self.c), &modal_parts(&cfg.modes), omega, drive, out)
                    }
                    false => forced_into(&self.k, &self.c, &cfg.modes.mass, omega, drive, out),
                };
                done.ok_or(SetupError::Singular { mask: cfg.mask })?;
            }
        }
        let support = self.system.base.as_ref().map_or(0.0, |b| b.displacement(omega));
        let max_rate = configs.iter().map(|c| c.modes.max_rate).fold(omega, f64::max);
        let window = vec![std::sync::OnceLock::new(); configs.len()];
        let coarse = vec![std::sync::OnceLock::new(); configs.len()];
        Ok(Dynamics {
            system: Arc::clone(&self.system),
            omega,
            configs,
            dof: n,
            forced,
            load,
            support,
            k: Arc::clone(&self.k),
            c: Arc::clone(&self.c),
            min_period: 2.0 * std::f64::consts::PI / max_rate,
            omega_pow: std::array::from_fn(|m| omega.powi(m as i32)),
            groups: Arc::clone(&self.groups),
            window,
            coarse,
            transfers: Arc::clone(&self.transfers),
        })
    }

    /// Decomposes all 2^N configurations once, without forcing (frequency 0; use
    /// [`Dynamics::at_omega`] to force it).
    pub fn unforced(system: &System) -> Result<Dynamics, SetupError> {
        let omega = 0.0;
        let n = system.dof();
        if n > MAX_DOF {
            return Err(SetupError::TooLarge { masses: n });
        }
        check_columns(system)?;
        let groups = system.groups();
        let limit = config_limit(n);
        let slots = configurations(groups.iter().map(|g| g.len()), limit);
        let Some(slots) = slots.filter(|_| system.dampers.len() <= MAX_GRAINS) else {
            return Err(SetupError::TooManyBeds { beds: system.dampers.len(), dof: n });
        };
        let k = system.structure.stiffness.clone();
        let c = system.structure.damping.clone();
        let k_inv = k.clone().try_inverse().ok_or(SetupError::Singular { mask: 0 })?;
        let mut configs = Vec::with_capacity(slots);
        for slot in 0..slots {
            let mask = representative(&groups, slot);
            let modes = configuration(system, mask, &k, &c, &k_inv)?;
            configs.push(Config { mask, modes: Arc::new(modes) });
        }
        let max_rate = configs.iter().map(|c| c.modes.max_rate).fold(omega, f64::max);
        let configs_len = configs.len();
        Ok(Dynamics {
            system: Arc::new(system.clone()),
            omega,
            forced: vec![Forced::default(); n * configs.len()],
            load: Vec::new(),
            support: 0.0,
            configs,
            dof: n,
            k: Arc::new(k),
            c: Arc::new(c),
            min_period: 2.0 * std::f64::consts::PI / max_rate,
            omega_pow: std::array::from_fn(|m| omega.powi(m as i32)),
            groups: Arc::new(groups),
            window: vec![std::sync::OnceLock::new(); configs_len],
            coarse: vec![std::sync::OnceLock::new(); configs_len],
            transfers: Arc::new(super::modal::Transfers::new(configs_len, n > LARGE_ABOVE)),
        })
    }

    /// The number of the configuration in which the beds of `mask` are attached: the mask
    /// itself without columns; with columns, the count of attached grains of each column
    /// (which grains does not matter: they are equal).
    #[inline]
    pub fn slot(&self, mask: usize) -> usize {
        if self.system.columns.is_empty() {
            return mask;
        }
        let mut slot = 0;
        let mut scale = 1;
        for g in self.groups.iter() {
            let bits = (mask >> g.start) & ((1usize << g.len()) - 1);
            slot += scale * bits.count_ones() as usize;
            scale *= g.len() + 1;
        }
        slot
    }

    /// The factors that carry a point of configuration `slot` by `dt` ([`Step`]).
    pub fn step(&self, slot: usize, dt: f64) -> Step {
        let cfg = &self.configs[slot];
        let len = cfg.modes.lambda.len();
        let mut factor = Terms::<Complex64>::zeros(len);
        let mut decay = Terms::<f64>::zeros(len);
        for ((f, e), l) in factor.iter_mut().zip(decay.iter_mut()).zip(&cfg.modes.lambda) {
            *e = (l.re * dt).exp();
            let (si, co) = (l.im * dt).sin_cos();
            *f = Complex64::new(*e * co, *e * si);
        }
        let (sin, cos) = (self.omega * dt).sin_cos();
        Step { dt, len, factor, decay, sin, cos }
    }

    /// The factors of the event search's default step in configuration `slot`.
    pub fn window_step(&self, slot: usize) -> &Step {
        self.window[slot].get_or_init(|| self.step(slot, self.min_period * STEP_FRACTION))
    }

    /// The event search's coarse windows in configuration `slot` ([`Levels`];
    /// none up to [`LARGE_ABOVE`] degrees of freedom).
    pub fn levels(&self, slot: usize) -> &Levels {
        self.coarse[slot].get_or_init(|| Levels::of(self, slot))
    }

    /// The change of real modal coordinates from configuration `from` to `to` (slots,
    /// [`super::modal`]), formed when first needed; `None` where transfers are not kept.
    pub fn transfer(&self, from: usize, to: usize) -> Option<&DMatrix<f64>> {
        self.transfers.get(from, to, |slot| self.configs[slot].modes.coordinates())
    }

    /// The configuration in which the beds of `mask` are attached.
    #[inline]
    pub fn config(&self, mask: usize) -> &Config {
        &self.configs[self.slot(mask)]
    }

    /// The forced response of configuration `slot` at every mass.
    #[inline]
    pub fn forced(&self, slot: usize) -> &[Forced] {
        &self.forced[slot * self.dof..(slot + 1) * self.dof]
    }
}

/// The closed form of configuration `mask` (the beds of its bits attached to their hosts):
/// the state matrix's eigenpairs, refused where nearly dependent eigenvectors or a growing
/// mode make the closed form meaningless, with what the event search needs of them.
fn configuration(
    system: &System,
    mask: usize,
    k: &DMatrix<f64>,
    c: &DMatrix<f64>,
    k_inv: &DMatrix<f64>,
) -> Result<Modes, SetupError> {
    let n = system.dof();
    let m = system.mass_matrix(mask);
    let m_inv = m.clone().try_inverse().ok_or(SetupError::Singular { mask })?;
    let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
    let mk = -&m_inv * k;
    let mc = -&m_inv * c;
    for i in 0..n {
        a[(i, n + i)] = 1.0;
        for j in 0..n {
            a[(n + i, j)] = mk[(i, j)];
            a[(n + i, n + j)] = mc[(i, j)];
        }
    }
    // Above LARGE_ABOVE degrees of freedom the eigenpairs come from the second-order
    // problem ([`eigen::decompose_second_order`]: a stiff structure's state matrix
    // leaves the slow modes' vectors inconsistent); the paper's structures keep the
    // state matrix's own, bit for bit.
    let eig = match n > LARGE_ABOVE {
        true => eigen::decompose_second_order(&a, &m, c, k),
        false => eigen::decompose(&a),
    }
    .ok_or(SetupError::Defective { mask })?;
    // A passive structure has no growing mode; nearly dependent eigenvectors make the
    // closed form meaningless (e.g. one mass 1e20 times another).
    let rate = eig.values.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let condition = eig.vectors.iter().map(|z| z.norm()).fold(0.0, f64::max)
        * eig.inverse.iter().map(|z| z.norm()).fold(0.0, f64::max);
    if condition.is_nan() || condition >= MAX_CONDITION || eig.values.iter().any(|l| l.re > 1e-9 * rate) {
        return Err(SetupError::IllConditioned { mask, condition });
    }
    // Above LARGE_ABOVE degrees of freedom the terms are ordered by |lambda| (slowest
    // first): the event search's coarse windows sum the slow ones as a prefix
    // (`sim::motion::coarse`). The paper's structures keep the decomposition's own order.
    let mut reps = eig.representatives.clone();
    if n > LARGE_ABOVE {
        reps.sort_by(|a, b| eig.values[a.0].norm().total_cmp(&eig.values[b.0].norm()));
    }
    let reps = &reps;
    let vl: Vec<[Vec<Complex64>; ORDERS]> = (0..n)
        .map(|p| {
            std::array::from_fn(|order| {
                reps.iter().map(|&(kk, w)| eig.vectors[(p, kk)] * eig.values[kk].powu(order as u32) * w).collect()
            })
        })
        .collect();
    let inverse = DMatrix::from_fn(reps.len(), 2 * n, |r, j| eig.inverse[(reps[r].0, j)]);
    let lambda: Vec<Complex64> = reps.iter().map(|&(kk, _)| eig.values[kk]).collect();
    let vl_abs =
        vl.iter().map(|rows| std::array::from_fn(|order| rows[order].iter().map(|z| z.norm()).collect())).collect();
    // The forced response (K - omega^2 M + i omega C) X = F e_k, x_p = Im(X e^{i omega t}),
    // is added by `at_omega`.
    let offset = k_inv * system.weight_load(mask);
    let max_rate = eig.values.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let host_rows = match n > LARGE_ABOVE {
        true => super::host_rows::host_rows(&a, &m_inv, system.dampers.iter().map(|d| d.host)),
        false => Vec::new(),
    };
    let by_term = std::array::from_fn(|order| {
        std::array::from_fn(|part| {
            let mut out = vec![0.0; reps.len() * n];
            for (p, rows) in vl.iter().enumerate() {
                for (r, z) in rows[order].iter().enumerate() {
                    out[r * n + p] = if part == 0 { z.re } else { z.im };
                }
            }
            out
        })
    });
    let inverse_parts = match n > LARGE_ABOVE {
        true => [inverse.map(|z| z.re), inverse.map(|z| z.im)],
        false => [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)],
    };
    Ok(Modes {
        lambda,
        by_term,
        vl,
        vl_abs,
        inverse,
        inverse_parts,
        offset,
        mass: m,
        mass_inv: m_inv,
        max_rate,
        residual: eig.residual,
        condition,
        host_rows,
    })
}

#[cfg(test)]
mod tests;
