//! Why no assignment exists, in scenario terms: objects no robot can grasp, and
//! objects that block each other in a cycle.

use std::collections::BTreeSet;

use std::fmt::Display;

use miette::{Diagnostic, LabeledSpan};

use crate::diag::{Located, Span};
use crate::plan::{Answer, Budget, Unreachable};
use crate::resolve::{FixedId, ObjectId, RobotId, Scenario, Target};
use crate::world::Blocker;

use super::graph::{Flag, Graph, Item};

/// No schedule: either a proof that the target cannot be reached (every branch of G
/// ends in a proved dead end), or the planner gave up within its budget on some branch
/// (then a bigger budget may find one). The two have distinct codes:
/// `declutter::plan::infeasible` and `declutter::plan::gave_up`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.headline())]
pub struct Infeasible {
    /// The target object's name, or `ROBOT at [...]` for a configuration target.
    pub target: String,
    pub span: Span,
    pub causes: Vec<Cause>,
    /// Every dead end the target's failure rests on is proved (see [`Graph::proved`]).
    pub proved: bool,
}

impl Diagnostic for Infeasible {
    fn code<'a>(&'a self) -> Option<Box<dyn Display + 'a>> {
        Some(Box::new(if self.is_proof() { "declutter::plan::infeasible" } else { "declutter::plan::gave_up" }))
    }
    fn help<'a>(&'a self) -> Option<Box<dyn Display + 'a>> {
        Some(Box::new(if self.is_proof() {
            "every way to the target was explored; the notes below say where each one ends"
        } else {
            "this is not a proof that no schedule exists: the planner stopped at its budget; the notes below say where"
        }))
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(std::iter::once(LabeledSpan::new_with_span(Some("the target".into()), self.span))))
    }
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        Some(Box::new(self.causes.iter().map(|c| c as &dyn Diagnostic)))
    }
}

/// One dead end of G.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum Cause {
    /// Every robot's flag is Null for this object, each with a proof.
    #[error("no robot can grasp `{name}` ({})", why(reasons))]
    #[diagnostic(code(declutter::plan::ungraspable))]
    Ungraspable {
        object: ObjectId,
        name: String,
        /// Robot name and why it cannot, per robot.
        reasons: Vec<(String, Reason)>,
        #[label("`{name}` is declared here")]
        span: Span,
    },
    /// The robot of a configuration target cannot reach it whatever is removed.
    #[error("`{robot}` cannot reach the target configuration: {}", reason.text)]
    #[diagnostic(code(declutter::plan::unreachable_target))]
    TargetUnreachable {
        robot: String,
        reason: Reason,
        #[label("this configuration")]
        span: Span,
    },
    /// No robot found a way to `what` (grasping an object, or reaching the target
    /// configuration), and at least one gave up at its sampling budget.
    #[error("no path {what} was found within the planning budget ({})", why(reasons))]
    #[diagnostic(code(declutter::plan::budget_exhausted))]
    NotFound {
        /// `to grasp `can`` or `for `r1` to the target configuration`.
        what: String,
        reasons: Vec<(String, Reason)>,
        #[label("{label}")]
        span: Span,
        label: String,
        /// The figures and the setting to raise; holds the time spent, so it is only
        /// rendered, never written into a schedule.
        #[help]
        advice: String,
    },
    /// Some robot's failure on the target is no proof: it gave up within its budget, or
    /// the path it found needs removals that cannot be made but that only its roadmap
    /// asked for (a path around them may exist beyond the budget).
    #[error("nothing proves there is no way {what}: {}", reasons.join("; "))]
    #[diagnostic(code(declutter::plan::not_proved))]
    Unproved {
        /// `to grasp `can`` or `for `r1` to the target configuration`.
        what: String,
        /// Per robot not proved, why (`r1`'s path needs `o6` removed, ...).
        reasons: Vec<String>,
        #[label("{label}")]
        span: Span,
        label: String,
        #[help]
        advice: String,
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

/// One robot's [`Unreachable`] in scenario terms: the flag and its text (bodies, links
/// and joints by name; grasps only for an object).
#[derive(Clone, Debug, PartialEq)]
pub struct Reason {
    pub why: Unreachable,
    pub text: String,
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

    /// Whether every dead end is proved; false when some branch only ran out of budget.
    pub fn is_proof(&self) -> bool {
        self.proved && !self.causes.iter().any(|c| matches!(c, Cause::NotFound { .. } | Cause::Unproved { .. }))
    }

    fn headline(&self) -> String {
        if self.is_proof() {
            format!("`{}` cannot be reached", self.target)
        } else {
            format!("no way to `{}` was found within the planning budget", self.target)
        }
    }
}

/// What a goal is, for messages: an object is grasped, a configuration reached.
#[derive(Clone, Copy)]
enum Aim {
    Object,
    Config,
}

/// A one-line description of an [`Unreachable`], naming bodies, links and joints.
pub fn describe(scn: &Scenario, u: &Unreachable) -> String {
    describe_for(scn, u, Aim::Object)
}

fn describe_for(scn: &Scenario, u: &Unreachable, aim: Aim) -> String {
    match (u, aim) {
        (Unreachable::NoGraspSolution, _) => "no grasp has an inverse-kinematics solution clear of fixed bodies".into(),
        (Unreachable::NoGrasp { why }, _) => why.clone(),
        (Unreachable::ApproachBlocked { blockers }, _) if blockers.is_empty() => {
            "every grasp's pre-grasp touches the object itself".into()
        }
        (Unreachable::ApproachBlocked { blockers }, _) => {
            let hits: Vec<String> = blockers.iter().map(|b| blocker(scn, b)).collect();
            format!(
                "its grasps are reachable, but every approach or retreat carrying it is blocked: {}",
                hits.join(", ")
            )
        }
        (Unreachable::GoalBlocked(Blocker::JointLimit { joint, value }), _) => {
            format!("it is outside the limits of joint `{joint}` ({value:.4} rad)")
        }
        (Unreachable::GoalBlocked(b), Aim::Config) => format!("at that configuration, {}", blocker(scn, b)),
        (Unreachable::GoalBlocked(b), Aim::Object) => format!("the goal configuration is blocked: {}", blocker(scn, b)),
        (Unreachable::DropBlocked(b), _) => format!("where it releases objects, {}", blocker(scn, b)),
        (Unreachable::BudgetExhausted(b), aim) => {
            let to = match aim {
                Aim::Object => "a grasp",
                Aim::Config => "it",
            };
            // The free-space trees grown beside the roadmap's rounds, when they were.
            let then = match b.extensions {
                0 => String::new(),
                n => format!(", then {n} free-space RRT-Connect extensions"),
            };
            if b.timed_out {
                format!("no path to {to} within `time_budget` ({} samples drawn{then})", b.samples)
            } else {
                format!("no path to {to} within {} samples{then}", b.samples)
            }
        }
    }
}

/// A block in scenario terms: which link or carried object hits which body.
fn blocker(scn: &Scenario, b: &Blocker) -> String {
    let fixed = |f: &FixedId| scn.fixed.get(f.index()).map_or_else(|| format!("#{}", f.0), |f| f.name.clone());
    let object = |o: &ObjectId| scn.object(*o).body.name.clone();
    match b {
        Blocker::Fixed { body, link } => format!("link `{link}` hits fixed body `{}`", fixed(body)),
        Blocker::HeldFixed { object: o, body } => {
            format!("carried `{}` hits fixed body `{}`", object(o), fixed(body))
        }
        Blocker::Robot { other, link, other_link } => {
            format!("link `{link}` hits link `{other_link}` of robot `{}` at its home", scn.robot(*other).name)
        }
        Blocker::HeldRobot { object: o, other, other_link } => {
            format!("carried `{}` hits link `{other_link}` of robot `{}`", object(o), scn.robot(*other).name)
        }
        Blocker::SelfCollision { link_a, link_b } => format!("links `{link_a}` and `{link_b}` collide"),
        Blocker::HeldSelf { object: o, link } => format!("carried `{}` hits link `{link}`", object(o)),
        Blocker::JointLimit { joint, value } => format!("joint `{joint}` = {value:.4} rad is outside its limits"),
    }
}

fn why(reasons: &[(String, Reason)]) -> String {
    if reasons.is_empty() {
        return "the scenario declares no robot".to_string();
    }
    reasons.iter().map(|(r, u)| format!("`{r}`: {}", u.text)).collect::<Vec<_>>().join("; ")
}

fn summary(causes: &[Cause]) -> String {
    if causes.is_empty() {
        return "no robot has a path to it".to_string();
    }
    causes.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
}

fn duration(ms: f64) -> String {
    if ms < 1e3 {
        format!("{ms:.1} ms")
    } else {
        format!("{:.2} s", ms / 1e3)
    }
}

/// The figures of the robots that gave up, and the settings to raise.
fn advice(scn: &Scenario, gave_up: &[(String, Budget, f64)]) -> String {
    let figures: Vec<String> =
        gave_up.iter().map(|(r, b, ms)| format!("`{r}` drew {} samples in {}", b.samples, duration(*ms))).collect();
    let max = scn.planner.max_samples;
    let raise = if gave_up.iter().any(|g| g.1.timed_out) {
        format!("raise `time_budget` (or remove it) and `max_samples` (now {max}) in the `planner` block")
    } else {
        format!("raise `max_samples` in the `planner` block (now {max}; e.g. `max_samples {}`)", max.saturating_mul(4))
    };
    format!("{}; a path may exist: {raise}", figures.join(", "))
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
            let aim = match node.item {
                Item::Object(_) => Aim::Object,
                Item::Config => Aim::Config,
            };
            let mut gave_up = Vec::new();
            let mut reasons = Vec::new();
            for (r, _) in &node.flags {
                let Some(Answer { result: Err(u), stats }) = graph.answer(*r, node.item) else { continue };
                let robot = scn.robot(*r).name.clone();
                if let Unreachable::BudgetExhausted(b) = u {
                    gave_up.push((robot.clone(), *b, stats.time_ms));
                }
                reasons.push((robot, Reason { why: u.clone(), text: describe_for(scn, u, aim) }));
            }
            match (aim_of(scn, node.item), node.item, &scn.target) {
                (None, ..) => {}
                (Some((what, span, label)), ..) if !gave_up.is_empty() => {
                    causes.push(Cause::NotFound { what, reasons, span, label, advice: advice(scn, &gave_up) })
                }
                (Some((_, span, _)), Item::Object(object), _) => {
                    let name = scn.object(object).body.name.clone();
                    causes.push(Cause::Ungraspable { object, name, reasons, span });
                }
                (Some((_, span, _)), Item::Config, Target::Config { robot, .. }) => {
                    if let Some((_, reason)) = reasons.into_iter().next() {
                        causes.push(Cause::TargetUnreachable { robot: scn.robot(*robot).name.clone(), reason, span })
                    }
                }
                (Some(_), Item::Config, Target::Object { .. }) => {}
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
    let proved = graph.proved(graph.root);
    if !proved && !causes.iter().any(|c| matches!(c, Cause::NotFound { .. })) {
        causes.insert(0, unproved(scn, graph, span));
    }
    Infeasible { target, span, causes, proved }
}

/// What a node's item is for messages (`to grasp `can`` or `for `r1` to the target
/// configuration`), where to point and the label there; `None` for the configuration
/// pseudo-node of an object target.
fn aim_of(scn: &Scenario, item: Item) -> Option<(String, Span, String)> {
    match (item, &scn.target) {
        (Item::Object(o), _) => {
            let name = &scn.object(o).body.name;
            Some((format!("to grasp `{name}`"), scn.object(o).body.span, format!("`{name}` is declared here")))
        }
        (Item::Config, Target::Config { robot, q, .. }) => Some((
            format!("for `{}` to the target configuration", scn.robot(*robot).name),
            q.span,
            "this configuration".into(),
        )),
        (Item::Config, Target::Object { .. }) => None,
    }
}

/// Why the root's failure is no proof, robot by robot.
fn unproved(scn: &Scenario, graph: &Graph, target: Span) -> Cause {
    let root = graph.node(graph.root);
    let mut reasons = Vec::new();
    for (r, flag) in &root.flags {
        let Some(a) = graph.answer(*r, root.item).filter(|_| !graph.proved_for(graph.root, *r)) else { continue };
        let robot = &scn.robot(*r).name;
        match (&a.result, flag) {
            (Err(u), _) if !u.is_proof() => reasons.push(format!("`{robot}` gave up within its budget")),
            (Ok(p), Flag::Blocked | Flag::Discarded) => {
                let names: Vec<String> = p
                    .removals
                    .iter()
                    .filter(|o| !p.forced.contains(*o))
                    .map(|o| format!("`{}`", scn.object(o).body.name))
                    .collect();
                if names.is_empty() {
                    // Every removal is forced; some object's own failure below is no proof.
                    reasons.push(format!("`{robot}` needs objects removed that nothing proves impossible to remove"));
                } else {
                    let them = if names.len() == 1 { "it" } else { "them" };
                    reasons.push(format!(
                        "the path `{robot}` found needs {} removed, which the objects' own dead ends below rule out, but only its roadmap asked for {them}",
                        names.join(", ")
                    ));
                }
            }
            _ => {}
        }
    }
    let (what, span, label) =
        aim_of(scn, root.item).unwrap_or_else(|| ("to the target".into(), target, "the target".into()));
    let max = scn.planner.max_samples;
    Cause::Unproved {
        what,
        reasons,
        span,
        label,
        advice: format!(
            "a bigger roadmap may find a way: raise `max_samples` in the `planner` block (now {max}; e.g. `max_samples {}`)",
            max.saturating_mul(4)
        ),
    }
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
