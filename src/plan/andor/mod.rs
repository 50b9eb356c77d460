//! The AND/OR precedence graph G of the paper's Section 4.2 and the assignment of
//! remove-actions to robots.
//!
//! In: a [`Scenario`] and an [`Oracle`] answering `findPath`. Out: a [`Solution`]: G
//! with its per-robot flags, every answer in the order asked, and either a [`Plan`]
//! (actions in order, each with the actions it waits for) or why there is none
//! ([`Infeasible`]). The expansion is the paper's Algorithm 4 (`AnalyzeNode`,
//! `expandNode`, `selectNode`); `checkGraph` is replaced by an exact AND/OR search
//! with a deterministic choice rule (see [`Plan`] and the book's "Reading the AND/OR
//! graph"). Answers are asked lazily, only for the nodes the
//! expansion reaches, and memoised per (robot, item), so the result is the same
//! whatever order or parallelism the oracle uses.

mod assign;
mod graph;
mod infeasible;

pub use assign::{Action, Plan, SEARCH_BUDGET};
pub use graph::{Edge, Flag, Graph, Item, Node, Query};
pub use infeasible::{describe, Cause, Infeasible, Reason};

use crate::plan::Oracle;
use crate::resolve::Scenario;

/// G, the answers it was built from, and the outcome.
#[derive(Clone, Debug)]
pub struct Solution {
    pub graph: Graph,
    pub outcome: Result<Plan, Infeasible>,
}

/// Algorithm 4: analyse the root, then, until an assignment frees it, expand the last
/// analysed node and analyse the cheapest unanalysed one. When none is left, explain.
pub fn solve(scn: &Scenario, oracle: &dyn Oracle) -> Solution {
    let mut graph = Graph::new(scn);
    let mut aux = Some(graph.root);
    while let Some(n) = aux {
        graph.analyse(scn, n, oracle);
        if let Some(plan) = assign::assign(&graph) {
            return Solution { graph, outcome: Ok(plan) };
        }
        graph.expand(scn, n);
        aux = graph.select();
    }
    let why = infeasible::explain(scn, &graph);
    Solution { graph, outcome: Err(why) }
}
