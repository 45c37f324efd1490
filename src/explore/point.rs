//! One frequency of one case, for the page's point view: the steady motion from rest (the
//! waveform analysis's), sampled over a few forcing periods, with its events, its period, how
//! it settled and the Floquet multipliers of its orbit.

use std::f64::consts::PI;

use serde::Deserialize;
use serde_json::{json, Value};

use super::{bad, Request};
use crate::analysis::curves;
use crate::analysis::event_words;
use crate::error::Result;
use crate::experiment::{Analysis, Experiment};
use crate::sim::motion::observe::Sampler;
use crate::sim::{steady_from_rest, Dynamics, Engine, SteadyOptions};

/// Samples per forcing period.
const SAMPLES: usize = 120;

/// Most forcing periods a point view draws.
const MAX_PERIODS: usize = 8;

/// A point asked for by the page: the setup of its curves, the case and the frequency.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointRequest {
    /// The setup, as a sweep request.
    pub setup: Request,
    /// The case's id.
    pub case: String,
    /// The forcing frequency, Hz.
    pub freq_hz: f64,
    /// Forcing periods to draw (1 to 8; default 2).
    #[serde(default = "two")]
    pub periods: usize,
}

fn two() -> usize {
    2
}

/// The steady motion of `req.case` at `req.freq_hz` from rest.
pub fn run(exp: &Experiment, req: &PointRequest) -> Result<Value> {
    let Some(case) = exp.cases.iter().find(|c| c.id == req.case) else {
        let ids: Vec<&str> = exp.cases.iter().map(|c| c.id.as_str()).collect();
        return Err(bad("case", &req.case, format!("one of the cases {ids:?}")));
    };
    if case.is_bare() {
        return Err(bad("case", &req.case, "a case with containers (the others are linear)"));
    }
    let f = req.freq_hz;
    if !(f.is_finite() && f > 0.0) {
        return Err(bad("freq_hz", f, "a positive frequency, Hz"));
    }
    // The lowest frequency a file may ask for holds here too: below it one period holds too
    // many oscillations of the fastest mode (its record alone would fill the memory).
    crate::experiment::parts::check_frequencies("request", "freq_hz", &[f], &exp.structure)?;
    if !(1..=MAX_PERIODS).contains(&req.periods) {
        return Err(bad("periods", req.periods, format!("1 to {MAX_PERIODS}")));
    }
    let opts = match &exp.analysis {
        Analysis::Sweep { steady, .. } => *steady,
        _ => SteadyOptions::default(),
    };
    let sys = curves::system(exp, case);
    let omega = 2.0 * PI * f;
    let d = Dynamics::new(&sys, omega).map_err(|e| bad("case", &req.case, format!("cannot be simulated: {e}")))?;
    let st = steady_from_rest(&d, &opts);
    let mut s = st.final_state.clone();
    let t0 = s.t;
    let period = 2.0 * PI / omega;
    let m = SAMPLES * req.periods;
    let times: Vec<f64> = (0..=m).map(|k| t0 + period * req.periods as f64 * k as f64 / m as f64).collect();
    let mut sampler = Sampler::new(times.clone());
    let ran = Engine::new(&d).advance(&mut s, t0 + period * req.periods as f64, &mut sampler);
    let phase = |t: f64| (t - t0) * omega * 180.0 / PI;
    let n = d.dof;
    let beds = sys.dampers.len();
    let column = |rows: &[Vec<f64>], j: usize| -> Vec<f64> { rows.iter().map(|r| r[j]).collect() };
    let hosts: Vec<usize> = sys.dampers.iter().map(|dm| dm.host).collect();
    let events: Vec<Value> = sampler
        .events
        .iter()
        .map(|e| json!({ "phase_deg": phase(e.t), "bed": e.bed + 1, "what": event_words(&e.kind) }))
        .collect();
    let multipliers: Vec<Value> = st
        .certificate
        .as_ref()
        .map(|c| c.multipliers.iter().map(|z| json!({ "re": z.re, "im": z.im, "modulus": z.norm() })).collect())
        .unwrap_or_default();
    Ok(json!({
        "case": case.id,
        "freq_hz": f,
        "converged": st.converged,
        "certified": st.certificate.is_some(),
        "period": st.period,
        "transient_periods": st.transient_periods,
        "amplitude_m": st.amplitude,
        "stop": curves::stop_text(&st),
        "ran": ran.is_ok(),
        "multipliers": multipliers,
        "phase_deg": times.iter().map(|&t| phase(t)).collect::<Vec<_>>(),
        "x": (0..n).map(|j| column(&sampler.x, j)).collect::<Vec<_>>(),
        "y": (0..beds).map(|j| column(&sampler.y, j)).collect::<Vec<_>>(),
        "hosts": hosts.iter().map(|h| h + 1).collect::<Vec<_>>(),
        "events": events,
    }))
}
