//! Numbers as shotdamp compares and shows them: the tolerance of a comparison, and the one
//! way a value is written in tables, checks and file keys. A leaf: it imports nothing of
//! shotdamp, so that experiment files and checks can both use it.

/// A tolerance: pass when `|computed - expected| <= abs + rel |expected|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Relative part.
    pub rel: f64,
    /// Absolute part, in the value's unit.
    pub abs: f64,
}

/// Number formatting shared by tables and checks.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if !v.is_finite() {
        format!("{v}")
    } else if v.abs() >= 1e-3 && v.abs() < 1e5 {
        let s = format!("{v:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.5e}")
    }
}
