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
        screened: false,
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
    let b = Budget {
        placements: 1,
        searches: 1,
        evaluations: 10,
        points: 100,
        fast: 32.2,
        screened: (0, 1.0, 0),
        expected: [(4, 0), (8, 0), (9, 0), (10, 0)],
    };
    let per = |n: usize| Budget::seconds_per_point(n);
    assert_eq!(b.nominal_seconds(5, 1), 10.0 * 100.0 * per(5) * 32.2);
    assert_eq!(b.nominal_seconds(47, 1), 10.0 * 100.0 * per(47));
    assert!((per(47) - 0.0368).abs() < 1e-3, "{}", per(47));
}

/// A search's usual evaluations lie between what every placement does at the least (its
/// coarse scan and each start's simplex) and its bound, grow with the constant, and the
/// estimate of a screened design counts the searched model's evaluations at their cost and
/// the file's model's at theirs.
#[test]
fn the_usual_evaluations_lie_between_the_least_and_the_bound() {
    use super::search::{dimension, expected_evaluations, most_evaluations, placements, Options, Space, COARSE};
    let space = Space {
        placements: placements(&[0, 1, 2], 3),
        shot_kg: 0.1,
        clearance_mm: (0.1, 10.0),
        shared_clearance: true,
    };
    let opts = Options::default();
    let least: u64 = space
        .placements
        .iter()
        .map(|h| COARSE.len() as u64 + opts.starts as u64 * (dimension(h.len(), &space) as u64 + 1))
        .sum();
    let [low, mid, high] = expected_evaluations(&space, &opts);
    assert!(
        least < low && low < mid && mid < high && high < most_evaluations(&space, &opts),
        "{least} {low} {mid} {high}"
    );
    // The starts of 1, 2 and 3 containers at c = 4: 4 * 4, 4 * 9, 4 * 16 evaluations.
    assert_eq!(mid, 7 * 7 + 3 * (3 * 16 + 3 * 36 + 64));
    let b = Budget {
        placements: 7,
        searches: 1,
        evaluations: 1000,
        points: 10,
        fast: 1.0,
        screened: (900, 1.0, 7),
        expected: [(300, 250), (600, 500), (700, 650), (900, 850)],
    };
    let (lo, hi) = b.expected_seconds(1.0, 10.0, 1, false);
    let (f_lo, f_hi) = Budget::EVALUATION_SPREAD;
    assert_eq!(lo, (250.0 + 50.0 * 10.0) * f_lo);
    assert_eq!(hi, (500.0 + 100.0 * 10.0) * f_hi);
    let unscreened = Budget { screened: (0, 1.0, 0), ..b };
    assert_eq!(unscreened.expected_seconds(1.0, 10.0, 2, false).0, 300.0 * f_lo / 2.0);
    assert_eq!(unscreened.expected_seconds(1.0, 10.0, 2, true).0, 700.0 * f_lo / 2.0);
}

/// A band's half-width is its points': an unknown interval (NaN) stays unknown, never 0 (a
/// certified orbit's); the RMS takes the widest.
#[test]
fn an_unknown_interval_is_not_a_certified_one() {
    use super::{measure_half_width, Band, Measure};
    let band = Band { name: "b".into(), freq_hz: vec![1.0, 2.0], masses: vec![0] };
    let point = |half_width: f64| Point { half_width, ..Point::default() };
    let points = vec![vec![point(0.0)], vec![point(f64::NAN)]];
    assert_eq!(measure_half_width(&band, &points, (0, 0), Measure::Peak), 0.0);
    assert!(measure_half_width(&band, &points, (1, 0), Measure::Peak).is_nan());
    assert!(measure_half_width(&band, &points, (0, 0), Measure::Rms).is_nan());
    let known = vec![vec![point(0.1)], vec![point(0.3)]];
    assert_eq!(measure_half_width(&band, &known, (0, 0), Measure::Rms), 0.3);
}

/// Two evaluations are equal within their intervals where those overlap; one whose interval is
/// not known counts as its objective alone, so it still equals itself.
#[test]
fn an_unknown_interval_overlaps_as_its_value() {
    use super::Evaluation;
    let with =
        |objective: f64, half_width: f64| Evaluation { half_width, ..Evaluation::with_objective(objective, 1, 2) };
    assert!(with(0.5, f64::NAN).overlaps(&with(0.5, f64::NAN)));
    assert!(with(0.5, f64::NAN).overlaps(&with(0.52, 0.03)));
    assert!(!with(0.5, f64::NAN).overlaps(&with(0.52, 0.01)));
    assert!(with(0.5, 0.02).overlaps(&with(0.52, 0.0)));
}
