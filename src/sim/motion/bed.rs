//! What a bed does when it hits an end of its container (docs/model.md section 2), written
//! once for the engine, which applies it ([`ImpactLaw::exchange`]), and for the linearised
//! flow, which differentiates it ([`ImpactLaw::derivative`]): momentum is conserved between
//! the bed and its host (with the beds riding on the host); the relative velocity is reversed
//! and scaled by the coefficient of restitution, or, for a plastic law or an impact slower
//! than the sticking speed, the bed keeps its host's velocity and rests on that end.

/// Position and velocity at `t` of a bed (or grain) in free flight since `t0` from position
/// `y0` with velocity `u0` under gravity `g` along its motion alone (docs/model.md section 5:
/// `g` for a vertical container, a parabola; 0 for a horizontal one, a straight line).
pub fn flight(g: f64, t0: f64, y0: f64, u0: f64, t: f64) -> (f64, f64) {
    let tau = t - t0;
    (y0 + u0 * tau - 0.5 * g * tau * tau, u0 - g * tau)
}

/// How a bed's impact exchanges momentum with its host: the law answers for itself (whether
/// it bounces, its parameters), so that a new law is one arm here and its keys in the
/// experiment file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ImpactLaw {
    /// The paper's assumption: the bed sticks to the end it hits (e = 0).
    Plastic,
    /// The relative velocity reversed and scaled by `e`, 0 < e < 1; an impact slower than
    /// `stick_speed` (m/s) sticks (what ends a sequence of ever smaller bounces).
    Restitution {
        /// Coefficient of restitution.
        e: f64,
        /// Relative impact speed below which the bed sticks, m/s.
        stick_speed: f64,
    },
}

/// What one impact did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exchange {
    /// The host's velocity after the impact, m/s.
    pub host: f64,
    /// The bed's velocity after the impact (the host's when it sticks), m/s.
    pub bed: f64,
    /// The bed rests on the end it hit and moves with its host.
    pub sticks: bool,
    /// Kinetic energy lost in the impact, J.
    pub loss: f64,
}

impl ImpactLaw {
    /// The paper's law: plastic impacts.
    pub const PLASTIC: ImpactLaw = ImpactLaw::Plastic;

    /// The law of coefficient of restitution `e` (0 <= e < 1) that sticks below
    /// `stick_speed`: plastic at `e = 0`.
    pub fn with_restitution(e: f64, stick_speed: f64) -> ImpactLaw {
        if e == 0.0 {
            ImpactLaw::Plastic
        } else {
            ImpactLaw::Restitution { e, stick_speed }
        }
    }

    /// Whether every impact sticks (the paper's bed).
    pub fn is_plastic(&self) -> bool {
        matches!(self, ImpactLaw::Plastic)
    }

    /// The coefficient of restitution: 0 for a plastic law.
    pub fn restitution(&self) -> f64 {
        match *self {
            ImpactLaw::Plastic => 0.0,
            ImpactLaw::Restitution { e, .. } => e,
        }
    }

    /// The relative impact speed below which a bouncing bed sticks, m/s (none: plastic).
    pub fn stick_speed(&self) -> Option<f64> {
        match *self {
            ImpactLaw::Plastic => None,
            ImpactLaw::Restitution { stick_speed, .. } => Some(stick_speed),
        }
    }

    /// Whether an impact at relative speed `rel` bounces (else the bed sticks).
    pub fn bounces(&self, rel: f64) -> bool {
        match *self {
            ImpactLaw::Plastic => false,
            ImpactLaw::Restitution { e, stick_speed } => e > 0.0 && rel.abs() >= stick_speed,
        }
    }

    /// The coefficient an impact at relative speed `rel` gets: the restitution when it
    /// bounces, 0 when the bed sticks.
    pub fn coefficient(&self, rel: f64) -> f64 {
        if self.bounces(rel) {
            self.restitution()
        } else {
            0.0
        }
    }

    /// A host of mass `mh` (with the beds riding on it) at velocity `vp` hit by a bed of mass
    /// `md` at velocity `u`.
    pub fn exchange(&self, mh: f64, vp: f64, md: f64, u: f64) -> Exchange {
        let rel = u - vp;
        let total = mh + md;
        let ke_before = 0.5 * mh * vp * vp + 0.5 * md * u * u;
        if self.bounces(rel) {
            let e = self.restitution();
            let host = vp + md * (1.0 + e) * rel / total;
            let bed = u - mh * (1.0 + e) * rel / total;
            Exchange { host, bed, sticks: false, loss: ke_before - 0.5 * mh * host * host - 0.5 * md * bed * bed }
        } else {
            let v = (mh * vp + md * u) / total;
            Exchange { host: v, bed: v, sticks: true, loss: ke_before - 0.5 * total * v * v }
        }
    }

    /// The exchange's derivative with respect to the velocities before the impact, as
    /// `(a, b)`: `v_p' = (1 - a) v_p + a u` and `u' = b v_p + (1 - b) u`.
    pub fn derivative(&self, mh: f64, md: f64, rel: f64) -> (f64, f64) {
        let e = self.coefficient(rel);
        let total = mh + md;
        (md * (1.0 + e) / total, mh * (1.0 + e) / total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn momentum_is_kept_and_energy_lost_as_the_closed_forms_say() {
        let (mh, md, vp, u) = (0.71, 0.071, 0.1, -0.3);
        for law in [ImpactLaw::PLASTIC, ImpactLaw::with_restitution(0.5, 1e-3)] {
            let x = law.exchange(mh, vp, md, u);
            let p = mh * vp + md * u;
            assert!((mh * x.host + md * x.bed - p).abs() < 1e-15);
            let e = law.coefficient(u - vp);
            // Relative velocity reversed and scaled by e; loss = (1 - e^2) mu rel^2 / 2.
            assert!(((x.bed - x.host) + e * (u - vp)).abs() < 1e-15);
            let reduced = mh * md / (mh + md);
            assert!((x.loss - 0.5 * (1.0 - e * e) * reduced * (u - vp).powi(2)).abs() < 1e-15);
            assert_eq!(x.sticks, e == 0.0);
        }
        // Slower than the sticking speed: plastic.
        let law = ImpactLaw::with_restitution(0.5, 1.0);
        assert!(law.exchange(mh, vp, md, u).sticks);
    }

    #[test]
    fn the_derivative_is_that_of_the_exchange() {
        let (mh, md, vp, u, h) = (0.71, 0.071, 0.1, -0.3, 1e-6);
        for law in [ImpactLaw::PLASTIC, ImpactLaw::with_restitution(0.4, 1e-3)] {
            let (a, b) = law.derivative(mh, md, u - vp);
            let d_vp = (law.exchange(mh, vp + h, md, u).host - law.exchange(mh, vp - h, md, u).host) / (2.0 * h);
            let d_u = (law.exchange(mh, vp, md, u + h).bed - law.exchange(mh, vp, md, u - h).bed) / (2.0 * h);
            assert!((d_vp - (1.0 - a)).abs() < 1e-8 && (d_u - (1.0 - b)).abs() < 1e-8, "{d_vp} {a} {d_u} {b}");
        }
    }
}
