//! Certified search for the first time an event function reaches zero.
//!
//! On `[a, a + L]` a function `h` obeys `h(a + tau) >= c(tau) - B tau^4 / 24`, where `c` is
//! its cubic Taylor polynomial at `a` and `B` bounds `|h''''|` there (the event functions are
//! sums of decaying exponentials, sinusoids and parabolas, so `B` comes in closed form). If
//! the minimum of `c` over the interval exceeds `B L^4 / 24`, the interval holds no root:
//! it is *excluded*. Otherwise it is bisected, left half first, until either every piece is
//! excluded or a piece shorter than the time tolerance remains: that is the first root,
//! grazes (touching zero without crossing) included. Where a sign change is bracketed and
//! `h` is proven monotone, a safeguarded Newton iteration finishes the job.

use super::segment::Taylor;

/// Width below which a piece that cannot be excluded is taken as the event, s.
pub const TIME_TOL: f64 = 1e-13;

/// Minimum of `c(tau) = h0 + h1 tau + h2 tau^2/2 + h3 tau^3/6` over `[0, l]`.
fn cubic_min(h: &[f64; 4], l: f64) -> f64 {
    let c = |t: f64| h[0] + t * (h[1] + t * (h[2] / 2.0 + t * h[3] / 6.0));
    let mut m = c(0.0).min(c(l));
    // c'(tau) = h1 + h2 tau + h3 tau^2 / 2.
    for r in quadratic_roots(h[3] / 2.0, h[2], h[1]) {
        if r > 0.0 && r < l {
            m = m.min(c(r));
        }
    }
    m
}

/// Maximum of `c'(tau)` over `[0, l]`.
fn slope_max(h: &[f64; 4], l: f64) -> f64 {
    let d = |t: f64| h[1] + t * (h[2] + t * h[3] / 2.0);
    let mut m = d(0.0).max(d(l));
    if h[3] != 0.0 {
        let r = -h[2] / h[3];
        if r > 0.0 && r < l {
            m = m.max(d(r));
        }
    }
    m
}

/// Real roots of `a x^2 + b x + c`.
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b != 0.0 { vec![-c / b] } else { Vec::new() };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Vec::new();
    }
    let s = disc.sqrt();
    let q = -0.5 * (b + b.signum() * s);
    let mut r = vec![q / a];
    if q != 0.0 {
        r.push(c / q);
    }
    r
}

/// True when `h` certainly has no root in `(a, a + l]`.
pub fn excluded(t: &Taylor, l: f64) -> bool {
    cubic_min(&t.h, l) > t.bound4 * l.powi(4) / 24.0
}

/// True when `h` is certainly strictly decreasing on `[a, a + l]`.
fn decreasing(t: &Taylor, l: f64) -> bool {
    slope_max(&t.h, l) + t.bound4 * l.powi(3) / 6.0 < 0.0
}

/// First root of `h` in `(a, b]`, given its Taylor data at `a` and an evaluator.
pub fn first_root(eval: &mut impl FnMut(f64) -> Taylor, a: f64, ta: Taylor, b: f64) -> Option<f64> {
    search(eval, a, ta, b, 0)
}

fn search(
    eval: &mut impl FnMut(f64) -> Taylor,
    a: f64,
    ta: Taylor,
    b: f64,
    depth: u32,
) -> Option<f64> {
    if ta.h[0] <= 0.0 {
        return Some(a);
    }
    let l = b - a;
    if excluded(&ta, l) {
        return None;
    }
    if l <= TIME_TOL || depth > 80 {
        return Some(a);
    }
    let tb = eval(b);
    if tb.h[0] <= 0.0 && decreasing(&ta, l) {
        return Some(refine(eval, a, ta, b));
    }
    let mid = a + 0.5 * l;
    if let Some(r) = search(eval, a, ta, mid, depth + 1) {
        return Some(r);
    }
    let tm = eval(mid);
    search(eval, mid, tm, b, depth + 1)
}

/// The single root of a decreasing `h` with `h(a) > 0 >= h(b)`, to [`TIME_TOL`].
fn refine(eval: &mut impl FnMut(f64) -> Taylor, mut a: f64, ta: Taylor, mut b: f64) -> f64 {
    let mut t = a;
    let mut h = ta.h[0];
    let mut dh = ta.h[1];
    for _ in 0..100 {
        // Newton from the current point; bisect when it leaves the bracket.
        let mut next = if dh < 0.0 { t - h / dh } else { 0.5 * (a + b) };
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
        }
        let tn = eval(next);
        if tn.h[0] > 0.0 {
            a = next;
        } else {
            b = next;
        }
        t = next;
        h = tn.h[0];
        dh = tn.h[1];
        if b - a <= TIME_TOL || h == 0.0 {
            break;
        }
        // Newton's step size tells the distance to the root near convergence.
        if dh != 0.0 && (h / dh).abs() < 0.25 * TIME_TOL {
            let root = t - h / dh;
            if root >= a && root <= b {
                return root;
            }
        }
    }
    b
}

/// After an event a function can start at zero (a bed that just lifted off sits on the
/// bottom with zero relative velocity). Returns how far past the start it is certainly
/// positive, ignoring the first `noise` seconds, or `None` when it does not become positive
/// (then the event is immediate).
pub fn fresh_window(t: &Taylor, noise: f64, slope_noise: f64, max: f64) -> Option<f64> {
    // Lower bound with the start value taken as zero and a slope at noise level as zero:
    // `L(tau) = h1+ tau + h2 tau^2/2 + h3 tau^3/6 - B tau^4/24`.
    if t.h[1] < -slope_noise {
        return None;
    }
    let h1 = t.h[1].max(0.0);
    let lower =
        |tau: f64| tau * (h1 + tau * (t.h[2] / 2.0 + tau * (t.h[3] / 6.0 - t.bound4 * tau / 24.0)));
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
            Taylor {
                h: [c + shift, -w * s, -w * w * c, w * w * w * s],
                bound4: w.powi(4),
            }
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
    fn finds_a_graze() {
        // cos(t) + 1 touches zero at t = pi without crossing.
        let mut f = cosine(1.0, 1.0);
        let t0 = f(0.0);
        let r = first_root(&mut f, 0.0, t0, 5.0).unwrap();
        assert!((r - std::f64::consts::PI).abs() < 1e-3, "{r}");
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
    fn no_root_when_positive() {
        let mut f = cosine(1.0, 1.0 + 1e-9);
        let t0 = f(0.0);
        assert_eq!(first_root(&mut f, 0.0, t0, 5.0), None);
    }

    #[test]
    fn fresh_window_skips_a_double_zero() {
        // h = tau^3 near zero: positive after any noise window.
        let t = Taylor {
            h: [0.0, 0.0, 0.0, 6.0],
            bound4: 24.0,
        };
        let w = fresh_window(&t, 1e-12, 1e-12, 0.5).unwrap();
        assert!(w > 0.1, "{w}");
        // h = -tau^2: never positive.
        let t = Taylor {
            h: [0.0, 0.0, -2.0, 0.0],
            bound4: 0.0,
        };
        assert_eq!(fresh_window(&t, 1e-12, 1e-12, 0.5), None);
    }
}
