//! Property tests on random DAGs: order, culling, lifetimes, reuse and determinism, each
//! checked against an independent recomputation from the generated graph.

use std::cmp::Reverse;
use std::collections::{BTreeSet, BinaryHeap};

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;
use proptest::prelude::*;

const DESCS: [TextureDesc; 3] = [
    TextureDesc {
        format: TextureFormat::Rgba16Float,
        size: SizeClass::FULL,
        mip_levels: 1,
    },
    TextureDesc {
        format: TextureFormat::R32Float,
        size: SizeClass::FULL,
        mip_levels: 1,
    },
    TextureDesc {
        format: TextureFormat::Rgba16Float,
        size: SizeClass::Relative { divisor: 2 },
        mip_levels: 1,
    },
];

/// A random DAG of passes. Pass `i` writes its own texture `t{i}`; an edge (j, i) means pass
/// `i` reads `t{j}`. Edges go from lower to higher `rank`, so the graph is acyclic whatever the
/// declaration order; edges whose producer is declared later are added by reopening the
/// consumer with `GraphBuilder::pass`.
#[derive(Clone, Debug)]
struct Dag {
    n: usize,
    edges: Vec<(usize, usize)>,
    exports: Vec<bool>,
    side_effects: Vec<bool>,
    descs: Vec<usize>,
}

fn dag() -> impl Strategy<Value = Dag> {
    (2usize..40).prop_flat_map(|n| {
        let rank = prop_oneof![
            Just((0..n).collect::<Vec<usize>>()),
            Just((0..n).collect::<Vec<usize>>()).prop_shuffle()
        ];
        (
            rank,
            proptest::collection::vec(0u8..100, n * n),
            0u8..40,
            proptest::collection::vec(proptest::bool::weighted(0.15), n),
            proptest::collection::vec(proptest::bool::weighted(0.05), n),
            proptest::collection::vec(0usize..DESCS.len(), n),
        )
            .prop_map(move |(rank, bits, density, exports, side_effects, descs)| {
                let mut edges = Vec::new();
                for i in 0..n {
                    for j in 0..n {
                        if rank[j] < rank[i] && bits[i * n + j] < density {
                            edges.push((j, i));
                        }
                    }
                }
                Dag {
                    n,
                    edges,
                    exports,
                    side_effects,
                    descs,
                }
            })
    })
}

fn declare(d: &Dag) -> GraphDecl {
    let mut b = GraphBuilder::new();
    let mut ids = Vec::new();
    let mut outs: Vec<TextureHandle> = Vec::new();
    for i in 0..d.n {
        let t = b.create_texture(&format!("t{i}"), DESCS[d.descs[i]]);
        let mut p = b.custom_pass(&format!("p{i}"), NoopPass);
        for &(j, c) in &d.edges {
            if c == i && j < i {
                p.sample(&format!("in{j}"), outs[j]);
            }
        }
        if d.side_effects[i] {
            p.side_effect();
        }
        let out = p.write_storage("out", t);
        ids.push(p.id());
        outs.push(out);
    }
    for &(j, i) in &d.edges {
        if j > i {
            b.pass(ids[i]).sample(&format!("in{j}"), outs[j]);
        }
    }
    for (out, _) in outs.iter().zip(&d.exports).filter(|(_, e)| **e) {
        b.export(*out);
    }
    b.build()
}

fn compile_dag(d: &Dag, reuse: bool) -> CompiledGraph {
    compile(
        declare(d),
        &ShaderLibrary::inline_only(),
        CompileOptions { reuse },
    )
    .expect("an acyclic random graph compiles")
}

/// Passes from which an export or a side effect is reachable (reverse DFS from the roots).
fn expected_kept(d: &Dag) -> Vec<bool> {
    let mut kept = vec![false; d.n];
    let mut stack: Vec<usize> = (0..d.n)
        .filter(|&i| d.exports[i] || d.side_effects[i])
        .collect();
    while let Some(i) = stack.pop() {
        if std::mem::replace(&mut kept[i], true) {
            continue;
        }
        stack.extend(d.edges.iter().filter(|e| e.1 == i).map(|e| e.0));
    }
    kept
}

/// The topological order of the kept passes that always takes the lowest index available.
fn expected_order(d: &Dag, kept: &[bool]) -> Vec<usize> {
    let mut indeg = vec![0; d.n];
    for &(j, i) in &d.edges {
        if kept[j] && kept[i] {
            indeg[i] += 1;
        }
    }
    let mut ready: BinaryHeap<Reverse<usize>> = (0..d.n)
        .filter(|&i| kept[i] && indeg[i] == 0)
        .map(Reverse)
        .collect();
    let mut order = Vec::new();
    while let Some(Reverse(i)) = ready.pop() {
        order.push(i);
        for &(j, c) in &d.edges {
            if j == i && kept[c] {
                indeg[c] -= 1;
                if indeg[c] == 0 {
                    ready.push(Reverse(c));
                }
            }
        }
    }
    order
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_dags_compile_to_valid_plans(d in dag()) {
        let plan = compile_dag(&d, true);
        let decl = &plan.decl;
        let pos: Vec<Option<usize>> = (0..d.n).map(|i| plan.order.iter().position(|p| p.index() == i)).collect();

        // (1) Edges as declared, and the order respects each of them.
        let mut mine: Vec<(usize, usize)> = d.edges.clone();
        mine.sort();
        let theirs: Vec<(usize, usize)> = plan.edges.iter().map(|(a, b)| (a.index(), b.index())).collect();
        prop_assert_eq!(&theirs, &mine);
        for &(j, i) in &mine {
            if let (Some(pj), Some(pi)) = (pos[j], pos[i]) {
                prop_assert!(pj < pi, "edge p{} -> p{} but order {:?}", j, i, plan.pass_names());
            }
        }
        // Also straight from the declaration's uses: every read of a version runs after its writer.
        for (pi, pass) in decl.passes.iter().enumerate() {
            for u in &pass.textures {
                if let Some(h) = u.read {
                    let producer = decl.resources[h.resource_index()].producer(h.version()).unwrap();
                    if let (Some(a), Some(b)) = (pos[producer.index()], pos[pi]) {
                        prop_assert!(a < b);
                    }
                }
            }
        }

        // (2) Kept set is exactly what reaches an export or side effect; stable order.
        let kept = expected_kept(&d);
        for i in 0..d.n {
            prop_assert_eq!(pos[i].is_some(), kept[i], "p{} kept mismatch", i);
        }
        let culled: Vec<usize> = plan.culled.iter().map(|c| c.pass.index()).collect();
        prop_assert_eq!(culled, (0..d.n).filter(|&i| !kept[i]).collect::<Vec<_>>());
        prop_assert_eq!(plan.order.iter().map(|p| p.index()).collect::<Vec<_>>(), expected_order(&d, &kept));

        // Lifetimes recomputed: first and last position using t_i (writer i and its readers).
        for i in 0..d.n {
            let users: Vec<usize> = std::iter::once(i).chain(d.edges.iter().filter(|e| e.0 == i).map(|e| e.1)).filter_map(|p| pos[p]).collect();
            let expected = if users.is_empty() {
                None
            } else {
                let last = if d.exports[i] { plan.order.len() - 1 } else { *users.iter().max().unwrap() };
                Some(Lifetime { first: *users.iter().min().unwrap(), last })
            };
            prop_assert_eq!(plan.lifetimes[i], expected, "lifetime of t{}", i);
        }

        // (3) Sharing a physical texture: equal descriptors, pairwise disjoint lifetimes.
        let mut seen = BTreeSet::new();
        for (s, p) in plan.physical.iter().enumerate() {
            prop_assert!(!p.resources.is_empty());
            for (k, &a) in p.resources.iter().enumerate() {
                prop_assert!(seen.insert(a), "t{} in two physical textures", a);
                prop_assert_eq!(plan.slot_of[a], Some(s));
                prop_assert_eq!(decl.resources[a].texture_desc(), Some(&p.desc));
                prop_assert!(p.usage.contains(plan.usage[a]));
                for &b in &p.resources[k + 1..] {
                    let (la, lb) = (plan.lifetimes[a].unwrap(), plan.lifetimes[b].unwrap());
                    prop_assert!(!la.overlaps(&lb), "t{} {:?} and t{} {:?} share texture {}", a, la, b, lb, s);
                }
            }
            // An exported resource is the last user of its texture.
            for &a in &p.resources[..p.resources.len() - 1] {
                prop_assert!(!decl.resources[a].exported, "t{} is exported but its texture is reused", a);
            }
        }

        // (4) Every transient texture a kept pass uses has a slot; unused ones have none.
        for i in 0..d.n {
            prop_assert_eq!(plan.slot_of[i].is_some(), plan.lifetimes[i].is_some(), "slot of t{}", i);
        }
        for &p in &plan.order {
            for u in &decl.passes[p.index()].textures {
                prop_assert!(plan.slot_of[u.resource()].is_some());
            }
        }

        // Bytes: reuse never costs more; without reuse there is one texture per used transient.
        let (with, without) = texture_bytes(&plan, Extent::new(97, 61));
        prop_assert!(with <= without);
        let flat = compile_dag(&d, false);
        prop_assert_eq!(&flat.order, &plan.order);
        prop_assert_eq!(flat.physical.len(), plan.slot_of.iter().filter(|s| s.is_some()).count());
        let (flat_with, flat_without) = texture_bytes(&flat, Extent::new(97, 61));
        prop_assert_eq!(flat_with, flat_without);
        prop_assert_eq!(flat_without, without);
    }

    #[test]
    fn compile_is_deterministic(d in dag()) {
        let a = compile_dag(&d, true);
        let b = compile_dag(&d, true);
        prop_assert_eq!(a.hash, b.hash);
        prop_assert_eq!(declare(&d).structure_hash(), a.hash);
        prop_assert_eq!(&a.order, &b.order);
        prop_assert_eq!(&a.culled, &b.culled);
        prop_assert_eq!(&a.edges, &b.edges);
        prop_assert_eq!(&a.lifetimes, &b.lifetimes);
        prop_assert_eq!(&a.physical, &b.physical);
        prop_assert_eq!(&a.slot_of, &b.slot_of);
        prop_assert_eq!(to_dot(&a), to_dot(&b));
        prop_assert_eq!(summary(&a, Extent::new(64, 64)), summary(&b, Extent::new(64, 64)));
    }

    #[test]
    fn compiler_cache_returns_the_same_plan_for_equal_declarations(d in dag()) {
        let lib = ShaderLibrary::inline_only();
        let mut c = GraphCompiler::new();
        let a = c.compile(declare(&d), &lib, CompileOptions::default()).unwrap();
        let b = c.compile(declare(&d), &lib, CompileOptions::default()).unwrap();
        prop_assert_eq!(a.key(), b.key());
        prop_assert_eq!(&a.order, &b.order);
        prop_assert_eq!(&a.culled, &b.culled);
        prop_assert_eq!(&a.lifetimes, &b.lifetimes);
        prop_assert_eq!(&a.physical, &b.physical);
        prop_assert_eq!(c.compile_count(), 1);
    }

    #[test]
    fn adding_an_edge_against_the_order_is_a_cycle(d in dag(), pick in any::<proptest::sample::Index>()) {
        // Reversing one edge into a path that already exists closes a loop.
        prop_assume!(!d.edges.is_empty());
        let (j, i) = d.edges[pick.index(d.edges.len())];
        let mut b = GraphBuilder::new();
        let ids: Vec<PassId> = (0..d.n).map(|k| b.custom_pass(&format!("p{k}"), NoopPass).id()).collect();
        let outs: Vec<TextureHandle> = (0..d.n)
            .map(|k| {
                let t = b.create_texture(&format!("t{k}"), DESCS[d.descs[k]]);
                b.pass(ids[k]).write_storage("out", t)
            })
            .collect();
        for &(p, c) in &d.edges {
            b.pass(ids[c]).sample(&format!("in{p}"), outs[p]);
        }
        b.pass(ids[j]).sample("back", outs[i]);
        b.export(outs[i]);
        let r = compile(b.build(), &ShaderLibrary::inline_only(), CompileOptions::default());
        prop_assert!(matches!(&r, Err(GraphError::Cycle { .. })), "{:?}", r.as_ref().map(|p| p.pass_names()));
    }
}

/// The generator must actually produce the interesting cases the properties are about.
#[test]
fn generator_covers_reopened_edges_culling_and_reuse() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = dag();
    let (mut reopened, mut culled, mut shared, mut kept_many, mut large) = (0, 0, 0, 0, 0);
    for _ in 0..256 {
        let d = strategy.new_tree(&mut runner).unwrap().current();
        let plan = compile_dag(&d, true);
        reopened += d.edges.iter().any(|&(j, i)| j > i) as usize;
        culled += !plan.culled.is_empty() as usize;
        shared += plan.physical.iter().any(|p| p.resources.len() > 1) as usize;
        kept_many += (plan.order.len() >= 5) as usize;
        large += (d.n >= 30) as usize;
    }
    assert!(reopened > 50, "reopened {reopened}");
    assert!(culled > 50, "culled {culled}");
    assert!(shared > 50, "shared {shared}");
    assert!(kept_many > 50, "kept_many {kept_many}");
    assert!(large > 30, "large {large}");
}
