//! Certified search for the first time an event function reaches zero.
//!
//! From a time `a` a function `h` obeys `h(a + tau) >= L(tau) = c(tau) - B tau^4 / 24`,
//! where `c` is its cubic Taylor polynomial at `a` and `B` bounds the fourth derivative of
//! `h` from `a` on (the event functions are sums of decaying exponentials, sinusoids and
//! parabolas, so `B` comes in closed form). `h` therefore has no root before the first root
//! of the quartic `L`, which is found exactly from the monotone pieces of `L`. The search
//! advances to that root and repeats: it approaches the first root of `h` from the left,
//! quickly near a simple root and near a graze (touching zero without crossing) alike, and
//! can never step over a root. When the advance falls below the time tolerance, the event
//! is there.

use super::segment::Taylor;

/// Advance below which the search takes the event as found, s.
pub const TIME_TOL: f64 = 1e-13;

/// Most advances in one window before the event is taken as found (a safeguard against a
/// pathological bound; never reached in the tests).
const MAX_ADVANCES: usize = 400;

/// `L(tau) = h0 + h1 tau + h2 tau^2/2 + h3 tau^3/6 - B tau^4/24` and its derivative.
fn lower(t: &Taylor, tau: f64) -> (f64, f64) {
    let h = &t.h;
    let b = t.bound4;
    let v = h[0] + tau * (h[1] + tau * (h[2] / 2.0 + tau * (h[3] / 6.0 - b * tau / 24.0)));
    let dv = h[1] + tau * (h[2] + tau * (h[3] / 2.0 - b * tau / 6.0));
    (v, dv)
}

/// Real roots of `a x^2 + b x + c` (at most two; unused slots are NaN).
fn quadratic_roots(a: f64, b: f64, c: f64) -> [f64; 2] {
    if a == 0.0 {
        return [if b != 0.0 { -c / b } else { f64::NAN }, f64::NAN];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    let s = disc.sqrt();
    let q = -0.5 * (b + if b >= 0.0 { s } else { -s });
    [q / a, if q != 0.0 { c / q } else { f64::NAN }]
}

/// The root of a function that changes sign on `[lo, hi]`, by Newton steps kept inside the
/// bracket (bisection otherwise), to a relative precision of 1e-12 of the bracket.
fn solve(f: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64) -> f64 {
    let (flo, dlo) = f(lo);
    let lo_positive = flo > 0.0;
    let tol = 1e-12 * (hi - lo).abs();
    // The first iterate: Newton's step from `lo` when it stays in the bracket. On the monotone
    // pieces the search works on, a root near `lo` (the usual case: the search closing in on
    // an event) is then found in a step or two, where a start from the midpoint would halve
    // the bracket until its curvature no longer throws Newton out of it.
    let from_lo = lo - flo / dlo;
    let mut x = if dlo != 0.0 && (from_lo - lo) * (from_lo - hi) < 0.0 { from_lo } else { 0.5 * (lo + hi) };
    let mut probed = false;
    for _ in 0..100 {
        let (v, dv) = f(x);
        if v == 0.0 {
            return x;
        }
        if (v > 0.0) == lo_positive {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - v / dv;
        let inside = (newton - lo) * (newton - hi) < 0.0;
        if dv != 0.0 && !inside && !probed {
            // Newton leaves the bracket: the root may sit at its end, where the function is
            // flat (a double root, as when the bound touches zero at a knot), and both
            // Newton and bisection would only halve the distance. Probe the end once.
            probed = true;
            let beyond_hi = newton >= hi;
            let inner = if beyond_hi { hi - tol } else { lo + tol };
            if inner > lo && inner < hi {
                let lo_side = (f(inner).0 > 0.0) == lo_positive;
                match (beyond_hi, lo_side) {
                    (true, true) => return hi,
                    (false, false) => return lo,
                    (_, true) => lo = inner,
                    (_, false) => hi = inner,
                }
            }
        }
        let next = if dv != 0.0 && inside { newton } else { 0.5 * (lo + hi) };
        if (next - x).abs() <= tol {
            return next;
        }
        x = next;
    }
    x
}

/// `L''(tau) = h2 + h3 tau - B tau^2 / 2` and its derivative.
fn lower_second(t: &Taylor, tau: f64) -> (f64, f64) {
    (t.h[2] + tau * (t.h[3] - t.bound4 * tau / 2.0), t.h[3] - t.bound4 * tau)
}

/// The first root of `L` in `(0, len]`, if any: `L''` has at most two roots, which split the
/// interval into pieces where `L'` is monotone; the roots of `L'` on those pieces split it
/// into pieces where `L` is monotone, and the first of those on which `L` reaches zero
/// holds its first root.
pub fn lower_root(t: &Taylor, len: f64) -> Option<f64> {
    if t.h[0] <= 0.0 {
        return Some(0.0);
    }
    // Quick exclusion: the value outweighs the largest possible change over the interval.
    let h = &t.h;
    let change = len * (h[1].abs() + len * (h[2].abs() / 2.0 + len * (h[3].abs() / 6.0 + t.bound4.abs() * len / 24.0)));
    if h[0] > change {
        return None;
    }
    if bernstein_positive(t, len) {
        return None;
    }
    lower_root_unbounded(t, len)
}

/// Whether `L` is certainly positive on `[0, len]`: its Bernstein coefficients there (the
/// polynomial lies in their convex hull) all exceed their rounding error.
fn bernstein_positive(t: &Taylor, len: f64) -> bool {
    let h = &t.h;
    // L(len s) = sum c_k s^k.
    let c1 = h[1] * len;
    let c2 = h[2] / 2.0 * len * len;
    let c3 = h[3] / 6.0 * len * len * len;
    let c4 = -t.bound4 / 24.0 * len * len * len * len;
    let margin = 16.0 * f64::EPSILON * (h[0].abs() + c1.abs() + c2.abs() + c3.abs() + c4.abs());
    let b =
        [h[0] + c1 / 4.0, h[0] + c1 / 2.0 + c2 / 6.0, h[0] + 0.75 * c1 + c2 / 2.0 + c3 / 4.0, h[0] + c1 + c2 + c3 + c4];
    h[0] > margin && b.iter().all(|&x| x > margin)
}

/// [`lower_root`] without its quick exclusion (any sign of the quartic term).
fn lower_root_unbounded(t: &Taylor, len: f64) -> Option<f64> {
    if t.h[0] <= 0.0 {
        return Some(0.0);
    }
    let mut knots = [0.0, len, len, len];
    let mut nk = 1;
    let mut r2 = quadratic_roots(-t.bound4 / 2.0, t.h[3], t.h[2]);
    r2.sort_by(f64::total_cmp);
    for r in r2 {
        if r > 0.0 && r < len {
            knots[nk] = r;
            nk += 1;
        }
    }
    knots[nk] = len;
    let slope = |x: f64| (lower(t, x).1, lower_second(t, x).0);
    let value = |x: f64| lower(t, x);
    let mut a = 0.0;
    for w in 0..nk {
        let (k0, k1) = (knots[w], knots[w + 1]);
        // Split [k0, k1] at the root of L' if it changes sign there.
        let (d0, d1) = (lower(t, k0).1, lower(t, k1).1);
        let mid = if d0 * d1 < 0.0 { Some(solve(slope, k0, k1)) } else { None };
        for b in mid.into_iter().chain(std::iter::once(k1)) {
            if lower(t, b).0 <= 0.0 {
                return Some(solve(value, a, b));
            }
            a = b;
        }
    }
    None
}

/// The first root in `(0, len]` of the upper bound `U(tau) = c(tau) + B tau^4 / 24`: by then
/// `h` has certainly reached zero.
fn upper_root(t: &Taylor, len: f64) -> Option<f64> {
    let flipped = Taylor { bound4: -t.bound4, ..*t };
    lower_root_unbounded(&flipped, len)
}

/// First root of `h` in `(a, b]`, given its Taylor data at `a` and an evaluator. The search
/// stops on a bound of its distance to the root: `h` has no root before `t + tau` (the lower
/// bound) and has reached zero by `t + up` (the upper bound), so it stops when `up - tau` is
/// below [`TIME_TOL`] (or below what the time's floating-point spacing can resolve), whatever
/// the size of the last advance. Near a graze, where the advances shrink without the bracket
/// closing, it goes on advancing; where no advance is possible any more (a touch that the
/// arithmetic cannot tell from a miss), the event is there.
pub fn first_root(eval: &mut impl FnMut(f64) -> Taylor, a: f64, ta: Taylor, b: f64) -> Option<f64> {
    let tau = lower_root(&ta, b - a)?;
    first_root_from(eval, a, ta, tau, b)
}

/// [`first_root`] given its first advance `tau = lower_root(&ta, b - a)` (which the caller
/// has computed to exclude the window): the same result.
pub fn first_root_from(eval: &mut impl FnMut(f64) -> Taylor, a: f64, ta: Taylor, tau: f64, b: f64) -> Option<f64> {
    let mut t = a;
    let mut ta = ta;
    let mut next = Some(tau);
    for _ in 0..MAX_ADVANCES {
        let tau = match next.take() {
            Some(tau) => tau,
            None => lower_root(&ta, b - t)?,
        };
        let resolution = TIME_TOL.max(4.0 * f64::EPSILON * t.abs());
        if tau <= resolution && upper_root(&ta, b - t).is_some_and(|up| up - tau <= resolution) {
            return Some(t + tau);
        }
        if t + tau == t || tau == 0.0 {
            return Some(t);
        }
        t += tau;
        ta = eval(t);
    }
    Some(t)
}

/// After an event a function can start at zero (a bed that just lifted off sits on the
/// bottom with zero relative velocity and zero relative acceleration). Returns how far past
/// the start it is certainly positive, ignoring the first `noise` seconds, or `None` when it
/// does not become positive (then the event is immediate). `tol` gives, for the value, the
/// slope and the curvature, what counts as zero: those are rounding residues of the event
/// just resolved.
pub fn fresh_window(t: &Taylor, noise: f64, tol: [f64; 3], max: f64) -> Option<f64> {
    if t.h[1] < -tol[1] || t.h[2] < -tol[2] && t.h[1] <= tol[1] {
        return None;
    }
    let h1 = t.h[1].max(0.0);
    let h2 = if t.h[2].abs() <= tol[2] { t.h[2].max(0.0) } else { t.h[2] };
    // L(tau) = h1 tau + h2 tau^2/2 + h3 tau^3/6 - B tau^4/24, the value taken as zero.
    let lower = |tau: f64| tau * (h1 + tau * (h2 / 2.0 + tau * (t.h[3] / 6.0 - t.bound4 * tau / 24.0)));
    if lower(noise) <= 0.0 {
        return None;
    }
    let mut last = noise;
    let mut tau = noise;
    while tau < max {
        tau = (tau * 2.0).min(max);
        if lower(tau) <= 0.0 {
            break;
        }
        last = tau;
    }
    Some(last)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `h(t) = cos(w t) + shift` with an exact fourth-derivative bound.
    fn cosine(w: f64, shift: f64) -> impl FnMut(f64) -> Taylor {
        move |t: f64| {
            let (s, c) = (w * t).sin_cos();
            Taylor { h: [c + shift, -w * s, -w * w * c, w * w * w * s], bound4: w.powi(4) }
        }
    }

    #[test]
    fn finds_first_crossing() {
        let mut f = cosine(3.0, 0.0);
        let t0 = f(0.0);
        let r = first_root(&mut f, 0.0, t0, 10.0).unwrap();
        assert!((r - std::f64::consts::FRAC_PI_2 / 3.0).abs() < 1e-12, "{r}");
    }

    #[test]
    fn finds_a_near_graze() {
        // cos(t) + 1 - 1e-14 dips below zero for about 3e-7 around pi; a touch at exactly
        // zero cannot be told from rounding noise of 1 + cos(t) (1e-16).
        let mut f = cosine(1.0, 1.0 - 1e-14);
        let t0 = f(0.0);
        let r = first_root(&mut f, 0.0, t0, 5.0).unwrap();
        assert!((r - std::f64::consts::PI).abs() < 2e-7, "{r}");
    }

    #[test]
    fn finds_a_shallow_dip_between_samples() {
        // cos(t) + 1 - 1e-12 dips below zero for about 3e-6 around pi.
        let mut f = cosine(1.0, 1.0 - 1e-12);
        let t0 = f(0.0);
        let r = first_root(&mut f, 0.0, t0, 5.0).unwrap();
        assert!((r - std::f64::consts::PI).abs() < 2e-6, "{r}");
    }

    #[test]
    fn stops_on_a_bound_of_the_distance_to_the_root() {
        // A slow crossing: cos(t) + 1 - eps first reaches zero at pi - delta, delta =
        // acos(1 - eps) ~ sqrt(2 eps) (1 + eps / 12), where its slope is only ~sqrt(2 eps). The
        // root is returned to what the function's rounding (~1e-16 / slope) allows, however
        // small the last advances are.
        for eps in [1e-6, 1e-8, 1e-10] {
            let mut f = cosine(1.0, 1.0 - eps);
            let t0 = f(0.0);
            let r = first_root(&mut f, 0.0, t0, 5.0).unwrap();
            let delta = (2.0 * eps).sqrt() * (1.0 + eps / 12.0);
            let root = std::f64::consts::PI - delta;
            let slope = delta;
            let err = (r - root).abs();
            assert!(err <= TIME_TOL + 4e-16 / slope, "eps {eps:e}: {err:e} s from the root");
            assert!(r <= root + 4e-16 / slope, "never past the root");
        }
    }

    #[test]
    fn no_root_when_positive() {
        let mut f = cosine(1.0, 1.0 + 1e-9);
        let t0 = f(0.0);
        assert_eq!(first_root(&mut f, 0.0, t0, 5.0), None);
    }

    #[test]
    fn fresh_window_skips_a_double_zero() {
        // h = tau^3 near zero: positive after any noise window.
        let t = Taylor { h: [0.0, 0.0, 0.0, 6.0], bound4: 24.0 };
        let w = fresh_window(&t, 1e-12, [1e-15, 1e-12, 1e-12], 0.5).unwrap();
        assert!(w > 0.1, "{w}");
        // h = -tau^2: never positive.
        let t = Taylor { h: [0.0, 0.0, -2.0, 0.0], bound4: 0.0 };
        assert_eq!(fresh_window(&t, 1e-12, [1e-15, 1e-12, 1e-12], 0.5), None);
    }
}
