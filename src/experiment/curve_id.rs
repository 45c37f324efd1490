//! Curve identities: the case a computed curve belongs to and which of its curves it is.
//!
//! A curve is named in tables, legends, exports and check names by the text of its
//! [`CurveId`] (`single`, `single:up`, `single:orbits-down`, `triple@0.2mm`); inside the library
//! it is compared as a value, never parsed back from that text.

use std::fmt;

use super::Linear;
use crate::number::fmt_num;
use crate::sim::settle::sweep::Direction;

/// Which of a case's curves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Variant {
    /// The case's only curve: a sweep from rest, or the linear response of a case without
    /// containers. Written as the case id alone.
    #[default]
    Whole,
    /// A continuation sweep in one direction: `CASE:up`, `CASE:down`.
    Continued(Direction),
    /// The orbit branch continued from a continuation sweep's first point:
    /// `CASE:orbits-up`, `CASE:orbits-down`.
    Orbits(Direction),
    /// The case at one scanned clearance, mm: `CASE@0.2mm` (`CASE@inf` without a top).
    Clearance(f64),
    /// A linear reference curve drawn under a sweep: the structure bare (`linear:bare`, one
    /// per experiment) or with the case's damper masses rigidly added (`linear:stuck:CASE`).
    Linear(Linear),
}

/// The identity of a computed curve: its case and which of the case's curves it is.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CurveId {
    /// The case id.
    pub case: String,
    /// Which of the case's curves.
    pub variant: Variant,
}

impl CurveId {
    /// The case's only curve.
    pub fn whole(case: &str) -> Self {
        Self { case: case.into(), variant: Variant::Whole }
    }

    /// A continuation sweep of the case.
    pub fn continued(case: &str, direction: Direction) -> Self {
        Self { case: case.into(), variant: Variant::Continued(direction) }
    }

    /// The orbit branch continued from the case's continuation sweep.
    pub fn orbits(case: &str, direction: Direction) -> Self {
        Self { case: case.into(), variant: Variant::Orbits(direction) }
    }

    /// The case at a scanned clearance, mm.
    pub fn clearance(case: &str, mm: f64) -> Self {
        Self { case: case.into(), variant: Variant::Clearance(mm) }
    }

    /// Whether a compliance plot that lists `case` draws this curve: the case's own curve and
    /// its continuation sweeps (scanned clearances and orbit branches have figures of their own).
    pub fn drawn_for(&self, case: &str) -> bool {
        self.case == case && matches!(self.variant, Variant::Whole | Variant::Continued(_))
    }

    /// A linear reference curve of the case.
    pub fn linear(case: &str, linear: Linear) -> Self {
        Self { case: case.into(), variant: Variant::Linear(linear) }
    }

    /// The scanned clearance, mm, of a clearance study's curve.
    pub fn clearance_mm(&self) -> Option<f64> {
        match self.variant {
            Variant::Clearance(mm) => Some(mm),
            _ => None,
        }
    }
}

/// `up` or `down`.
fn word(direction: Direction) -> &'static str {
    match direction {
        Direction::Up => "up",
        Direction::Down => "down",
    }
}

impl fmt::Display for CurveId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let case = &self.case;
        match self.variant {
            Variant::Whole => write!(f, "{case}"),
            Variant::Continued(d) => write!(f, "{case}:{}", word(d)),
            Variant::Orbits(d) => write!(f, "{case}:orbits-{}", word(d)),
            Variant::Clearance(mm) if mm.is_infinite() => write!(f, "{case}@inf"),
            Variant::Clearance(mm) => write!(f, "{case}@{}mm", fmt_num(mm)),
            Variant::Linear(Linear::Bare) => write!(f, "linear:bare"),
            Variant::Linear(Linear::Stuck) => write!(f, "linear:stuck:{case}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_the_tables_key() {
        assert_eq!(CurveId::whole("D").to_string(), "D");
        assert_eq!(CurveId::continued("single", Direction::Up).to_string(), "single:up");
        assert_eq!(CurveId::continued("single", Direction::Down).to_string(), "single:down");
        assert_eq!(CurveId::orbits("triple", Direction::Down).to_string(), "triple:orbits-down");
        assert_eq!(CurveId::clearance("triple", 0.2).to_string(), "triple@0.2mm");
        assert_eq!(CurveId::clearance("triple", 1.0).to_string(), "triple@1mm");
        assert_eq!(CurveId::clearance("single", f64::INFINITY).to_string(), "single@inf");
        assert_eq!(CurveId::linear("D", Linear::Stuck).to_string(), "linear:stuck:D");
    }

    #[test]
    fn a_case_id_with_the_separators_stays_one_case() {
        // Case ids are free text in a file: a case named "a:up" is not case "a" swept up.
        let odd = CurveId::whole("a:up");
        assert_ne!(odd, CurveId::continued("a", Direction::Up));
        assert!(odd.drawn_for("a:up"));
        assert!(!odd.drawn_for("a"));
        assert!(CurveId::continued("a", Direction::Up).drawn_for("a"));
        assert!(!CurveId::clearance("a", 0.2).drawn_for("a"));
        assert!(!CurveId::orbits("a", Direction::Up).drawn_for("a"));
        assert!(!CurveId::linear("a", Linear::Bare).drawn_for("a"));
    }
}
