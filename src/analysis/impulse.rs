//! Impulse analyses (Fig. 10b): the free decay of every case after the same kick, its
//! envelopes and decay times, the split of the dissipated energy, the equivalent damping of
//! each mode against its amplitude, and the spectrum of each acceleration.

use std::collections::BTreeMap;

use crate::checks::fmt_num;
use crate::checks::reference::ReferenceStore;
use crate::experiment::{Experiment, PlotKind};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series, VLine};
use crate::model::modal::{symmetric_modes, ModeSummary};
use crate::model::GRAVITY;
use crate::signal::{decay_time, envelope, falling_envelope, log_decrements, spectra, Decrement};
use crate::sim::motion::impulse::{free_response, ImpulseOptions, Kick};
use crate::sim::{EventKind, Stop};
use crate::table::Table;

use super::curves;
pub use super::evidence::Decay;
use super::kind::{Input, Kind, Output};
use super::result::Tick;

/// Horizontal resolution of dense signals in figures (min/max per bin).
const BINS: usize = 1400;

/// Half cycles over which one log decrement is taken (two cycles: impacts make single half
/// cycles scatter).
const DECREMENT_SPAN: usize = 4;

/// An impulse analysis (`kind = "impulse"`): the kick, the spectrum's frequencies and the
/// envelope levels whose decay times are measured.
pub(crate) struct Impulse<'a> {
    pub(crate) options: &'a ImpulseOptions,
    pub(crate) spectrum_hz: &'a [f64],
    pub(crate) levels: &'a [f64],
}

impl Kind for Impulse<'_> {
    fn work(&self, exp: &Experiment, _refs: &ReferenceStore) -> u64 {
        exp.cases.len() as u64
    }

    fn run(&self, i: &Input<'_>) -> Output {
        let (tables, figures, decays, skipped) =
            run(i.exp, i.modes, self.options, self.spectrum_hz, self.levels, i.tick);
        let mut out = Output { tables, figures, decays, ..Output::default() };
        out.missing_cases(i.exp, skipped);
        out
    }
}

/// Decay times of a sampled acceleration at each level (the estimator used for computed
/// histories and reference files alike).
pub fn decay_times(t: &[f64], a: &[f64], levels: &[f64]) -> Vec<Option<f64>> {
    let env = envelope(t, a);
    levels.iter().map(|&l| decay_time(&env, l)).collect()
}

/// Runs every case: tables, figures, each case's decay and the cases that could not be
/// simulated (and why).
fn run(
    exp: &Experiment,
    modes: &[ModeSummary],
    options: &ImpulseOptions,
    spectrum_hz: &[f64],
    levels: &[f64],
    tick: &Tick,
) -> (Vec<Table>, Vec<Figure>, BTreeMap<String, Decay>, Vec<String>) {
    let mut skipped = Vec::new();
    let n = exp.structure.dof();
    let bare = symmetric_modes(&exp.structure.mass_matrix(), &exp.structure.stiffness);
    let mut decays = BTreeMap::new();
    let mut order = Vec::new();
    for case in &exp.cases {
        let sys = curves::system(exp, case);
        let run = match free_response(&sys, options) {
            Ok(run) => run,
            Err(e) => {
                skipped.push(format!("case {} cannot be simulated: {e}", case.id));
                continue;
            }
        };
        tick();
        let s = &run.samples;
        let t = &s.times[..s.a.len()];
        let accelerations: Vec<Vec<f64>> = (0..n).map(|i| s.a.iter().map(|r| r[i]).collect()).collect();
        let envelopes: Vec<Vec<(f64, f64)>> = accelerations.iter().map(|a| envelope(t, a)).collect();
        let signals: Vec<&[f64]> = accelerations.iter().map(Vec::as_slice).collect();
        let spectra = spectra(options.dt, &signals, spectrum_hz);
        let decay_times = envelopes.iter().map(|env| levels.iter().map(|&l| decay_time(env, l)).collect()).collect();
        // Modal coordinates of the bare structure about the rest state, scaled to the
        // displacement of the mass of largest modal amplitude.
        let decrements = modes
            .iter()
            .enumerate()
            .map(|(k, m)| {
                let phi = bare.mass_normalised.column(k);
                let scale = phi[m.reference_mass];
                // The modal coordinate's weights `M0 phi` (lumped: each mass times phi).
                let weights: Vec<f64> = match &exp.structure.coupled_mass {
                    None => (0..n).map(|r| phi[r] * exp.structure.masses[r]).collect(),
                    Some(m0) => (m0 * phi).iter().copied().collect(),
                };
                let q: Vec<f64> =
                    s.x.iter()
                        .map(|x| (0..n).map(|r| weights[r] * (x[r] - run.rest[r])).sum::<f64>() * scale)
                        .collect();
                log_decrements(t, &q, DECREMENT_SPAN)
            })
            .collect();
        let last_liftoff = s
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::LiftOff { .. }))
            .map(|e| e.t)
            .fold(None, |a, t| Some(a.map_or(t, |a: f64| a.max(t))));
        order.push(case.id.clone());
        decays.insert(
            case.id.clone(),
            Decay {
                id: case.id.clone(),
                label: case.label.clone(),
                run,
                envelopes,
                decay_times,
                decrements,
                last_liftoff,
                spectra,
            },
        );
    }
    let list: Vec<&Decay> = order.iter().filter_map(|id| decays.get(id)).collect();
    let tables = tables(exp, modes, &list, options, spectrum_hz, levels);
    let figures = figures(exp, modes, &list, options, spectrum_hz, levels);
    (tables, figures, decays, skipped)
}

fn kick_words(o: &ImpulseOptions) -> String {
    match o.kick {
        Kick::Velocity(v) => {
            format!("an initial velocity of {} m/s given to m{} and the beds resting on it", fmt_num(v), o.mass + 1)
        }
        Kick::Impulse(i) => format!("an impulse of {} N s on m{} and the beds resting on it", fmt_num(i), o.mass + 1),
    }
}

fn level_name(l: f64) -> String {
    format!("t_{}pct", fmt_num(100.0 * l))
}

fn tables(
    exp: &Experiment,
    modes: &[ModeSummary],
    decays: &[&Decay],
    o: &ImpulseOptions,
    spectrum_hz: &[f64],
    levels: &[f64],
) -> Vec<Table> {
    let n = exp.structure.dof();
    let h = histories(exp, decays, o);
    let ev: Vec<(&Decay, &crate::sim::Event)> =
        decays.iter().flat_map(|d| d.run.samples.events.iter().map(move |e| (*d, e))).collect();
    let events = Table::new(
        "events",
        format!(
            "Every event: time (s), {}, kind, relative speed at impact (m/s), kinetic energy lost (J)",
            super::waveform::bed_words(exp)
        ),
    )
    .str("case", ev.iter().map(|(d, _)| d.id.clone()).collect())
    .f64("t", ev.iter().map(|(_, e)| e.t).collect());
    let ev: Vec<(&str, &crate::sim::Event)> = ev.iter().map(|(d, e)| (d.id.as_str(), *e)).collect();
    let events = super::waveform::event_columns(events, exp, &ev);
    // Decay times per case and mass.
    let drows: Vec<(&Decay, usize)> = decays.iter().flat_map(|d| (0..n).map(move |k| (*d, k))).collect();
    let mut decay = Table::new(
        "decay",
        "Envelope of |acceleration| of each mass: first peak (m/s^2) and the time (s) for it to fall for good to each level of the first peak (empty: not within the record)",
    )
    .str("case", drows.iter().map(|(d, _)| d.id.clone()).collect())
    .i64("mass", drows.iter().map(|(_, k)| *k as i64 + 1).collect())
    .f64("first_peak", drows.iter().map(|(d, k)| d.envelopes[*k].first().map_or(f64::NAN, |p| p.1)).collect());
    for (li, &l) in levels.iter().enumerate() {
        decay =
            decay.f64(level_name(l), drows.iter().map(|(d, k)| d.decay_times[*k][li].unwrap_or(f64::NAN)).collect());
    }
    let energy = Table::new(
        "energy",
        "Energy balance over the run (J): the kinetic energy given, the energy left at the end, the viscous loss (integrated), the impact loss (sum over impacts), and the relative residual of the balance",
    )
    .str("case", decays.iter().map(|d| d.id.clone()).collect())
    .f64("initial", decays.iter().map(|d| d.run.initial_energy).collect())
    .f64("remaining", decays.iter().map(|d| d.run.final_energy).collect())
    .f64("viscous_loss", decays.iter().map(|d| d.run.viscous_loss).collect())
    .f64("impact_loss", decays.iter().map(|d| d.run.impact_loss).collect())
    .f64("residual", decays.iter().map(|d| d.run.energy_residual()).collect())
    .str(
        "stop",
        decays
            .iter()
            .map(|d| match &d.run.stop {
                Some(Stop::Chatter { t, events }) => format!("chatter: {events} events before t = {t:.4} s"),
                None => String::new(),
            })
            .collect(),
    );
    let erows: Vec<(&Decay, usize)> =
        decays.iter().flat_map(|d| (0..d.run.remaining.len()).step_by(10).map(move |i| (*d, i))).collect();
    let energy_history = Table::new(
        "energy_history",
        "Energy above the rest state (J) and the energy lost in impacts so far (J), every tenth sample; the viscous loss is the rest",
    )
    .str("case", erows.iter().map(|(d, _)| d.id.clone()).collect())
    .f64("t", erows.iter().map(|(d, i)| d.run.samples.times[*i]).collect())
    .f64("remaining", erows.iter().map(|(d, i)| d.run.remaining[*i]).collect())
    .f64("impact_loss", erows.iter().map(|(d, i)| d.run.impact_loss_until[*i]).collect());
    let zrows: Vec<(&Decay, usize, &Decrement)> = decays
        .iter()
        .flat_map(|d| d.decrements.iter().enumerate().flat_map(move |(k, list)| list.iter().map(move |z| (*d, k, z))))
        .collect();
    let damping = Table::new(
        "damping",
        "Equivalent damping ratio of each mode from the log decrement of its modal coordinate (bare structure's modes) over half cycles: time (s), amplitude at the mass of largest modal amplitude (m), the same as acceleration omega_i^2 q / g, and zeta",
    )
    .str("case", zrows.iter().map(|(d, _, _)| d.id.clone()).collect())
    .i64("mode", zrows.iter().map(|(_, k, _)| *k as i64 + 1).collect())
    .f64("t", zrows.iter().map(|(_, _, z)| z.t).collect())
    .f64("amplitude_m", zrows.iter().map(|(_, _, z)| z.amplitude).collect())
    .f64("acceleration_g", zrows.iter().map(|(_, k, z)| z.amplitude * modes[*k].omega.powi(2) / GRAVITY).collect())
    .f64("zeta", zrows.iter().map(|(_, _, z)| z.zeta).collect());
    let mut spec = Table::new(
        "spectrum",
        "Magnitude of the Fourier transform of each mass's acceleration over the record, |dt sum a_k exp(-i 2 pi f t_k)| (m/s)",
    );
    let srows: Vec<(&Decay, usize)> =
        decays.iter().flat_map(|d| (0..spectrum_hz.len()).map(move |i| (*d, i))).collect();
    spec = spec
        .str("case", srows.iter().map(|(d, _)| d.id.clone()).collect())
        .f64("freq_hz", srows.iter().map(|(_, i)| spectrum_hz[*i]).collect());
    for k in 0..n {
        let col: Vec<f64> = decays.iter().flat_map(|d| d.spectra[k].iter().copied()).collect();
        spec = spec.f64(format!("a{}", k + 1), col);
    }
    vec![h, events, decay, energy, energy_history, damping, spec]
}

/// The histories table: one row per case and sample, every mass's x, v, a and every bed's
/// position and state.
fn histories(exp: &Experiment, decays: &[&Decay], o: &ImpulseOptions) -> Table {
    let n = exp.structure.dof();
    let beds =
        exp.cases.iter().map(|c| c.beds.iter().map(|b| &b.grains).map(|g| g.max(&1)).sum::<usize>()).max().unwrap_or(0);
    // Histories: one row per case and sample.
    let rows: Vec<(&Decay, usize)> =
        decays.iter().flat_map(|d| (0..d.run.samples.a.len()).map(move |i| (*d, i))).collect();
    let mut h = Table::new(
        "histories",
        format!(
            "Free response after {}: time (s), displacement x (m), velocity v (m/s) and acceleration a (m/s^2) of each mass, position y (m) and state (B bottom, T top, F free) of each bed",
            kick_words(o)
        ),
    )
    .str("case", rows.iter().map(|(d, _)| d.id.clone()).collect())
    .f64("t", rows.iter().map(|(d, i)| d.run.samples.times[*i]).collect());
    for (name, pick) in [("x", 0), ("v", 1), ("a", 2)] {
        for k in 0..n {
            h = h.f64(
                format!("{name}{}", k + 1),
                rows.iter()
                    .map(|(d, i)| {
                        let s = &d.run.samples;
                        [&s.x, &s.v, &s.a][pick][*i][k]
                    })
                    .collect(),
            );
        }
    }
    for j in 0..beds {
        h = h
            .f64(
                format!("y{}", j + 1),
                rows.iter().map(|(d, i)| d.run.samples.y[*i].get(j).copied().unwrap_or(f64::NAN)).collect(),
            )
            .str(
                format!("state{}", j + 1),
                rows.iter()
                    .map(|(d, i)| d.run.samples.state[*i].get(j).map(|c| c.to_string()).unwrap_or_default())
                    .collect(),
            );
    }
    h
}

fn figures(
    exp: &Experiment,
    modes: &[ModeSummary],
    decays: &[&Decay],
    o: &ImpulseOptions,
    spectrum_hz: &[f64],
    levels: &[f64],
) -> Vec<Figure> {
    let mut out = Vec::new();
    for p in &exp.plots {
        let span = p.x_range.unwrap_or((0.0, o.duration));
        let title = p.title.clone().unwrap_or_else(|| format!("{}: {}", exp.meta.figure, exp.meta.title));
        let shown: Vec<(usize, &Decay)> =
            decays.iter().enumerate().filter(|(_, d)| p.cases.contains(&d.id)).map(|(i, d)| (i, *d)).collect();
        let (panels, caption) = match p.kind {
            PlotKind::Acceleration => {
                let mut panels = Vec::new();
                for &k in &p.masses {
                    let peak = shown.iter().map(|(_, d)| d.envelopes[k].first().map_or(0.0, |p| p.1)).fold(0.0, f64::max);
                    for &(ci, d) in &shown {
                        let s = &d.run.samples;
                        let a: Vec<f64> = s.a.iter().map(|r| r[k]).collect();
                        let mut panel = Panel::new(format!("m{}, {}", k + 1, d.label), "time (s)", "acceleration (m/s^2)", span);
                        panel.series.push(Series::dense(format!("a{}", k + 1), &s.times[..a.len()], &a, ci, BINS));
                        let env = falling_envelope(&d.envelopes[k]);
                        let (t, v): (Vec<f64>, Vec<f64>) = env.iter().copied().unzip();
                        let neg: Vec<f64> = v.iter().map(|x| -x).collect();
                        panel.series.push(Series::line("envelope", t.clone(), v, 7).dashed(Dash::Dashed));
                        panel.series.push(Series::line("", t, neg, 7).dashed(Dash::Dashed));
                        panel.y_range = Some((-1.08 * peak, 1.08 * peak));
                        panels.push(panel);
                    }
                }
                (
                    panels,
                    format!(
                        "Acceleration after {}, no force, one panel per mass and case on the same scale; dashed: the envelope of |a| as it falls for good (at each peak, the largest peak from then on).",
                        kick_words(o)
                    ),
                )
            }
            PlotKind::Decay => decay_panels(&p.masses, &shown, span, levels),
            PlotKind::Spectrum => (
                p.masses
                    .iter()
                    .map(|&k| {
                        let range = p.x_range.unwrap_or((spectrum_hz[0], spectrum_hz[spectrum_hz.len() - 1]));
                        let mut panel =
                            Panel::new(format!("spectrum of the acceleration of m{}", k + 1), "frequency (Hz)", "|A(f)| (m/s)", range).log_y();
                        for &(ci, d) in &shown {
                            panel.series.push(Series::line(d.label.clone(), spectrum_hz.to_vec(), d.spectra[k].clone(), ci));
                        }
                        panel.vlines = modes
                            .iter()
                            .filter(|m| m.freq_hz >= range.0 && m.freq_hz <= range.1)
                            .map(|m| VLine { x: m.freq_hz, label: format!(" f{} = {:.2} Hz", m.number, m.freq_hz) })
                            .collect();
                        panel
                    })
                    .collect(),
                format!(
                    "Magnitude of the Fourier transform of the decaying acceleration over the {} s record (rectangular window, evaluated every {} Hz); dashed lines: natural frequencies of the bare structure.",
                    fmt_num(o.duration),
                    fmt_num(spectrum_hz.get(1).map_or(0.0, |f| f - spectrum_hz[0]))
                ),
            ),
            PlotKind::Damping => damping_panels(&title, &shown, modes),
            _ => continue,
        };
        out.push(Figure { id: p.id.clone(), title: title.clone(), caption, panels });
    }
    out
}

/// The decay figure's panels: the peaks of |a| and their falling envelope at each mass, with
/// where it reaches each level, and the energy left and lost in impacts; and its caption.
fn decay_panels(masses: &[usize], shown: &[(usize, &Decay)], span: (f64, f64), levels: &[f64]) -> (Vec<Panel>, String) {
    let mut panels: Vec<Panel> = masses
        .iter()
        .map(|&k| {
            let mut panel =
                Panel::new(format!("envelope of |a| at m{}", k + 1), "time (s)", "|a| (m/s^2)", span).log_y();
            for &(ci, d) in shown {
                let (t, v): (Vec<f64>, Vec<f64>) = d.envelopes[k].iter().copied().unzip();
                panel.series.push(Series::points("", t, v, ci, Marker::Cross));
                let (t, v): (Vec<f64>, Vec<f64>) = falling_envelope(&d.envelopes[k]).into_iter().unzip();
                panel.series.push(Series::line(d.label.clone(), t, v, ci));
                let first = d.envelopes[k].first().map_or(f64::NAN, |p| p.1);
                let (tx, ty): (Vec<f64>, Vec<f64>) =
                    levels.iter().zip(&d.decay_times[k]).filter_map(|(l, td)| td.map(|td| (td, l * first))).unzip();
                panel.series.push(Series::points("", tx, ty, ci, Marker::Circle).filled());
            }
            panel
        })
        .collect();
    let mut energy = Panel::new("energy", "time (s)", "energy / energy given", span).log_y();
    for &(ci, d) in shown {
        let s = &d.run.samples;
        let e0 = d.run.initial_energy;
        let r: Vec<f64> = d.run.remaining.iter().map(|e| e / e0).collect();
        energy.series.push(Series::dense(format!("{}: remaining", d.label), &s.times[..r.len()], &r, ci, BINS));
        if d.run.impact_loss > 0.0 {
            let imp: Vec<f64> = d.run.impact_loss_until.iter().map(|e| e / e0).collect();
            energy.series.push(
                Series::dense(format!("{}: lost in impacts", d.label), &s.times[..imp.len()], &imp, ci, BINS)
                    .dashed(Dash::Dashed),
            );
        }
    }
    energy.y_range = Some((1e-4, 1.5));
    panels.push(energy);
    let levels_words: Vec<String> = levels.iter().map(|l| format!("{} %", fmt_num(100.0 * l))).collect();
    (
            panels,
            format!(
                "Peaks of |acceleration| (crosses, log scale) and the envelope as it falls for good (line); filled circles where it reaches {} of its first peak. Bottom: energy above the rest state and the energy lost in impacts, as fractions of the energy given (the viscous loss is the rest).",
                levels_words.join(", ")
            ),
        )
}

/// The damping figure's panel: each mode's equivalent damping ratio against its acceleration
/// amplitude (filled while beds lift off); and its caption.
fn damping_panels(title: &str, shown: &[(usize, &Decay)], modes: &[ModeSummary]) -> (Vec<Panel>, String) {
    let accel = |k: usize, z: &Decrement| z.amplitude * modes[k].omega.powi(2) / GRAVITY;
    let all: Vec<f64> = shown
        .iter()
        .flat_map(|(_, d)| d.decrements.iter().enumerate().flat_map(move |(k, z)| z.iter().map(move |z| accel(k, z))))
        .filter(|a| *a > 0.0)
        .collect();
    let lo = all.iter().copied().fold(f64::INFINITY, f64::min).max(1e-6);
    let hi = all.iter().copied().fold(0.0, f64::max).max(lo * 10.0);
    let mut panel = Panel::new(
        title,
        "acceleration amplitude of the mode, omega_i^2 q_i / g",
        "equivalent damping ratio",
        (lo / 1.3, hi * 1.3),
    )
    .log_x()
    .log_y();
    panel.legend = Corner::LowerLeft;
    panel.y_range = Some((2e-3, 0.3));
    for &(ci, d) in shown {
        for (k, z) in d.decrements.iter().enumerate() {
            let marker = [Marker::Circle, Marker::Square, Marker::Triangle][k % 3];
            let lifting = |z: &&Decrement| d.last_liftoff.is_some_and(|tl| z.t <= tl);
            let part = |keep: bool| -> (Vec<f64>, Vec<f64>) {
                z.iter().filter(|z| z.zeta > 0.0 && lifting(z) == keep).map(|z| (accel(k, z), z.zeta)).unzip()
            };
            let (x, y) = part(false);
            panel.series.push(Series::points(format!("{}, mode {}", d.label, k + 1), x, y, ci, marker));
            let (x, y) = part(true);
            if !x.is_empty() {
                panel.series.push(Series::points("", x, y, ci, marker).filled());
            }
        }
    }
    (
            vec![panel],
            format!(
                "Equivalent damping ratio of each mode from the log decrement of its modal coordinate (modes of the bare structure) over {} half cycles, against the mode's acceleration amplitude at its largest modal displacement, in g. Filled: while beds still lift off; hollow: after the last lift-off, when only the structure's own damping acts (with the beds' mass added). While beds fly, impacts also pass energy between modes, so single values scatter (values outside the axis are in the damping table).",
                DECREMENT_SPAN
            ),
        )
}
