//! G in Graphviz DOT, drawn like the paper's figures: each node a small table with
//! the object on top and one cell per robot holding its flag (Figure 5), edges
//! coloured and labelled by robot. Several children of one node through one robot are
//! AND edges: they leave the node as one edge into a small dot, and fan out from it.
//! Edges of different robots are OR alternatives. The chosen assignment is drawn bold,
//! each chosen node names its action in the schedule (`#2`), and a legend says all this.

use std::collections::BTreeSet;
use std::fmt::Write;

use petgraph::graph::NodeIndex;

use crate::plan::andor::{Flag, Solution};
use crate::resolve::{RobotId, Scenario};

const PALETTE: [&str; 6] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

fn colour(r: RobotId) -> &'static str {
    PALETTE[r.index() % PALETTE.len()]
}

fn fill(f: Flag) -> &'static str {
    match f {
        Flag::Empty => "white",
        Flag::Null => "#d9d9d9",
        Flag::Free => "#c7e9c0",
        Flag::Blocked => "#fdd0a2",
        Flag::Discarded => "#fcbba1",
    }
}

fn html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn quoted(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The nodes and robots of the chosen assignment: from the root, the chosen robot's
/// children, recursively.
fn chosen(sol: &Solution) -> BTreeSet<(NodeIndex, RobotId)> {
    let mut out = BTreeSet::new();
    let Ok(plan) = &sol.outcome else { return out };
    let g = &sol.graph;
    let mut stack = vec![g.root];
    while let Some(n) = stack.pop() {
        if let Some(r) = plan.robot_for(g.node(n).item) {
            if out.insert((n, r)) {
                stack.extend(g.children(n, r));
            }
        }
    }
    out
}

/// The legend: flags and their fills, the edge kinds, the chosen robot, action ids.
fn legend() -> String {
    let mut rows = String::new();
    for (f, what) in [
        (Flag::Empty, "not asked"),
        (Flag::Null, "null: the robot cannot grasp it"),
        (Flag::Free, "free: a path with nothing to remove"),
        (Flag::Blocked, "blocked: a path once its children are removed"),
        (Flag::Discarded, "discarded: its path needs an object of its own branch"),
    ] {
        let _ = write!(rows, "<TR><TD BGCOLOR=\"{}\">{}</TD><TD ALIGN=\"LEFT\">{what}</TD></TR>", fill(f), f.symbol());
    }
    for (key, what) in [
        ("→", "a robot's path needs that object removed first (edges coloured by robot)"),
        ("• AND", "one robot's edges through a dot: all its children must go"),
        ("OR", "edges of different robots: alternatives"),
        ("bold", "the chosen robot (thick cell, bold edge)"),
        ("#k", "the object's action in the schedule"),
    ] {
        let _ = write!(rows, "<TR><TD>{}</TD><TD ALIGN=\"LEFT\">{what}</TD></TR>", html(key));
    }
    format!(
        "  legend [label=<<TABLE BORDER=\"1\" CELLBORDER=\"0\" CELLSPACING=\"0\" CELLPADDING=\"3\"><TR><TD COLSPAN=\"2\"><B>Legend</B></TD></TR>{rows}</TABLE>>, fontsize=10];\n"
    )
}

/// G as a DOT digraph. Deterministic: nodes in creation order, robots in order.
pub fn to_dot(scn: &Scenario, sol: &Solution) -> String {
    let g = &sol.graph;
    let chosen = chosen(sol);
    let mut out = String::new();
    let title = super::scenario_name(scn);
    let _ = writeln!(out, "digraph {} {{", quoted(&title));
    out.push_str("  // Flags per robot: ∅ not asked, N null, F free, B blocked, D discarded.\n");
    out.push_str("  // Edges by robot; one robot's edges through a dot are AND; robots are OR. Bold: chosen.\n");
    out.push_str("  graph [rankdir=TB, fontname=\"Helvetica\"];\n");
    out.push_str("  node [shape=plaintext, fontname=\"Helvetica\"];\n");
    out.push_str("  edge [fontname=\"Helvetica\", fontsize=10];\n");
    out.push_str(&legend());
    // Action ids (1-based, as in the schedule) of the chosen items.
    let action_of = |item| match &sol.outcome {
        Ok(plan) => plan.actions.iter().position(|a| a.item == item).map(|i| i + 1),
        Err(_) => None,
    };
    let mut drawn: Vec<String> = Vec::new();
    for n in g.nodes() {
        let node = g.node(n);
        let cols = node.flags.len().max(1);
        let name = node.item.name(scn);
        // A repeated object that was never analysed here reuses the answers of its first
        // node (the planner memoises them): say so, rather than leave a bare ∅.
        let unasked = node.flags.iter().all(|(_, f)| *f == crate::plan::andor::Flag::Empty);
        let mut note =
            if unasked && drawn.contains(&name) { "<BR/><FONT POINT-SIZE=\"10\">answers as above</FONT>" } else { "" }
                .to_string();
        if let Some(id) = chosen.iter().any(|(c, _)| *c == n).then(|| action_of(node.item)).flatten() {
            note = format!(" <FONT POINT-SIZE=\"10\">#{id}</FONT>{note}");
        }
        let mut label = String::new();
        let _ = write!(
            label,
            "<TABLE BORDER=\"0\" CELLBORDER=\"1\" CELLSPACING=\"0\" CELLPADDING=\"4\"><TR><TD COLSPAN=\"{cols}\"><B>{}</B>{note}</TD></TR><TR>",
            html(&name)
        );
        drawn.push(name);
        for (r, f) in &node.flags {
            let border = if chosen.contains(&(n, *r)) { " BORDER=\"3\"" } else { "" };
            let _ = write!(
                label,
                "<TD BGCOLOR=\"{}\"{border}><FONT COLOR=\"{}\">{}</FONT> {}</TD>",
                fill(*f),
                colour(*r),
                html(&scn.robot(*r).name),
                f.symbol()
            );
        }
        label.push_str("</TR></TABLE>");
        let _ = writeln!(out, "  n{} [label=<{label}>];", n.index());
    }
    for n in g.nodes() {
        let robots: Vec<RobotId> = g.node(n).flags.iter().map(|(r, _)| *r).collect();
        for r in robots {
            let children = g.children(n, r);
            let name = quoted(&scn.robot(r).name);
            let c = colour(r);
            let bold = if chosen.contains(&(n, r)) { ", penwidth=2.5" } else { "" };
            match children.as_slice() {
                [] => {}
                [child] => {
                    let _ = writeln!(
                        out,
                        "  n{} -> n{} [label={name}, color=\"{c}\", fontcolor=\"{c}\"{bold}];",
                        n.index(),
                        child.index()
                    );
                }
                many => {
                    let and = format!("and{}_{}", n.index(), r.index());
                    let _ = writeln!(out, "  {and} [shape=point, width=0.08, color=\"{c}\"];");
                    let _ = writeln!(
                        out,
                        "  n{} -> {and} [label={}, color=\"{c}\", fontcolor=\"{c}\", arrowhead=none{bold}];",
                        n.index(),
                        quoted(&format!("{} (AND)", scn.robot(r).name))
                    );
                    for child in many {
                        let _ = writeln!(out, "  {and} -> n{} [color=\"{c}\"{bold}];", child.index());
                    }
                }
            }
        }
    }
    out.push_str("}\n");
    out
}
