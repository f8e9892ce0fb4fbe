//! Property tests on random programs over a few shared resources with several versions each:
//! write-only overwrites, in-place (read-write) updates and reads of stale versions. These
//! exercise write-after-read and write-after-write ordering, which single-write DAGs do not.
//!
//! The strongest check simulates the plan: each physical texture holds one (resource, version)
//! at a time; every read must find exactly the version it declared, and every exported resource
//! must hold its final version at the end. That covers ordering and reuse together.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;
use proptest::prelude::*;

const DESCS: [TextureDesc; 2] = [
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
];

#[derive(Clone, Copy, Debug)]
enum Op {
    Write(usize),
    ReadWrite(usize),
    Read(usize, u8),
}

#[derive(Clone, Debug)]
struct Prog {
    descs: Vec<usize>,
    passes: Vec<(Vec<Op>, bool)>,
    exports: Vec<bool>,
}

fn prog() -> impl Strategy<Value = Prog> {
    (1usize..10, 2usize..30).prop_flat_map(|(r, n)| {
        let op = prop_oneof![
            3 => (0..r).prop_map(Op::Write),
            2 => (0..r).prop_map(Op::ReadWrite),
            4 => (0..r, any::<u8>()).prop_map(|(r, pick)| Op::Read(r, pick)),
        ];
        let pass = (
            proptest::collection::vec(op, 1..3),
            proptest::bool::weighted(0.08),
        );
        (
            proptest::collection::vec(0..DESCS.len(), r),
            proptest::collection::vec(pass, n),
            proptest::collection::vec(proptest::bool::weighted(0.4), r),
        )
            .prop_map(|(descs, passes, exports)| Prog {
                descs,
                passes,
                exports,
            })
    })
}

/// One use in the model: resource, version read, version written.
type Use = (usize, Option<u32>, Option<u32>);

struct Model {
    uses: Vec<Vec<Use>>,
    /// producer[r][v - 1] = pass that wrote version v of r.
    producer: Vec<Vec<usize>>,
    side_effects: Vec<bool>,
}

fn declare(p: &Prog) -> (GraphDecl, Model) {
    let mut b = GraphBuilder::new();
    let mut latest: Vec<TextureHandle> = p
        .descs
        .iter()
        .enumerate()
        .map(|(i, d)| b.create_texture(&format!("r{i}"), DESCS[*d]))
        .collect();
    let mut versions: Vec<Vec<TextureHandle>> = latest.iter().map(|h| vec![*h]).collect();
    let mut model = Model {
        uses: Vec::new(),
        producer: vec![Vec::new(); p.descs.len()],
        side_effects: Vec::new(),
    };
    for (pi, (ops, side)) in p.passes.iter().enumerate() {
        let mut pb = b.custom_pass(&format!("p{pi}"), NoopPass);
        if *side {
            pb.side_effect();
        }
        let mut touched = vec![false; p.descs.len()];
        let mut uses = Vec::new();
        for (k, op) in ops.iter().enumerate() {
            let binding = format!("b{k}");
            let r = match *op {
                Op::Write(r) | Op::ReadWrite(r) | Op::Read(r, _) => r,
            };
            if std::mem::replace(&mut touched[r], true) {
                continue;
            }
            let cur = latest[r].version();
            match *op {
                Op::Read(_, pick) => {
                    if cur == 0 {
                        continue;
                    }
                    let v = 1 + pick as u32 % cur;
                    pb.sample(&binding, versions[r][v as usize]);
                    uses.push((r, Some(v), None));
                }
                Op::ReadWrite(_) if cur > 0 => {
                    let h = pb.read_write_storage(&binding, latest[r]);
                    uses.push((r, Some(cur), Some(h.version())));
                    latest[r] = h;
                    versions[r].push(h);
                    model.producer[r].push(pi);
                }
                Op::Write(_) | Op::ReadWrite(_) => {
                    let h = pb.write_storage(&binding, latest[r]);
                    uses.push((r, None, Some(h.version())));
                    latest[r] = h;
                    versions[r].push(h);
                    model.producer[r].push(pi);
                }
            }
        }
        model.uses.push(uses);
        model.side_effects.push(*side);
    }
    for (r, &e) in p.exports.iter().enumerate() {
        if e {
            b.export(latest[r]);
        }
    }
    (b.build(), model)
}

impl Model {
    fn n(&self) -> usize {
        self.uses.len()
    }
    fn producer(&self, r: usize, v: u32) -> Option<usize> {
        v.checked_sub(1)
            .and_then(|i| self.producer[r].get(i as usize).copied())
    }
    /// (from, to, is_data) for read-after-write, write-after-read and write-after-write.
    fn edges(&self) -> Vec<(usize, usize, bool)> {
        let mut e = Vec::new();
        for (pi, uses) in self.uses.iter().enumerate() {
            for &(r, read, written) in uses {
                if let Some(v) = read {
                    if let Some(p) = self.producer(r, v).filter(|&p| p != pi) {
                        e.push((p, pi, true));
                    }
                    if let Some(next) = self.producer(r, v + 1).filter(|&p| p != pi) {
                        e.push((pi, next, false));
                    }
                }
                if let Some(w) = written {
                    if let Some(prev) = self.producer(r, w - 1).filter(|&p| p != pi) {
                        e.push((prev, pi, false));
                    }
                }
            }
        }
        e
    }
    fn has_cycle(&self) -> bool {
        let all = vec![true; self.n()];
        self.stable_order(&all).len() < self.n()
    }
    fn kept(&self, exports: &[bool]) -> Vec<bool> {
        let mut roots: Vec<usize> = (0..self.n()).filter(|&i| self.side_effects[i]).collect();
        for (r, &e) in exports.iter().enumerate() {
            if let (true, Some(&last)) = (e, self.producer[r].last()) {
                roots.push(last);
            }
        }
        let data: Vec<(usize, usize, bool)> = self.edges().into_iter().filter(|e| e.2).collect();
        let mut kept = vec![false; self.n()];
        while let Some(i) = roots.pop() {
            if !std::mem::replace(&mut kept[i], true) {
                roots.extend(data.iter().filter(|e| e.1 == i).map(|e| e.0));
            }
        }
        kept
    }
    fn stable_order(&self, kept: &[bool]) -> Vec<usize> {
        let mut edges = self.edges();
        edges.sort();
        edges.dedup_by_key(|e| (e.0, e.1));
        // Over all passes (culled ones relay ordering between kept ones), emitting kept ones.
        let mut indeg = vec![0; self.n()];
        for &(_, b, _) in &edges {
            indeg[b] += 1;
        }
        let mut ready: BinaryHeap<Reverse<usize>> = (0..self.n())
            .filter(|&i| indeg[i] == 0)
            .map(Reverse)
            .collect();
        let mut order = Vec::new();
        let mut visited = 0;
        while let Some(Reverse(i)) = ready.pop() {
            visited += 1;
            if kept[i] {
                order.push(i);
            }
            for &(a, b, _) in &edges {
                if a == i {
                    indeg[b] -= 1;
                    if indeg[b] == 0 {
                        ready.push(Reverse(b));
                    }
                }
            }
        }
        if visited < self.n() {
            order.clear();
        }
        order
    }
}

/// Runs the plan on symbolic contents: each physical texture holds a (resource, version).
fn simulate(plan: &CompiledGraph, model: &Model, exports: &[bool]) -> Result<(), String> {
    let mut contents: Vec<Option<(usize, u32)>> = vec![None; plan.physical.len()];
    for &p in &plan.order {
        let pi = p.index();
        for &(r, read, _) in &model.uses[pi] {
            if let Some(v) = read {
                let slot = plan.slot_of[r].ok_or(format!("r{r} read by p{pi} has no texture"))?;
                if contents[slot] != Some((r, v)) {
                    return Err(format!(
                        "p{pi} reads r{r} v{v} but texture {slot} holds {:?}; order {:?}",
                        contents[slot],
                        plan.pass_names()
                    ));
                }
            }
        }
        for &(r, _, written) in &model.uses[pi] {
            if let Some(w) = written {
                let slot =
                    plan.slot_of[r].ok_or(format!("r{r} written by p{pi} has no texture"))?;
                contents[slot] = Some((r, w));
            }
        }
    }
    for (r, &e) in exports.iter().enumerate() {
        let last = model.producer[r].len() as u32;
        if e && last > 0 {
            let slot = plan.slot_of[r].ok_or(format!("exported r{r} has no texture"))?;
            if contents[slot] != Some((r, last)) {
                return Err(format!(
                    "exported r{r} should end at v{last} but texture {slot} holds {:?}",
                    contents[slot]
                ));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_versioned_programs_compile_to_correct_plans(p in prog()) {
        let (decl, model) = declare(&p);
        let result = compile(decl, &ShaderLibrary::inline_only(), CompileOptions::default());
        if model.has_cycle() {
            // Reading a stale version while also depending on its overwriter cannot be scheduled.
            prop_assert!(matches!(result, Err(GraphError::Cycle { .. })), "expected a cycle, got {:?}", result.map(|p| p.order.clone()));
            return Ok(());
        }
        let plan = result.map_err(|e| TestCaseError::fail(format!("acyclic program failed: {e}")))?;
        let kept = model.kept(&p.exports);
        let order: Vec<usize> = plan.order.iter().map(|p| p.index()).collect();
        prop_assert_eq!(&order, &model.stable_order(&kept));
        let pos = |i: usize| order.iter().position(|&o| o == i);
        for (a, b, _) in model.edges() {
            if let (Some(pa), Some(pb)) = (pos(a), pos(b)) {
                prop_assert!(pa < pb, "edge p{} -> p{} violated in {:?}", a, b, plan.pass_names());
            }
        }
        let mut data: Vec<(usize, usize)> = model.edges().into_iter().filter(|e| e.2).map(|e| (e.0, e.1)).collect();
        data.sort();
        data.dedup();
        prop_assert_eq!(plan.edges.iter().map(|(a, b)| (a.index(), b.index())).collect::<Vec<_>>(), data);

        simulate(&plan, &model, &p.exports).map_err(TestCaseError::fail)?;
        let (decl, _) = declare(&p);
        let flat = compile(decl, &ShaderLibrary::inline_only(), CompileOptions { reuse: false }).unwrap();
        simulate(&flat, &model, &p.exports).map_err(TestCaseError::fail)?;

        for s in &plan.physical {
            for (k, &a) in s.resources.iter().enumerate() {
                for &b in &s.resources[k + 1..] {
                    prop_assert!(!plan.lifetimes[a].unwrap().overlaps(&plan.lifetimes[b].unwrap()));
                }
            }
        }
    }
}

/// The generator must produce both schedulable programs with stale reads and cyclic ones.
#[test]
fn generator_covers_stale_reads_overwrites_and_cycles() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = prog();
    let (mut cycles, mut war, mut culled, mut shared) = (0, 0, 0, 0);
    for _ in 0..256 {
        let p = strategy.new_tree(&mut runner).unwrap().current();
        let (decl, model) = declare(&p);
        if model.has_cycle() {
            cycles += 1;
            continue;
        }
        let plan = compile(
            decl,
            &ShaderLibrary::inline_only(),
            CompileOptions::default(),
        )
        .unwrap();
        let pos = |i: usize| plan.order.iter().position(|o| o.index() == i);
        // A kept write-after-read edge whose reader was declared after the overwriter.
        war += model
            .edges()
            .iter()
            .any(|&(a, b, data)| !data && a > b && pos(a).is_some() && pos(b).is_some())
            as usize;
        culled += !plan.culled.is_empty() as usize;
        shared += plan.physical.iter().any(|s| s.resources.len() > 1) as usize;
    }
    eprintln!("cycles {cycles} war {war} culled {culled} shared {shared}");
    assert!(cycles > 5, "cycles {cycles}");
    assert!(war > 10, "war {war}");
    assert!(culled > 30, "culled {culled}");
    assert!(shared > 10, "shared {shared}");
}
