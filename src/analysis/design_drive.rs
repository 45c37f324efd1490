//! A design's drive level (docs/design.md, "Drive level"): how hard the structure shakes at the
//! containers' hosts, bare and with the shot, and whether the beds then move at all. Beds that
//! never leave their containers only add mass, and an optimiser will happily "find" a layout
//! that merely detunes the structure: the table says so, and the warnings name the force that
//! would make the beds work.

use crate::design::{Evaluation, Layout, Problem};
use crate::model::GRAVITY;
use crate::number::fmt_sig;
use crate::table::Table;

/// Share of a band's steady states below which the beds count as hardly moving.
pub const FEW: f64 = 0.1;

/// The largest `(2 pi f)^2 x amplitude / g` of `hosts` over a band (`curves`: per frequency and
/// mass, compliance in m/N; `force` the force amplitude, N).
fn peak_g(curves: &[Vec<f64>], freq_hz: &[f64], hosts: &[usize], force: f64) -> f64 {
    curves
        .iter()
        .zip(freq_hz)
        .flat_map(|(row, f)| {
            let w = 2.0 * std::f64::consts::PI * f;
            hosts.iter().map(move |&h| w * w * row[h] * force / GRAVITY)
        })
        .fold(0.0, f64::max)
}

/// The largest displacement amplitude of the masses the bands read, m (with its band,
/// frequency and mass), and the largest `(2 pi f)^2 x amplitude / g` among them, over the
/// bands' curves (`curves`: per band, frequency and mass, compliance per unit of `force`).
fn peaks(bands: &[crate::design::Band], curves: &[Vec<Vec<f64>>], force: f64) -> (f64, (usize, f64, usize), f64) {
    let mut x = (0.0, (0, f64::NAN, 0));
    let mut g = 0.0f64;
    for (b, (band, rows)) in bands.iter().zip(curves).enumerate() {
        for (f, row) in band.freq_hz.iter().zip(rows) {
            let w = 2.0 * std::f64::consts::PI * f;
            for &m in &band.masses {
                let amp = row.get(m).copied().unwrap_or(f64::NAN) * force;
                if amp > x.0 {
                    x = (amp, (b, *f, m));
                }
                g = g.max(w * w * amp / GRAVITY);
            }
        }
    }
    (x.0, x.1, g)
}

/// The engineer's quantities of the answer at the design's drive: the largest displacement
/// amplitude in mm and acceleration in g of the masses the bands read, with the shot and bare.
fn quantities(problem: &Problem, eval: &Evaluation, bare: &[Vec<Vec<f64>>], force: f64) -> String {
    let (x, (b, f, m), g) = peaks(&problem.bands, &eval.curves, force);
    let (x0, (b0, f0, m0), g0) = peaks(&problem.bands, bare, force);
    if !(x > 0.0 && x0 > 0.0) {
        return String::new();
    }
    let relative = if problem.supports { " relative to the supports" } else { "" };
    let displacement = format!(
        " Its largest displacement amplitude{relative} is {} mm (m{} at {} Hz, {}) against {} mm bare (m{} at {} Hz, {})",
        fmt_sig(1e3 * x, 3),
        m + 1,
        fmt_sig(f, 3),
        problem.bands[b].name,
        fmt_sig(1e3 * x0, 3),
        m0 + 1,
        fmt_sig(f0, 3),
        problem.bands[b0].name,
    );
    // On moving supports the floors' absolute accelerations follow (design_storeys).
    if problem.supports {
        return displacement + ".";
    }
    format!(
        "{displacement}, and its largest acceleration, (2 pi f)^2 times the amplitude, {} g against {} g bare (the smooth part of the motion: each landing jumps the host's velocity, a spike the plastic-impact model does not resolve).",
        fmt_sig(g, 2),
        fmt_sig(g0, 2)
    )
}

/// A row of the table: layout, band, hosts, bare g, g, lift-off points, points, flight mm.
type Row = (String, String, String, f64, f64, i64, i64, f64);

/// One layout to report on: its label, the layout and its evaluation.
pub type Rated<'a> = (String, &'a Layout, &'a Evaluation);

/// The drive-level table of `layouts` (the best first) over each band of `problem`, with
/// `bare` the bare structure's curves per band (the first scenario's, as the layouts' curves),
/// and the warnings about the first layout: bands where its beds lift off at few of the
/// steady states, and its unsettled points.
pub fn drive(problem: &Problem, bare: &[Vec<Vec<f64>>], layouts: &[Rated<'_>]) -> (Table, Vec<String>) {
    let force = problem.cases()[0].force;
    // Moving supports: the hosts' acceleration relative to them, plus their own (a bound).
    let lift = if problem.supports { force / GRAVITY } else { 0.0 };
    let mut rows: Vec<Row> = Vec::new();
    let mut warnings = Vec::new();
    for (k, (label, layout, eval)) in layouts.iter().enumerate() {
        let hosts = &layout.hosts;
        let words = hosts.iter().map(|h| format!("m{}", h + 1)).collect::<Vec<_>>().join(" ");
        for (b, band) in problem.bands.iter().enumerate() {
            let bare_g = bare.get(b).map_or(f64::NAN, |c| peak_g(c, &band.freq_hz, hosts, force) + lift);
            let with_g = eval.curves.get(b).map_or(f64::NAN, |c| peak_g(c, &band.freq_hz, hosts, force) + lift);
            let m = eval.motion.get(b).copied().unwrap_or_default();
            rows.push((
                label.clone(),
                band.name.clone(),
                words.clone(),
                bare_g,
                with_g,
                m.lifting as i64,
                m.points as i64,
                crate::number::decimal(m.flight_m * 1e3),
            ));
            if k == 0 && m.points > 0 && m.share() < FEW {
                // Below 1 g at the hosts vertical beds cannot lift off: the motion is the
                // stuck structure's, linear in the force, so the force scales exactly to 1 g.
                // (A horizontal bed has no such threshold: it leaves a wall whenever its host
                // decelerates.)
                let vertical = problem.direction == crate::model::Direction::Vertical;
                let need = if vertical && with_g > 0.0 && with_g < 1.0 {
                    format!(
                        "; about {} (now {}) would bring the hosts to 1 g at the peak, where the beds start to move",
                        problem.drive().amount(&fmt_sig(force / with_g, 2)),
                        problem.drive().amount(&fmt_sig(force, 3))
                    )
                } else {
                    String::new()
                };
                warnings.push(format!(
                    "{}, {label}: the beds {} in {} of {} steady states (highest flight {} mm); the hosts reach {} g with the shot, {} g bare: at this drive level the shot mostly adds mass{need}",
                    band.name,
                    if vertical { "lift off" } else { "leave their walls" },
                    m.lifting,
                    m.points,
                    fmt_sig(m.flight_m * 1e3, 2),
                    fmt_sig(with_g, 2),
                    fmt_sig(bare_g, 2),
                ));
            }
        }
        if k == 0 && eval.unsettled > 0 {
            warnings.push(format!(
                "{label}: {} of {} steady states did not settle into a certified orbit ({} of them measured as irregular motion: their compliance is the 95th percentile of the per-period amplitudes, with its interval; {} of those over a short screen only, below their band's peak; design_placements, unsettled_points, measured_points, screened_points)",
                eval.unsettled, eval.points, eval.measured(), eval.screened
            ));
        }
    }
    let table = Table::new(
        "design_drive",
        format!(
            "The drive level of the best layout and the experiment's cases in each band ({} {}): the largest host acceleration, (2 pi f)^2 x amplitude / g at the layout's hosts{}, bare and with the shot (exact for the bare structure and for beds that never lift off, whose motion is linear; the first harmonic's scale otherwise), the steady states in which some bed lifts off (over the band's frequencies and sweeps; the worst scenario's) and the highest flight, mm; beds that lift off in under {} % of them mostly add mass",
            problem.drive().name(),
            problem.drive().amount(&fmt_sig(force, 3)),
            if problem.supports {
                " (the amplitude relative to the supports, plus the supports' own acceleration: a bound on the absolute one)"
            } else {
                ""
            },
            FEW * 100.0
        ),
    )
    .str("layout", rows.iter().map(|r| r.0.clone()).collect())
    .str("band", rows.iter().map(|r| r.1.clone()).collect())
    .str("hosts", rows.iter().map(|r| r.2.clone()).collect())
    .f64("host_g_bare", rows.iter().map(|r| r.3).collect())
    .f64("host_g", rows.iter().map(|r| r.4).collect())
    .i64("lift_off_points", rows.iter().map(|r| r.5).collect())
    .i64("points", rows.iter().map(|r| r.6).collect())
    .f64("max_flight_mm", rows.iter().map(|r| r.7).collect());
    (table, warnings)
}

/// What the answer paragraph reads besides the problem and the best layout.
pub struct AnswerIn<'a> {
    /// The structure's mass a shot mass is stated against, kg ([`crate::experiment::structure_mass`]),
    /// and its words ("mass", "mass moving vertically", a stated mass's); `None`: a full mass matrix, no share
    /// is said.
    pub total_mass: Option<(f64, String)>,
    /// What the clearance profile of the best layout found.
    pub profile: Profile,
    /// On moving supports: the sentence of the storeys' largest drift and floor acceleration
    /// (with a leading space; empty under a force).
    pub storeys: &'a str,
    /// The clearance bounds the profile sampled, mm.
    pub sampled: (f64, f64),
    /// The best layout's objective at other forces, `(force N, objective)` in increasing
    /// force (empty: none evaluated).
    pub levels: &'a [(f64, f64)],
    /// Why the search stopped before its end (the time limit, an interrupt), when it did:
    /// the answer then opens with it.
    pub stopped: Option<&'a str>,
}

/// The clearance profile of the best layout, as the answer reads it: a sentence is written
/// only from a profile that was computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// Not computed (the search stopped before it).
    NotComputed,
    /// Computed: the clearances within 5 % of the best, mm.
    Within(f64, f64),
    /// Computed: no sampled clearance comes within 5 % of the best (only its own).
    Narrow,
}

/// The design's answer in one paragraph, for the top of its page: where the shot goes, how
/// much, the clearance to the precision the objective allows (the clearances within 5 % of
/// the best), the reduction per band, the drive level it holds at (and at other forces when
/// they were evaluated), unsettled points.
pub fn answer(problem: &Problem, best: &Rated<'_>, inputs: &AnswerIn<'_>, bare: &[Vec<Vec<f64>>]) -> String {
    let total_mass = inputs.total_mass.as_ref();
    let (_, layout, eval) = best;
    let force = problem.cases()[0].force;
    let shot = layout.shot_kg();
    // A container the split left with a vanishing share (1e-17 kg of a quarter kilogram) holds
    // no shot in words.
    let beds: Vec<String> = layout
        .hosts
        .iter()
        .zip(&layout.masses_kg)
        .filter(|(_, m)| **m > 1e-9 * shot)
        .map(|(h, m)| format!("{} kg on m{}", fmt_sig(*m, 2), h + 1))
        .collect();
    let clearances = &layout.clearances_mm;
    let clearance = clearance_words(inputs, clearances);
    // Beds that never reach their lid: every clearance above their highest flight gives the
    // same motion (the lid is never touched), which the answer says rather than a precision.
    let flight_mm = 1e3 * eval.motion.iter().map(|m| m.flight_m).fold(0.0, f64::max);
    let smallest = clearances.iter().copied().fold(f64::INFINITY, f64::min);
    let lid = if flight_mm == 0.0 {
        " The beds never leave their containers' bottoms: the clearance does not change the motion.".to_string()
    } else if flight_mm.is_finite() && flight_mm < smallest {
        format!(
            " The beds fly at most {} mm above their containers' bottoms and never reach the lid: any clearance above {} mm gives the same motion.",
            fmt_sig(flight_mm, 2),
            fmt_sig(flight_mm, 2)
        )
    } else {
        String::new()
    };
    let levels = if inputs.levels.len() > 1 {
        let at: Vec<String> = inputs
            .levels
            .iter()
            // Above 1 to the digits that keep it above 1 (1.03 is not "1").
            .map(|(f, o)| {
                let o = if *o > 1.0 { above_one(*o) } else { fmt_sig(*o, 2) };
                format!("{o} at {}", problem.drive().amount(&fmt_sig(*f, 3)))
            })
            .collect();
        format!(" At other drive levels the same layout gives {} (design_drive_levels).", at.join(", "))
    } else {
        String::new()
    };
    // A drive level at which the shot makes the structure worse than bare leads the answer.
    let worse: Vec<String> = inputs
        .levels
        .iter()
        .filter(|(_, o)| *o > 1.0)
        .map(|(f, o)| {
            format!("{} of the bare structure's at {}", above_one(*o), problem.drive().amount(&fmt_sig(*f, 3)))
        })
        .collect();
    let lead = if worse.is_empty() {
        String::new()
    } else {
        format!(
            "At {} of the {} drive levels evaluated this layout makes the response worse than the bare structure's ({}). ",
            worse.len(),
            inputs.levels.len(),
            worse.join(", ")
        )
    };
    let stop = inputs.stopped.map_or(String::new(), |words| format!("{words} "));
    let bands: Vec<String> = problem
        .bands
        .iter()
        .zip(eval.bands.iter().zip(&eval.bare))
        .map(|(b, (v, bare))| format!("{} {}", b.name, fmt_sig(v / bare, 2)))
        .collect();
    let drive: Vec<String> = problem
        .bands
        .iter()
        .enumerate()
        .map(|(b, band)| {
            let lift = if problem.supports { force / GRAVITY } else { 0.0 };
            let g = bare.get(b).map_or(f64::NAN, |c| peak_g(c, &band.freq_hz, &layout.hosts, force) + lift);
            let m = eval.motion.get(b).copied().unwrap_or_default();
            let moving = match problem.direction {
                crate::model::Direction::Vertical => "lifting",
                crate::model::Direction::Horizontal => "flying",
            };
            format!("{} {} g, beds {moving} in {} of {}", band.name, fmt_sig(g, 2), m.lifting, m.points)
        })
        .collect();
    let along = match problem.direction {
        crate::model::Direction::Vertical => "",
        crate::model::Direction::Horizontal => " in horizontal containers",
    };
    format!(
        "{stop}{lead}Put {}{along} ({} kg{}), {clearance}.{lid} The worst band then reaches {} of the bare structure's (per band: {}).{}{} This holds at a {} of {} (the bare hosts' peak acceleration: {}); the answer depends on the drive level.{levels} {} of {} steady states did not settle.",
        beds.join(", "),
        fmt_sig(shot, 2),
        total_mass.map_or(String::new(), |(m, what)| format!(", {} % of the structure's {what}", fmt_sig(100.0 * shot / m, 2))),
        fmt_sig(eval.objective, 3),
        bands.join(", "),
        quantities(problem, eval, bare, force),
        inputs.storeys,
        problem.drive().name(),
        problem.drive().amount(&fmt_sig(force, 3)),
        drive.join("; "),
        eval.unsettled,
        eval.points
    )
}

/// A ratio above 1 to three significant digits, or more where three would round it to 1
/// (1.0033 is "1.003", not "1", which would not read as worse than bare).
fn above_one(o: f64) -> String {
    (3..=8).map(|d| fmt_sig(o, d)).find(|s| s != "1").unwrap_or_else(|| format!("{o}"))
}

/// The layout's clearance in words, with how the answer varies with it (within 5 % from
/// where to where, a narrow optimum, or not computed); several clearances listed.
fn clearance_words(inputs: &AnswerIn<'_>, clearances: &[f64]) -> String {
    let same = clearances.windows(2).all(|w| w[0] == w[1]);
    match (inputs.profile, same, clearances.first()) {
        (Profile::Within(lo, hi), true, Some(d)) if fmt_sig(lo, 2) == fmt_sig(hi, 2) => format!(
            "clearance {} mm (of the clearances sampled, only {} mm is within 5 % of the best: a narrow optimum)",
            fmt_sig(*d, 2),
            fmt_sig(lo, 2)
        ),
        (Profile::Within(lo, hi), true, Some(d)) => {
            format!(
                "clearance {} mm (of the clearances sampled, those from {} to {} mm are within 5 % of the best)",
                fmt_sig(*d, 2),
                fmt_sig(lo, 2),
                fmt_sig(hi, 2)
            )
        }
        (Profile::Narrow, true, Some(d)) => format!(
            "clearance {} mm (none of the other clearances sampled from {} to {} mm comes within 5 % of it: a narrow optimum)",
            fmt_sig(*d, 2),
            fmt_sig(inputs.sampled.0, 2),
            fmt_sig(inputs.sampled.1, 2)
        ),
        (Profile::NotComputed, true, Some(d)) => {
            format!("clearance {} mm (how the answer varies with the clearance was not computed)", fmt_sig(*d, 2))
        }
        _ => format!("clearances {} mm", clearances.iter().map(|d| fmt_sig(*d, 2)).collect::<Vec<_>>().join(" / ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_acceleration_of_a_harmonic_motion() {
        // 1e-3 m/N at 10 Hz under 2 N: 2 mm amplitude, (20 pi)^2 x 2e-3 = 7.896 m/s^2.
        let curves = vec![vec![0.0, 1e-3], vec![0.0, 5e-4]];
        let g = peak_g(&curves, &[10.0, 12.0], &[1], 2.0);
        let want = (20.0 * std::f64::consts::PI).powi(2) * 2e-3 / GRAVITY;
        assert!((g - want).abs() < 1e-12 * want, "{g} {want}");
        assert_eq!(peak_g(&curves, &[10.0, 12.0], &[0], 2.0), 0.0);
    }

    #[test]
    fn a_ratio_worse_than_bare_never_reads_as_1() {
        assert_eq!(above_one(1.0033107), "1.003");
        assert_eq!(above_one(1.23100279), "1.23");
        assert_eq!(above_one(1.0000001), "1.0000001");
    }

    #[test]
    fn the_largest_amplitude_and_acceleration_over_the_bands_masses() {
        // Two bands; the second reads m1 only: m2's larger compliance there does not count.
        let band = |name: &str, freq_hz: Vec<f64>, masses: Vec<usize>| crate::design::Band {
            name: name.into(),
            freq_hz,
            masses,
        };
        let bands = [band("a", vec![10.0, 12.0], vec![0, 1]), band("b", vec![30.0], vec![0])];
        let curves = vec![vec![vec![1e-4, 2e-4], vec![1e-4, 3e-4]], vec![vec![1e-4, 9e-3]]];
        let (x, at, g) = peaks(&bands, &curves, 2.0);
        assert_eq!((x, at), (6e-4, (0, 12.0, 1)));
        let w = |f: f64| (2.0 * std::f64::consts::PI * f).powi(2);
        assert_eq!(g, (w(30.0) * 2e-4 / GRAVITY).max(w(12.0) * 6e-4 / GRAVITY));
    }
}
