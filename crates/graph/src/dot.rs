//! Graphviz export of a compiled plan: passes as boxes (culled ones grey), resources as
//! ellipses, edges labelled with the access. Uses petgraph's dot writer.

use petgraph::dot::{Config, Dot};
use petgraph::graph::{DiGraph, NodeIndex};

use crate::compile::CompiledGraph;

enum Node {
    Pass { name: String, culled: bool },
    Resource(String),
}

impl std::fmt::Display for Node {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Node::Pass { name, .. } | Node::Resource(name) => f.write_str(name),
        }
    }
}

/// The plan as a DOT digraph: pass -> resource for writes, resource -> pass for reads.
pub fn to_dot(plan: &CompiledGraph) -> String {
    let decl = &plan.decl;
    let mut g: DiGraph<Node, String> = DiGraph::new();
    let passes: Vec<NodeIndex> = decl
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            g.add_node(Node::Pass {
                name: p.name.clone(),
                culled: !plan.order.iter().any(|o| o.0 == i),
            })
        })
        .collect();
    let resources: Vec<NodeIndex> = decl
        .resources
        .iter()
        .map(|r| g.add_node(Node::Resource(r.name.clone())))
        .collect();
    for (i, p) in decl.passes.iter().enumerate() {
        for u in &p.textures {
            let r = resources[u.resource()];
            let label = format!("{:?}", u.access);
            if u.read.is_some() && u.written.is_none() {
                g.add_edge(r, passes[i], label);
            } else if u.written.is_some() {
                if u.read.is_some() {
                    g.add_edge(r, passes[i], "keeps".into());
                }
                g.add_edge(passes[i], r, label);
            }
        }
        for u in &p.buffers {
            let Some(h) = u.read.or(u.written) else {
                continue;
            };
            let r = resources[h.id as usize];
            if u.written.is_some() {
                g.add_edge(passes[i], r, format!("{:?}", u.access));
            } else {
                g.add_edge(r, passes[i], format!("{:?}", u.access));
            }
        }
    }
    let node_attrs = |_, (_, n): (NodeIndex, &Node)| match n {
        Node::Pass { culled: true, .. } => {
            "shape=box, style=filled, fillcolor=lightgrey, fontcolor=grey40, color=grey60"
                .to_string()
        }
        Node::Pass { .. } => "shape=box, style=filled, fillcolor=lightblue".to_string(),
        Node::Resource(_) => "shape=ellipse".to_string(),
    };
    let edge_attrs = |_, _| String::new();
    format!(
        "{}",
        Dot::with_attr_getters(
            &g,
            &[Config::RankDir(petgraph::dot::RankDir::LR)],
            &edge_attrs,
            &node_attrs
        )
    )
}
