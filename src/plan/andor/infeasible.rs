//! Why no assignment exists, in scenario terms: objects no robot can grasp, and
//! objects that block each other in a cycle.

use std::collections::BTreeSet;

use miette::LabeledSpan;

use crate::diag::{Located, Span};
use crate::plan::Unreachable;
use crate::resolve::{ObjectId, RobotId, Scenario, Target};

use super::graph::{Flag, Graph, Item};

/// The target cannot be reached: every branch of G ends in one of the `causes`.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
#[error("`{target}` cannot be reached")]
#[diagnostic(
    code(declutter::plan::infeasible),
    help("every way to the target was explored; the notes below say where each one ends")
)]
pub struct Infeasible {
    /// The target object's name, or `ROBOT at [...]` for a configuration target.
    pub target: String,
    #[label("the target")]
    pub span: Span,
    #[related]
    pub causes: Vec<Cause>,
}

/// One dead end of G.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum Cause {
    /// Every robot's flag is Null for this object.
    #[error("no robot can grasp `{name}` ({})", why(reasons))]
    #[diagnostic(code(declutter::plan::ungraspable))]
    Ungraspable {
        object: ObjectId,
        name: String,
        /// Robot name and why it cannot, per robot.
        reasons: Vec<(String, Unreachable)>,
        #[label("`{name}` is declared here")]
        span: Span,
    },
    /// The robot of a configuration target cannot reach it whatever is removed.
    #[error("`{robot}` cannot reach the target configuration ({})", describe(reason))]
    #[diagnostic(code(declutter::plan::unreachable_target))]
    TargetUnreachable {
        robot: String,
        reason: Unreachable,
        #[label("this configuration")]
        span: Span,
    },
    /// Removing the first object needs the second removed first, and so on, until the
    /// last needs the first: no order can work.
    #[error("{chain}")]
    #[diagnostic(
        code(declutter::plan::cycle),
        help(
            "no removal order can break this loop; it takes another robot, or another grasp, for one of these objects"
        )
    )]
    Cycle {
        objects: Vec<ObjectId>,
        /// `grasping `a` with `r1` needs `b` removed first, and ...: they block each other`.
        chain: String,
        #[label(collection)]
        labels: Vec<LabeledSpan>,
    },
}

impl Located for Infeasible {
    fn primary_span(&self) -> Option<Span> {
        Some(self.span)
    }
}

impl Infeasible {
    /// The whole reason on one line, for the schedule's `reason`.
    pub fn reason(&self) -> String {
        format!("{self}: {}", summary(&self.causes))
    }
}

/// A short description of an [`Unreachable`], for messages.
pub fn describe(u: &Unreachable) -> &'static str {
    match u {
        Unreachable::NoGraspSolution => "no grasp has an inverse-kinematics solution clear of fixed bodies",
        Unreachable::ApproachBlocked => {
            "its grasps are reachable, but every straight approach or retreat carrying it hits something fixed"
        }
        Unreachable::NoPath => "every path to a grasp hits something fixed",
        Unreachable::GoalBlocked => "the configuration is outside the joint limits or hits something fixed",
    }
}

fn why(reasons: &[(String, Unreachable)]) -> String {
    if reasons.is_empty() {
        return "the scenario declares no robot".to_string();
    }
    reasons.iter().map(|(r, u)| format!("`{r}`: {}", describe(u))).collect::<Vec<_>>().join("; ")
}

fn summary(causes: &[Cause]) -> String {
    if causes.is_empty() {
        return "no robot has a path to it".to_string();
    }
    causes.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
}

/// Collects the dead ends of a fully expanded G: nodes whose robots are all Null, and
/// the cycles behind Discarded flags (each set of objects once).
pub fn explain(scn: &Scenario, graph: &Graph) -> Infeasible {
    let (target, span) = match &scn.target {
        Target::Object { object, span } => (scn.object(*object).body.name.clone(), *span),
        Target::Config { robot, q, span } => {
            let values: Vec<String> = q.values.iter().map(|v| format!("{v}")).collect();
            (format!("{} at [{}]", scn.robot(*robot).name, values.join(", ")), *span)
        }
    };
    let mut causes = Vec::new();
    let mut seen_null = BTreeSet::new();
    let mut seen_cycle = BTreeSet::new();
    for n in graph.nodes() {
        let node = graph.node(n);
        if !node.is_analysed() {
            continue;
        }
        if node.flags.iter().all(|(_, f)| *f == Flag::Null) && seen_null.insert(node.item) {
            let reasons: Vec<(RobotId, Unreachable)> = node
                .flags
                .iter()
                .filter_map(|(r, _)| match graph.answer(*r, node.item).map(|a| &a.result) {
                    Some(Err(u)) => Some((*r, u.clone())),
                    _ => None,
                })
                .collect();
            match (node.item, &scn.target) {
                (Item::Object(object), _) => causes.push(Cause::Ungraspable {
                    object,
                    name: scn.object(object).body.name.clone(),
                    reasons: reasons.into_iter().map(|(r, u)| (scn.robot(r).name.clone(), u)).collect(),
                    span: scn.object(object).body.span,
                }),
                (Item::Config, Target::Config { robot, q, .. }) => {
                    if let Some((_, reason)) = reasons.into_iter().next() {
                        causes.push(Cause::TargetUnreachable {
                            robot: scn.robot(*robot).name.clone(),
                            reason,
                            span: q.span,
                        })
                    }
                }
                (Item::Config, Target::Object { .. }) => {}
            }
        }
        for (robot, flag) in &node.flags {
            if *flag != Flag::Discarded {
                continue;
            }
            let Some(p) = graph.found(*robot, node.item) else { continue };
            for blocker in p.removals.iter() {
                let Some(chain) = graph.cycle(n, *robot, blocker) else { continue };
                let set: BTreeSet<ObjectId> = chain.iter().map(|(o, _)| *o).collect();
                if seen_cycle.insert(set) {
                    causes.push(cycle(scn, &chain));
                }
            }
        }
    }
    Infeasible { target, span, causes }
}

fn cycle(scn: &Scenario, chain: &[(ObjectId, RobotId)]) -> Cause {
    let name = |o: ObjectId| scn.object(o).body.name.clone();
    let mut steps = Vec::new();
    let mut labels = Vec::new();
    for (i, (o, r)) in chain.iter().enumerate() {
        let next = chain[(i + 1) % chain.len()].0;
        let robot = &scn.robot(*r).name;
        steps.push(format!("grasping `{}` with `{robot}` needs `{}` removed first", name(*o), name(next)));
        labels.push(LabeledSpan::new_with_span(
            Some(format!("`{robot}` can grasp `{}` only after `{}` is removed", name(*o), name(next))),
            scn.object(*o).body.span,
        ));
    }
    let text = match steps.as_slice() {
        [one] => format!("{one}: it blocks itself"),
        [init @ .., last] => format!("{}, and {last}: they block each other", init.join(", ")),
        [] => String::new(),
    };
    Cause::Cycle { objects: chain.iter().map(|(o, _)| *o).collect(), chain: text, labels }
}
