//! The front page's view (`index.html`): the summary table, the figures' verdicts on every
//! model, the bed and bottom-line rows, each formatted here (templates only fill in).

use serde::Serialize;

use crate::analysis::ExperimentResult;
use crate::checks::verdict::{figure_group, verdict};
use crate::checks::{CheckOutcome, Status};
use crate::experiment::ModelInfo;

use super::report::CheckRow;
use super::view::counts;

/// One row of the summary table.
#[derive(Debug, Serialize)]
pub struct SummaryRow {
    /// The experiment's key.
    pub id: String,
    /// The paper figure.
    pub figure: String,
    /// The experiment's title.
    pub title: String,
    /// Link to its page.
    pub link: String,
    /// Link to its first figure's PNG.
    pub thumbnail: String,
    /// The verdict, in words.
    pub verdict: String,
    /// CSS class of the verdict.
    pub verdict_class: String,
    /// Checks passed, failed and known deviations, in words.
    pub counts: String,
}

/// A figure's verdict on one model.
#[derive(Debug, Serialize)]
pub struct ModelCell {
    /// The verdict on this model, in words.
    pub verdict: String,
    /// CSS class of the verdict.
    pub verdict_class: String,
    /// Checks against the paper that pass, of all against the paper ("7/8"; "" when none).
    pub checks: String,
    /// Checks against the paper whose value rests on a point that did not settle (counted
    /// in `checks` as they came out, named apart).
    pub unsettled: usize,
    /// The page of the figure's experiment on this model ("" when not run).
    pub link: String,
    /// Its claims that hold at a joint study's best setup on this model ("2/3"; "" when no
    /// joint study the report runs holds the figure on this model).
    pub joint: String,
    /// That setup, in words (the cell's tooltip).
    pub joint_setup: String,
    /// The model's id.
    #[serde(skip)]
    pub model: String,
}

/// One paper figure: its verdict and the experiments behind it.
#[derive(Debug, Serialize)]
pub struct FigureRow {
    /// The paper figure.
    pub figure: String,
    /// The overall verdict, in words.
    pub verdict: String,
    /// CSS class of the verdict.
    pub verdict_class: String,
    /// The verdict on each model of [`IndexView::models`] (empty when no experiment of the
    /// report runs on several models).
    pub cells: Vec<ModelCell>,
    /// (title, link) of each experiment.
    pub experiments: Vec<(String, String)>,
    /// The ids of its experiments.
    #[serde(skip)]
    pub ids: Vec<String>,
    /// One short sentence: the verdict on each model, grouped.
    pub sentence: String,
    /// Checks against the paper's own numbers and figures, counted in words.
    pub paper_checks: String,
    /// Other checks (independent solver, baseline), counted in words.
    pub other_checks: String,
    /// Link to the figure's thumbnail.
    pub thumbnail: String,
    /// Not the paper's: every experiment of the row is an engineer's own (an example), so it
    /// is listed apart from the paper's figures ([`IndexView::examples`]).
    pub own: bool,
}

/// The context of the index page.
#[derive(Debug, Serialize)]
pub struct IndexView {
    /// The report's title.
    pub title: String,
    /// Whether any experiment is one of the paper's figures (else the report is of an
    /// engineer's own project, and neither its title nor its lead speaks of the paper).
    pub paper: bool,
    /// shotdamp's version and the command that wrote the report.
    pub generated_by: String,
    /// The overall outcome, in words.
    pub overall: String,
    /// CSS class of the outcome.
    pub overall_class: String,
    /// The replication's verdict: per model, how many figures are reproduced, partly, not
    /// (named), without a reference (empty without several models).
    pub replication: Vec<String>,
    /// Labels of the models experiments run on, in first-seen order.
    pub models: Vec<String>,
    /// One row per paper figure.
    pub figures: Vec<FigureRow>,
    /// One row per group of experiments that are not the paper's (examples, an engineer's
    /// structures): a section of their own, with their own verdicts.
    pub examples: Vec<FigureRow>,
    /// One row per experiment run.
    pub rows: Vec<SummaryRow>,
    /// Every check.
    pub checks: Vec<CheckRow>,
    /// Every assumption of the runs.
    pub assumptions: Vec<String>,
    /// The paper's conclusion tested by the design experiments, a sentence per model.
    pub conclusions: Vec<super::conclusion::Conclusion>,
    /// "Does the bed model matter?": per bed study, its figure, the link to its section and a
    /// sentence.
    pub bed: Vec<BedRow>,
    /// The bottom line of each joint study the report runs (above the verdict matrix).
    pub bottom: Vec<super::bottom_line::BottomLine>,
    /// Experiments whose answer is partial (a design stopped by its time limit or an
    /// interrupt): `(key, link, why)`, first on the page.
    pub partial: Vec<(String, String, String)>,
}

/// One bed study in the index.
#[derive(Debug, Serialize)]
pub struct BedRow {
    /// The paper figure.
    pub figure: String,
    /// Link to its bed-model section.
    pub link: String,
    /// One sentence: how far the claims move with the bed model.
    pub sentence: String,
}

/// Builds the index view.
pub fn index_view(results: &[ExperimentResult]) -> IndexView {
    let all: Vec<CheckOutcome> = results.iter().flat_map(|r| r.checks.iter().cloned()).collect();
    let (overall, class, words) = counts(&all);
    let mut assumptions: Vec<String> = Vec::new();
    for r in results {
        for a in super::setup_words::assumptions(&r.experiment) {
            if !assumptions.contains(&a) {
                assumptions.push(a);
            }
        }
    }
    let models = model_list(results);
    let (examples, figures): (Vec<FigureRow>, Vec<FigureRow>) =
        figure_rows(results, &models).into_iter().partition(|f| f.own);
    let paper = !figures.is_empty();
    IndexView {
        examples,
        replication: replication(&figures, &models),
        figures,
        models: models.iter().map(|m| m.label.clone()).collect(),
        paper,
        title: if !paper {
            format!("shotdamp: {} experiment{}", results.len(), if results.len() == 1 { "" } else { "s" })
        } else {
            "shotdamp: replication of Araki et al. (1997)".into()
        },
        generated_by: format!("shotdamp {}", env!("CARGO_PKG_VERSION")),
        overall: format!("{overall}: {words}"),
        overall_class: class.to_string(),
        rows: results
            .iter()
            .map(|r| {
                let (verdict, class, counts) = counts(&r.checks);
                let id = &r.experiment.key();
                SummaryRow {
                    id: id.clone(),
                    figure: r.experiment.meta.figure.clone(),
                    title: r.experiment.meta.title.clone(),
                    link: format!("{id}/index.html"),
                    thumbnail: r.figures.first().map(|f| format!("{id}/{}.png", f.id)).unwrap_or_default(),
                    verdict,
                    verdict_class: class.to_string(),
                    counts,
                }
            })
            .collect(),
        checks: results.iter().flat_map(|r| r.checks.iter().map(|c| CheckRow::new(&r.experiment.key(), c))).collect(),
        assumptions,
        conclusions: super::conclusion::conclusions(results),
        bed: Vec::new(),
        bottom: Vec::new(),
        partial: results
            .iter()
            .filter_map(|r| {
                let id = r.experiment.key();
                r.partial.clone().map(|why| (id.clone(), format!("{id}/index.html"), why))
            })
            .collect(),
    }
}

/// Per model: the figures reproduced, partly reproduced, not reproduced (named) and without a
/// reference, from the verdict matrix's cells.
fn replication(figures: &[FigureRow], models: &[ModelInfo]) -> Vec<String> {
    use crate::checks::verdict::Verdict as V;
    models
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let of = |v: V| -> Vec<&str> {
                figures
                    .iter()
                    .filter(|f| f.cells.get(i).is_some_and(|c| c.verdict == v.label()))
                    .map(|f| f.figure.as_str())
                    .collect()
            };
            let (rep, part, not, none) =
                (of(V::Reproduced), of(V::PartlyReproduced), of(V::NotReproduced), of(V::NoReference));
            let mut words = vec![format!("{} reproduced", rep.len()), format!("{} partly", part.len())];
            words.push(if not.is_empty() {
                "0 not reproduced".to_string()
            } else {
                format!("{} not reproduced ({})", not.len(), not.join(", "))
            });
            if !none.is_empty() {
                words.push(format!("{} without a reference", none.len()));
            }
            format!("{}: {}", m.label, words.join(", "))
        })
        .collect()
}

/// Marks each verdict cell whose figure a joint study the report runs holds on its model:
/// how many of the figure's claims hold at that study's best setup (the first study that
/// has the figure on the model).
pub fn mark_joint(view: &mut IndexView, joint: &[super::bottom_line::AtJointSetup]) {
    for f in &mut view.figures {
        for cell in &mut f.cells {
            let here: Vec<&super::bottom_line::AtJointSetup> =
                joint.iter().filter(|j| j.model == cell.model && f.ids.contains(&j.experiment)).collect();
            // The joint study whose best setup on this model holds the most claims.
            let Some(top) = here.iter().max_by_key(|j| (j.total, std::cmp::Reverse(joint_rank(joint, &j.study))))
            else {
                continue;
            };
            let same: Vec<&&super::bottom_line::AtJointSetup> = here.iter().filter(|j| j.study == top.study).collect();
            let holds: usize = same.iter().map(|j| j.holds).sum();
            let claims: usize = same.iter().map(|j| j.claims).sum();
            cell.joint = format!("{holds}/{claims}");
            cell.joint_setup = top.setup.clone();
        }
    }
}

/// The position of study `id` among the joint studies (the first wins a tie).
fn joint_rank(joint: &[super::bottom_line::AtJointSetup], id: &str) -> usize {
    joint.iter().position(|j| j.study == id).unwrap_or(usize::MAX)
}

/// Sort key of a figure label: its number, then the label ("Fig. 10(a)" after "Fig. 9").
fn figure_order(label: &str) -> (u32, String) {
    let digits: String = label.chars().skip_while(|c| !c.is_ascii_digit()).take_while(|c| c.is_ascii_digit()).collect();
    (digits.parse().unwrap_or(u32::MAX), label.to_string())
}

/// The models of the report's runs, in first-seen order.
fn model_list(results: &[ExperimentResult]) -> Vec<ModelInfo> {
    let mut out: Vec<ModelInfo> = Vec::new();
    for m in results.iter().filter_map(|r| r.experiment.model.as_ref()) {
        if !out.contains(m) {
            out.push(m.clone());
        }
    }
    out
}

/// One row per paper figure, in the paper's order.
fn figure_rows(results: &[ExperimentResult], models: &[ModelInfo]) -> Vec<FigureRow> {
    let mut groups: Vec<String> = results.iter().map(|r| figure_group(&r.experiment.meta.figure)).collect();
    groups.sort_by_key(|g| figure_order(g));
    groups.dedup();
    groups
        .into_iter()
        .map(|g| {
            // The experiment of the paper figure itself first (its deviation and preview stand
            // for the figure), then its companions ("Fig. 5 (clearance)", ...).
            let mut members: Vec<&ExperimentResult> =
                results.iter().filter(|r| figure_group(&r.experiment.meta.figure) == g).collect();
            members.sort_by_key(|r| r.experiment.meta.figure != g);
            let checks: Vec<&CheckOutcome> = members.iter().flat_map(|r| r.checks.iter()).collect();
            let v = verdict(checks.iter().copied());
            // A row of the experiments' own (an engineer's structure) has no paper to verdict on.
            let own = !members.iter().any(|r| r.experiment.meta.from_paper());
            let label = |v: crate::checks::verdict::Verdict| {
                if own && v == crate::checks::verdict::Verdict::NoReference {
                    "not in the paper"
                } else {
                    v.label()
                }
            };
            let count = |paper: bool| {
                let sel: Vec<&&CheckOutcome> = checks.iter().filter(|c| c.source.is_paper() == paper).collect();
                if sel.is_empty() {
                    return "none".to_string();
                }
                let n = |s: Status| sel.iter().filter(|c| c.status == s).count();
                format!(
                    "{} pass, {} known deviation, {} fail",
                    n(Status::Pass) + n(Status::KnownDeviationPasses),
                    n(Status::KnownDeviation),
                    n(Status::Fail)
                )
            };
            // Not the paper's: the verdict is its own checks' (a stored design replayed, a
            // reduction against its full model), as no paper number applies.
            let own_verdict = own.then(|| {
                if checks.iter().any(|c| c.status == Status::Fail) {
                    ("a check fails", "fail")
                } else if checks.is_empty() {
                    ("no checks", "none")
                } else {
                    ("its checks pass", "pass")
                }
            });
            let cells: Vec<ModelCell> = models
                .iter()
                .map(|m| {
                    let on: Vec<&&ExperimentResult> =
                        members.iter().filter(|r| r.experiment.model.as_ref() == Some(m)).collect();
                    if on.is_empty() {
                        return ModelCell {
                            verdict: "not run".into(),
                            verdict_class: "none".into(),
                            checks: String::new(),
                            unsettled: 0,
                            link: String::new(),
                            joint: String::new(),
                            joint_setup: String::new(),
                            model: m.id.clone(),
                        };
                    }
                    let v = verdict(on.iter().flat_map(|r| r.checks.iter()));
                    let paper: Vec<&CheckOutcome> =
                        on.iter().flat_map(|r| r.checks.iter()).filter(|c| c.source.is_paper()).collect();
                    let passing = paper
                        .iter()
                        .filter(|c| matches!(c.status, Status::Pass | Status::KnownDeviationPasses))
                        .count();
                    ModelCell {
                        verdict: label(v).to_string(),
                        verdict_class: v.class().to_string(),
                        checks: if paper.is_empty() { String::new() } else { format!("{passing}/{}", paper.len()) },
                        unsettled: paper.iter().filter(|c| c.settled == Some(false)).count(),
                        link: format!("{}/index.html", on[0].experiment.key()),
                        joint: String::new(),
                        joint_setup: String::new(),
                        model: m.id.clone(),
                    }
                })
                .collect();
            let sentence = if models.is_empty() || own {
                format!("{}.", capitalise(label(v)))
            } else {
                grouped_sentence(&cells, models)
            };
            let mut titles: Vec<(String, String)> = Vec::new();
            for r in &members {
                let link = format!("{}/index.html", r.experiment.meta.id);
                if !titles.iter().any(|(_, l)| *l == link) {
                    titles.push((r.experiment.meta.title.clone(), link));
                }
            }
            let mut ids: Vec<String> = members.iter().map(|r| r.experiment.meta.id.clone()).collect();
            ids.dedup();
            FigureRow {
                ids,
                figure: g,
                verdict: own_verdict.map_or_else(|| label(v).to_string(), |o| o.0.to_string()),
                verdict_class: own_verdict.map_or_else(|| v.class().to_string(), |o| o.1.to_string()),
                cells,
                experiments: titles,
                sentence,
                paper_checks: count(true),
                other_checks: count(false),
                thumbnail: members
                    .iter()
                    .find_map(|r| r.figures.first().map(|f| format!("{}/{}.png", r.experiment.key(), f.id)))
                    .unwrap_or_default(),
                own,
            }
        })
        .collect()
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map(|f| f.to_uppercase().chain(c).collect()).unwrap_or_default()
}

/// "Reproduced on stated and fitted; partly reproduced on coil.": the models grouped by their
/// verdict, in the order of the first model of each group.
fn grouped_sentence(cells: &[ModelCell], models: &[ModelInfo]) -> String {
    let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
    for (c, m) in cells.iter().zip(models.iter().map(|m| m.label.as_str())) {
        match groups.iter_mut().find(|(v, _)| *v == c.verdict) {
            Some((_, ms)) => ms.push(m),
            None => groups.push((&c.verdict, vec![m])),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(v, ms)| {
            let on = if ms.len() == models.len() && models.len() > 1 {
                "every model".to_string()
            } else if ms.len() == 1 {
                ms[0].to_string()
            } else {
                format!("{} and {}", ms[..ms.len() - 1].join(", "), ms[ms.len() - 1])
            };
            format!("{v} on {on}")
        })
        .collect();
    format!("{}.", capitalise(&parts.join("; ")))
}
