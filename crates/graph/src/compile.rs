//! Compile phase: pure, no GPU. Validates a declaration, orders its passes, culls what no
//! output needs, and plans resource lifetimes and physical reuse.
//!
//! Invariants of a [`CompiledGraph`]: `order` respects every producer-to-consumer and
//! write-after-read edge and is stable by declaration order; a kept pass reaches an exported
//! resource, a history write or a side effect; resources sharing a physical texture have
//! disjoint lifetimes. Plans are cached by the declaration's structure hash.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::{Dfs, Reversed};

use crate::binding_slots::BindingSlot;
use crate::declaration::*;
use crate::device_fit::{DeviceProfile, check_plan};
use crate::error::{GraphError, GraphResult};
use crate::history_slots::{HistorySlot, resolve_histories};
use crate::lifetime::{Lifetime, PhysicalTexture, plan_lifetimes};
use crate::sampler::SamplerDesc;
use crate::shader::{ShaderLibrary, ShaderModuleInfo, ShaderRevision};
use crate::shader_check::check_pass_shader;

mod validate;
use validate::{validate_attachments, validate_names, validate_reads};

/// Compile options.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CompileOptions {
    /// Let resources with equal descriptors and disjoint lifetimes share a physical texture.
    pub reuse: bool,
}

impl Default for CompileOptions {
    fn default() -> Self {
        Self { reuse: true }
    }
}

/// A plan's identity in the executor: see [`CompiledGraph::key`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PlanKey {
    /// The declaration's structure hash ([`GraphDecl::structure_hash`]).
    pub structure: u64,
    /// Whether the plan was compiled with [`CompileOptions::reuse`].
    pub reuse: bool,
}

/// Why a pass was culled.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CulledPass {
    /// The pass that will not run.
    pub pass: PassId,
    /// Why, in words, for summaries and debug output.
    pub reason: String,
}

/// The result of compile: an execution plan.
#[derive(Debug)]
pub struct CompiledGraph {
    /// The declaration the plan runs: on a compile-cache hit the caller's newest one, so its
    /// custom passes and uniform contents are current.
    pub decl: Arc<GraphDecl>,
    /// The declaration's structure hash ([`GraphDecl::structure_hash`]).
    pub hash: u64,
    /// The options the plan was compiled with.
    pub options: CompileOptions,
    /// Kept passes in execution order.
    pub order: Vec<PassId>,
    /// Passes that will not run, in declaration order, with the reason.
    pub culled: Vec<CulledPass>,
    /// Dependency edges (producer, consumer) between passes, culled ones included.
    pub edges: Vec<(PassId, PassId)>,
    /// Per resource: first and last position in `order` that uses it (`None` when unused).
    pub lifetimes: Vec<Option<Lifetime>>,
    /// Physical textures of transient resources.
    pub physical: Vec<PhysicalTexture>,
    /// Per resource: its physical texture, for transient textures that are used.
    pub slot_of: Vec<Option<usize>>,
    /// Per resource: the union of the usages its uses need.
    pub usage: Vec<wgpu::TextureUsages>,
    /// Per pass: the reflected shader, for compute and full-screen passes.
    pub shaders: Vec<Option<Arc<ShaderModuleInfo>>>,
    /// Per pass: where each binding of its shader takes its resource from, resolved here
    /// (`binding_slots.rs`); empty for passes without a shader and culled passes.
    pub binding_slots: Vec<Vec<BindingSlot>>,
    /// The distinct samplers the kept passes bind, indexed by `BindingSource::Sampler`.
    pub samplers: Vec<SamplerDesc>,
    /// The plan's histories, resolved here (`history_slots.rs`).
    pub histories: Vec<HistorySlot>,
    /// Per resource: the history (index into `histories`) it is a half of.
    pub history_of: Vec<Option<usize>>,
}

impl CompiledGraph {
    /// This plan with another declaration of the same structure (equal
    /// [`GraphDecl::structure_hash`]): what a compile-cache hit returns.
    fn with_declaration(&self, decl: Arc<GraphDecl>) -> Self {
        Self {
            decl,
            hash: self.hash,
            options: self.options,
            order: self.order.clone(),
            culled: self.culled.clone(),
            edges: self.edges.clone(),
            lifetimes: self.lifetimes.clone(),
            physical: self.physical.clone(),
            slot_of: self.slot_of.clone(),
            usage: self.usage.clone(),
            shaders: self.shaders.clone(),
            binding_slots: self.binding_slots.clone(),
            samplers: self.samplers.clone(),
            histories: self.histories.clone(),
            history_of: self.history_of.clone(),
        }
    }
    /// Identifies the plan for the executor: structure and compile options. Plans with equal
    /// keys share the executor's per-plan state (uniform buffers, bind groups, history).
    pub fn key(&self) -> PlanKey {
        PlanKey {
            structure: self.hash,
            reuse: self.options.reuse,
        }
    }
    /// True when `pass` survived culling and runs (it is in [`CompiledGraph::order`]).
    pub fn is_kept(&self, pass: PassId) -> bool {
        self.order.contains(&pass)
    }
    /// Names of the kept passes, in execution order.
    pub fn pass_names(&self) -> Vec<&str> {
        self.order
            .iter()
            .map(|p| self.decl.passes[p.0].name.as_str())
            .collect()
    }
    /// Names of the culled passes, in declaration order.
    pub fn culled_names(&self) -> Vec<&str> {
        self.culled
            .iter()
            .map(|c| self.decl.passes[c.pass.0].name.as_str())
            .collect()
    }
}

/// Compiles declarations, caching plans by structure hash so an unchanged graph costs a hash.
///
/// The cache is correct and bounded:
/// - A hit returns the cached plan's order, culling, lifetimes and shaders with the *new*
///   declaration attached, so custom passes (and their per-frame state, such as a g-buffer's
///   clock) and uniform contents are always the caller's latest, never an older declaration's.
/// - Uniform contents are not part of the key ([`GraphDecl::structure_hash`]): changing a
///   parameter value is a hit; the executor writes the new contents into the plan's buffers.
/// - The shader library is ([`ShaderRevision`]): a plan compiled against one library, or
///   before a source was replaced, is not served for another library or the new source.
/// - At most `capacity` plans are kept ([`GraphCompiler::DEFAULT_CAPACITY`] by default); a miss
///   beyond that evicts the least recently used plan.
/// - With a device ([`GraphCompiler::for_device`]), a plan is returned only if it fits the
///   device's limits and formats ([`crate::check_plan`]), checked once, when it is built.
pub struct GraphCompiler {
    cache: HashMap<(u64, CompileOptions, ShaderRevision), CacheEntry>,
    capacity: usize,
    uses: u64,
    compiles: usize,
    device: Option<DeviceProfile>,
}

struct CacheEntry {
    plan: Arc<CompiledGraph>,
    last_use: u64,
}

impl Default for GraphCompiler {
    fn default() -> Self {
        Self::with_capacity(Self::DEFAULT_CAPACITY)
    }
}

impl GraphCompiler {
    /// Plans kept by [`GraphCompiler::new`]: every technique and preset of a session, with room.
    pub const DEFAULT_CAPACITY: usize = 64;

    /// A compiler with an empty cache of [`GraphCompiler::DEFAULT_CAPACITY`] plans.
    pub fn new() -> Self {
        Self::default()
    }
    /// A compiler keeping at most `capacity` plans (at least 1).
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            cache: HashMap::new(),
            capacity: capacity.max(1),
            uses: 0,
            compiles: 0,
            device: None,
        }
    }
    /// A compiler whose plans must fit `device` (see [`crate::check_plan`]): a plan needing
    /// more than it allows is an error naming the pass and the limit, at compile, before any
    /// pipeline is made.
    pub fn for_device(device: DeviceProfile) -> Self {
        Self {
            device: Some(device),
            ..Self::default()
        }
    }
    /// The device plans are checked against, if any.
    pub fn device(&self) -> Option<&DeviceProfile> {
        self.device.as_ref()
    }
    /// How many times a plan was actually built (cache misses).
    pub fn compile_count(&self) -> usize {
        self.compiles
    }
    /// Plans held now (at most the capacity).
    pub fn cached_plans(&self) -> usize {
        self.cache.len()
    }
    /// The plan for `decl`: the cached structure with `decl` attached on a hit, compiled on a
    /// miss.
    pub fn compile(
        &mut self,
        decl: GraphDecl,
        shaders: &ShaderLibrary,
        options: CompileOptions,
    ) -> GraphResult<Arc<CompiledGraph>> {
        let key = (decl.structure_hash(), options, shaders.revision());
        self.uses += 1;
        if let Some(entry) = self.cache.get_mut(&key) {
            entry.last_use = self.uses;
            if let Some(e) = decl.errors.first() {
                return Err(e.clone());
            }
            let decl = Arc::new(decl);
            return Ok(Arc::new(entry.plan.with_declaration(decl)));
        }
        let plan = Arc::new(compile_hashed(decl, key.0, shaders, options)?);
        if let Some(device) = &self.device {
            check_plan(&plan, device)?;
        }
        self.compiles += 1;
        if self.cache.len() >= self.capacity {
            let oldest = self
                .cache
                .iter()
                .min_by_key(|(_, e)| e.last_use)
                .map(|(k, _)| *k);
            if let Some(k) = oldest {
                self.cache.remove(&k);
            }
        }
        self.cache.insert(
            key,
            CacheEntry {
                plan: plan.clone(),
                last_use: self.uses,
            },
        );
        Ok(plan)
    }
}

fn pass_name(decl: &GraphDecl, p: PassId) -> String {
    decl.passes[p.0].name.clone()
}

/// Every (read handle, writing?) use of a pass as (resource, version read, version written).
fn pass_uses(pass: &PassDecl) -> impl Iterator<Item = (usize, Option<u32>, Option<u32>)> + '_ {
    let t = pass.textures.iter().map(|u| {
        (
            u.resource(),
            u.read.map(|h| h.version),
            u.written.map(|h| h.version),
        )
    });
    let b = pass.buffers.iter().map(|u| {
        (
            u.read.or(u.written).map(|h| h.id as usize).unwrap_or(0),
            u.read.map(|h| h.version),
            u.written.map(|h| h.version),
        )
    });
    t.chain(b)
}

/// Checks a declaration and builds its plan. Pure: reads shader files, touches no GPU.
pub fn compile(
    decl: GraphDecl,
    shaders: &ShaderLibrary,
    options: CompileOptions,
) -> GraphResult<CompiledGraph> {
    let hash = decl.structure_hash();
    compile_hashed(decl, hash, shaders, options)
}

/// [`compile`] of a declaration whose structure hash is known.
fn compile_hashed(
    decl: GraphDecl,
    hash: u64,
    shaders: &ShaderLibrary,
    options: CompileOptions,
) -> GraphResult<CompiledGraph> {
    if let Some(e) = decl.errors.first() {
        return Err(e.clone());
    }
    validate_names(&decl)?;
    validate_reads(&decl)?;
    validate_attachments(&decl)?;

    // Dependency graph: producer -> consumer (read after write), reader -> next writer
    // (write after read), writer -> next writer (write after write).
    let mut g: DiGraph<PassId, bool> =
        DiGraph::with_capacity(decl.passes.len(), decl.passes.len() * 2);
    let nodes: Vec<NodeIndex> = (0..decl.passes.len())
        .map(|i| g.add_node(PassId(i)))
        .collect();
    let mut edges = Vec::new();
    for (pi, pass) in decl.passes.iter().enumerate() {
        for (r, read, written) in pass_uses(pass) {
            let res = &decl.resources[r];
            if let Some(v) = read {
                if let Some(p) = res.producer(v).filter(|p| p.0 != pi) {
                    add_dependency(&mut g, nodes[p.0], nodes[pi], true);
                    edges.push((p, PassId(pi)));
                }
                if let Some(next) = res.producer(v + 1).filter(|p| p.0 != pi) {
                    add_dependency(&mut g, nodes[pi], nodes[next.0], false);
                }
            }
            if let Some(w) = written {
                if let Some(prev) = res.producer(w - 1).filter(|p| p.0 != pi) {
                    add_dependency(&mut g, nodes[prev.0], nodes[pi], false);
                }
            }
        }
    }
    if let Err(cycle) = petgraph::algo::toposort(&g, None) {
        return Err(GraphError::Cycle {
            pass: pass_name(&decl, g[cycle.node_id()]),
        });
    }

    let kept = needed_passes(&decl, &g, &nodes);
    let order = stable_order(&g, &nodes, &kept);
    let culled = (0..decl.passes.len())
        .filter(|&i| !kept[i])
        .map(|i| CulledPass {
            pass: PassId(i),
            reason: "no exported output, history write or side effect depends on it".into(),
        })
        .collect();

    let mut pass_shaders = vec![None; decl.passes.len()];
    let mut binding_slots = vec![Vec::new(); decl.passes.len()];
    let mut samplers = Vec::new();
    for &p in &order {
        if let Some(checked) = check_pass_shader(&decl, p, shaders, &mut samplers)? {
            pass_shaders[p.0] = Some(checked.info);
            binding_slots[p.0] = checked.slots;
        }
    }
    let plan = plan_lifetimes(&decl, &order, options.reuse);
    edges.sort();
    edges.dedup();
    let (histories, history_of) = resolve_histories(&decl, &plan.usage);
    Ok(CompiledGraph {
        hash,
        options,
        order,
        culled,
        edges,
        lifetimes: plan.lifetimes,
        physical: plan.physical,
        slot_of: plan.slot_of,
        usage: plan.usage,
        shaders: pass_shaders,
        binding_slots,
        samplers,
        histories,
        history_of,
        decl: Arc::new(decl),
    })
}

/// Adds an ordering edge; `data` marks a read-after-write edge, which also makes `from` needed
/// by `to`. A pair keeps one edge, which is a data edge if any of its reasons is.
fn add_dependency(g: &mut DiGraph<PassId, bool>, from: NodeIndex, to: NodeIndex, data: bool) {
    match g.find_edge(from, to) {
        Some(e) => g[e] |= data,
        None => {
            g.add_edge(from, to, data);
        }
    }
}

/// Passes from which an exported resource's final version, a history write or a side effect is
/// reachable along read-after-write edges.
fn needed_passes(decl: &GraphDecl, g: &DiGraph<PassId, bool>, nodes: &[NodeIndex]) -> Vec<bool> {
    let mut kept = vec![false; decl.passes.len()];
    let mut roots: Vec<usize> = decl
        .passes
        .iter()
        .enumerate()
        .filter(|(_, p)| p.side_effect)
        .map(|(i, _)| i)
        .collect();
    for res in &decl.resources {
        let is_root = res.exported || matches!(res.origin, ResourceOrigin::HistoryCurrent { .. });
        if let Some(p) = res.writers.last().filter(|_| is_root) {
            roots.push(p.0);
        }
    }
    // Only data edges (weight true) make a pass needed; ordering edges do not. One walk from
    // all roots at once: a pass reached from several outputs is visited once.
    let data = petgraph::visit::EdgeFiltered::from_fn(g, |e| *e.weight());
    let reversed = Reversed(&data);
    let mut dfs = Dfs::empty(reversed);
    for r in roots {
        if kept[r] {
            continue;
        }
        dfs.move_to(nodes[r]);
        while let Some(n) = dfs.next(reversed) {
            kept[g[n].0] = true;
        }
    }
    kept
}

/// Kahn's algorithm taking the lowest declaration index first: a topological order that keeps
/// declaration order wherever the edges allow. It runs over all passes and emits the kept ones:
/// a culled pass still relays ordering (a reader of version v must precede a kept writer of
/// v+2 when the writer of v+1 is culled).
fn stable_order(g: &DiGraph<PassId, bool>, nodes: &[NodeIndex], kept: &[bool]) -> Vec<PassId> {
    let n = nodes.len();
    let mut indegree = vec![0usize; n];
    for e in g.raw_edges() {
        indegree[g[e.target()].0] += 1;
    }
    let mut ready: BinaryHeap<Reverse<usize>> =
        (0..n).filter(|&i| indegree[i] == 0).map(Reverse).collect();
    let mut order = Vec::with_capacity(n);
    while let Some(Reverse(i)) = ready.pop() {
        if kept[i] {
            order.push(PassId(i));
        }
        for m in g.neighbors(nodes[i]) {
            let j = g[m].0;
            indegree[j] -= 1;
            if indegree[j] == 0 {
                ready.push(Reverse(j));
            }
        }
    }
    order
}
