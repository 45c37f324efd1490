//! The index's sentences on the paper's conclusion ("multi-unit dampers with properly selected
//! mass ratios and clearances effectively suppress the resonant peaks over a wide frequency
//! range"): for each design experiment and model, how far the best layout lowers the worst
//! resonance peak of its bands against the bare structure, and how much of that the paper's
//! own layout (the case `paper`) reaches. The numbers are the run's exports.

use serde::Serialize;

use crate::analysis::ExperimentResult;

/// One sentence, with the design page it comes from.
#[derive(Debug, Serialize)]
pub struct Conclusion {
    /// The experiment's key.
    pub experiment: String,
    /// Link to its page.
    pub link: String,
    /// The sentence.
    pub text: String,
}

fn percent(x: f64) -> String {
    format!("{:.0} %", 100.0 * x)
}

/// The sentences, in the order of the results.
pub fn conclusions(results: &[ExperimentResult]) -> Vec<Conclusion> {
    results
        .iter()
        .filter_map(|r| {
            let (spec, _) = r.experiment.analysis.design()?;
            let best = *r.exports.get("best_objective")?;
            let model = r.experiment.model.as_ref().map(|m| format!(", {}", m.label)).unwrap_or_default();
            let bands: Vec<&str> = spec.bands.iter().map(|b| b.name.as_str()).collect();
            let mut text = format!(
                "{}{model}: properly selected mass ratios and clearances (the best layout found, {} in shot) lower the worst resonance peak of {} to {} of the bare structure's",
                r.experiment.meta.figure,
                r.experiment.structure_mass().map_or(format!("{} kg", spec.shot_kg), |m| format!(
                    "{} of the structure's mass",
                    percent(spec.shot_kg / m)
                )),
                bands.join(", "),
                percent(best)
            );
            if let Some(&paper) = r.exports.get("objective_paper") {
                let share = (1.0 - paper) / (1.0 - best);
                if paper < 1.0 && best < 1.0 {
                    text += &format!(
                        "; the paper's layout (mu = 0.1 on every mass, one clearance) lowers it to {}: {} of that reduction",
                        percent(paper),
                        percent(share)
                    );
                } else if best < 1.0 {
                    text += &format!(
                        "; the paper's layout (mu = 0.1 on every mass, one clearance) gives {} of it (no reduction)",
                        percent(paper)
                    );
                }
            }
            text.push('.');
            let key = r.experiment.key();
            Some(Conclusion { link: format!("{key}/index.html"), experiment: key, text })
        })
        .collect()
}
