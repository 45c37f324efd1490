//! The clearance of a container: the bed's free travel between its bottom and its top.

use std::fmt;

use crate::number::fmt_num;

/// A container's clearance, with its unit in the type.
///
/// Held in millimetres, the unit every experiment file, table and export states clearances
/// in, so a value read from a file is written back exactly as it was given; the physics reads
/// it in metres through [`Clearance::m`]. Infinite: the container has no top.
///
/// ```
/// use shotdamp::model::Clearance;
/// let d = Clearance::from_mm(0.45);
/// assert_eq!(d.mm(), 0.45);
/// assert_eq!(d.m(), 0.45 * 1e-3);
/// assert!(!Clearance::NO_TOP.is_bounded());
/// assert_eq!(d.to_string(), "0.45 mm");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct Clearance {
    mm: f64,
}

impl Clearance {
    /// No top: the bed may fly any height.
    pub const NO_TOP: Self = Self { mm: f64::INFINITY };

    /// A clearance in millimetres.
    pub const fn from_mm(mm: f64) -> Self {
        Self { mm }
    }

    /// A clearance in metres.
    pub fn from_m(m: f64) -> Self {
        Self { mm: m * 1e3 }
    }

    /// In millimetres, exactly as given.
    pub const fn mm(self) -> f64 {
        self.mm
    }

    /// In metres.
    pub fn m(self) -> f64 {
        self.mm * 1e-3
    }

    /// Whether the container has a top.
    pub fn is_bounded(self) -> bool {
        self.mm.is_finite()
    }

    /// Whether bottom and top touch: the bed cannot move in its container.
    pub fn is_zero(self) -> bool {
        self.mm == 0.0
    }
}

/// `0.35 mm`, or `inf` without a top.
impl fmt::Display for Clearance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_bounded() {
            write!(f, "{} mm", fmt_num(self.mm))
        } else {
            write!(f, "inf")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn millimetres_come_back_exactly() {
        // 0.45 mm through metres and back is 0.45000000000000007: held in mm, it is not.
        assert_ne!(0.45 * 1e-3 * 1e3, 0.45);
        for mm in [0.05, 0.1, 0.3, 0.35, 0.45, 0.793221, 2.0] {
            assert_eq!(Clearance::from_mm(mm).mm(), mm);
            assert_eq!(Clearance::from_mm(mm).m(), mm * 1e-3);
        }
        assert_eq!(Clearance::from_m(0.002).mm(), 2.0);
    }

    #[test]
    fn no_top_and_zero() {
        assert!(!Clearance::NO_TOP.is_bounded());
        assert_eq!(Clearance::NO_TOP.m(), f64::INFINITY);
        assert!(Clearance::from_mm(0.0).is_zero());
        assert!(Clearance::from_mm(0.0).is_bounded());
        assert_eq!(Clearance::NO_TOP.to_string(), "inf");
        assert_eq!(Clearance::from_mm(1.0).to_string(), "1 mm");
        assert!(Clearance::from_mm(0.2) < Clearance::from_mm(0.3));
    }
}
