use super::{Budget, Point};
use crate::sim::settle::statistic::Motion as Class;

/// Two motions coexist where their intervals do not overlap; certified orbits within
/// rounding of each other are one; a point of one sweep has nothing to compare.
#[test]
fn coexisting_motions_are_those_whose_intervals_do_not_overlap() {
    let p = |lowest: f64, lowest_half_width: f64, half_width: f64| Point {
        class: Class::Chaotic,
        half_width,
        lowest,
        lowest_class: Class::Chaotic,
        lowest_half_width,
    };
    assert_eq!(p(0.8, 0.05, 0.05).coexisting(1.0), Some(true));
    assert_eq!(p(0.8, 0.1, 0.1).coexisting(1.0), Some(false));
    assert_eq!(p(1.0 - 1e-12, 0.0, 0.0).coexisting(1.0), Some(false));
    assert_eq!(p(0.99, 0.0, 0.0).coexisting(1.0), Some(true));
    assert_eq!(p(0.99, f64::NAN, 0.0).coexisting(1.0), None);
    assert_eq!(p(1.0, f64::NAN, 0.0).coexisting(1.0), Some(false));
    assert_eq!(Point::default().coexisting(1.0), Some(false));
}

/// The fastest mode's factor counts up to 8 degrees of freedom and not above, where the
/// event search skips its oscillations.
#[test]
fn the_fast_mode_factor_counts_only_where_the_search_steps_through_it() {
    let b = Budget { placements: 1, searches: 1, evaluations: 10, points: 100, fast: 32.2, screened: (0, 1.0, 0) };
    let per = |n: usize| Budget::seconds_per_point(n);
    assert_eq!(b.nominal_seconds(5, 1), 10.0 * 100.0 * per(5) * 32.2);
    assert_eq!(b.nominal_seconds(47, 1), 10.0 * 100.0 * per(47));
    assert!((per(47) - 0.0368).abs() < 1e-3, "{}", per(47));
}
