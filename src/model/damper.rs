//! One shot damper: a bed of shot in a container on a host mass, the container's clearance
//! and the direction its bed moves in relative to gravity (docs/model.md sections 2 and 5).

use super::{Clearance, GRAVITY};

/// The direction a container's bed moves in, relative to gravity (docs/model.md section 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Direction {
    /// Along gravity (the paper's): the bed rests on the container bottom under its weight,
    /// lifts off when the host accelerates downward faster than g and flies a parabola.
    #[default]
    Vertical,
    /// Across gravity (a container on a swaying floor): no gravity along the motion, the bed
    /// flies at constant velocity between two walls `clearance` apart and hits either
    /// (the classic impact damper); friction with the container floor is neglected.
    Horizontal,
}

impl Direction {
    /// Gravity along the motion, `g_a`, m/s^2: g for a vertical container, 0 for a
    /// horizontal one.
    pub fn gravity(self) -> f64 {
        match self {
            Direction::Vertical => GRAVITY,
            Direction::Horizontal => 0.0,
        }
    }

    /// The name experiment files use: `"vertical"` or `"horizontal"`.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Vertical => "vertical",
            Direction::Horizontal => "horizontal",
        }
    }

    /// The direction named `name` in an experiment file.
    pub fn from_name(name: &str) -> Option<Direction> {
        match name {
            "vertical" => Some(Direction::Vertical),
            "horizontal" => Some(Direction::Horizontal),
            _ => None,
        }
    }

    /// The names allowed, for error messages.
    pub const NAMES: &'static str =
        "the direction a container's bed moves in: \"vertical\" (along gravity, the paper's) or \"horizontal\"";
}

/// One shot damper: a particle bed of mass `mass` in a container on primary mass `host`
/// (0-based) with free travel `clearance` ([`Clearance::NO_TOP`] for no top), moving along
/// `direction`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    /// Host mass index, 0-based.
    pub host: usize,
    /// Bed mass, kg.
    pub mass: f64,
    /// Clearance between bottom and top (between the two walls of a horizontal container).
    pub clearance: Clearance,
    /// The direction the bed moves in relative to gravity.
    pub direction: Direction,
}

impl Damper {
    /// A vertical container (the paper's).
    pub const fn new(host: usize, mass: f64, clearance: Clearance) -> Damper {
        Damper { host, mass, clearance, direction: Direction::Vertical }
    }

    /// The same damper moving along `direction`.
    pub const fn along(self, direction: Direction) -> Damper {
        Damper { direction, ..self }
    }

    /// Gravity along the bed's motion, `g_a`, m/s^2.
    pub fn gravity(&self) -> f64 {
        self.direction.gravity()
    }
}

/// `(host, mass)` pairs of a damper set, for [`super::Structure::mass_matrix_with`].
pub fn added_masses(dampers: &[Damper]) -> Vec<(usize, f64)> {
    dampers.iter().map(|d| (d.host, d.mass)).collect()
}
