//! Frame inputs: data beyond the g-buffer that a frame's passes read (the `View` block, the
//! scene's lighting, its BVH or acceleration structures, or an application's own), each a type
//! implementing [`FrameInput`]. A technique declares the inputs it reads while it builds and
//! gets their graph handles ([`DeclaredInputs::declare`]); whoever owns the frame (the
//! renderer, the embedding, an application) binds what was declared, for each plan, by those
//! handles ([`DeclaredInputs::bind`]), and builds nothing that was not declared.
//!
//! Invariant: a graph declares each input once ([`DeclaredInputs::declare`] returns the first
//! declaration's handles again), and [`DeclaredInputs`] lists exactly the inputs the graph
//! declared, in the order they were first declared.

use std::any::{Any, TypeId};
use std::marker::PhantomData;
use std::sync::Arc;

use aograph_graph::{BufferDesc, BufferHandle, CompiledGraph, Executor, GraphBuilder, GraphResult};

/// One kind of frame input: how a graph declares it (its imports) and how its owner's
/// resources are bound behind the handles of one plan.
///
/// Adding one: a type implementing this (here, or in your own crate), the WGSL that reads it,
/// and the owner's call to bind it (`Renderer::bind_input`, `AmbientOcclusion::bind_input`, or
/// [`DeclaredInputs::bind`] on your own executor): docs/guide/writing-a-technique.md.
pub trait FrameInput: 'static {
    /// What it is, for messages ("the scene's BVH").
    const NAME: &'static str;
    /// The graph handles its declaration returns.
    type Handles: Copy + std::fmt::Debug + PartialEq + Send + Sync + 'static;
    /// What its owner binds behind the handles (buffers, an acceleration structure).
    type Resources: ?Sized;
    /// Declares its imports in `b`.
    fn declare(b: &mut GraphBuilder) -> Self::Handles;
    /// Binds `resources` behind `handles` for `plan` (`Executor::bind_import_buffer`, ...).
    fn bind(
        exec: &mut Executor,
        plan: &CompiledGraph,
        handles: Self::Handles,
        resources: &Self::Resources,
    ) -> GraphResult<()>;
}

/// A block of data that one buffer holds, its owner fills and passes read as a uniform (the
/// View block, the scene's lighting, an application's exposure): the frame input
/// [`BufferInput<Self>`](BufferInput).
pub trait BufferBlock: bytemuck::Pod {
    /// What it is, for messages ("the View block").
    const NAME: &'static str;
    /// The name the graph imports its buffer under (summaries, DOT, messages).
    const IMPORT: &'static str;
}

/// The frame input of one buffer holding a `B`: declared as an import of `size_of::<B>()`
/// bytes, bound to the owner's `wgpu::Buffer`.
pub struct BufferInput<B>(PhantomData<B>);

impl<B: BufferBlock> FrameInput for BufferInput<B> {
    const NAME: &'static str = B::NAME;
    type Handles = BufferHandle;
    type Resources = wgpu::Buffer;
    fn declare(b: &mut GraphBuilder) -> BufferHandle {
        b.import_buffer(
            B::IMPORT,
            BufferDesc {
                size: std::mem::size_of::<B>() as u64,
            },
        )
    }
    fn bind(
        exec: &mut Executor,
        plan: &CompiledGraph,
        handles: BufferHandle,
        buffer: &wgpu::Buffer,
    ) -> GraphResult<()> {
        exec.bind_import_buffer(plan, handles, buffer.clone())
    }
}

/// One declared input: its type, name and handles.
#[derive(Clone)]
struct Declared {
    input: TypeId,
    name: &'static str,
    handles: Arc<dyn Any + Send + Sync>,
}

/// The frame inputs a graph declared, with their handles (see the module docs).
#[derive(Clone, Default)]
pub struct DeclaredInputs {
    inputs: Vec<Declared>,
}

impl DeclaredInputs {
    /// Declares input `I` in `b`, or returns its handles when it was declared already.
    pub fn declare<I: FrameInput>(&mut self, b: &mut GraphBuilder) -> I::Handles {
        if let Some(h) = self.get::<I>() {
            return h;
        }
        let handles = I::declare(b);
        self.inputs.push(Declared {
            input: TypeId::of::<I>(),
            name: I::NAME,
            handles: Arc::new(handles),
        });
        handles
    }
    /// The handles of input `I`, when the graph declared it.
    pub fn get<I: FrameInput>(&self) -> Option<I::Handles> {
        self.inputs
            .iter()
            .find(|d| d.input == TypeId::of::<I>())
            .and_then(|d| d.handles.downcast_ref::<I::Handles>().copied())
    }
    /// Whether the graph declared input `I`.
    pub fn contains<I: FrameInput>(&self) -> bool {
        self.get::<I>().is_some()
    }
    /// Whether the graph declared the input of type `input` (`TypeId::of::<I>()`).
    pub fn contains_type(&self, input: TypeId) -> bool {
        self.inputs.iter().any(|d| d.input == input)
    }
    /// The declared inputs as (type, name), in declaration order.
    pub fn iter(&self) -> impl Iterator<Item = (TypeId, &'static str)> + '_ {
        self.inputs.iter().map(|d| (d.input, d.name))
    }
    /// Binds `resources` behind input `I`'s handles for `plan` when the graph declared it;
    /// returns whether it did.
    pub fn bind<I: FrameInput>(
        &self,
        exec: &mut Executor,
        plan: &CompiledGraph,
        resources: &I::Resources,
    ) -> GraphResult<bool> {
        match self.get::<I>() {
            Some(h) => I::bind(exec, plan, h, resources).map(|()| true),
            None => Ok(false),
        }
    }
}

impl std::fmt::Debug for DeclaredInputs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.inputs.iter().map(|d| d.name))
            .finish()
    }
}

/// Binds one input's resources for a plan, when the plan declared the input.
type Binder =
    Arc<dyn Fn(&mut Executor, &CompiledGraph, &DeclaredInputs) -> GraphResult<bool> + Send + Sync>;

/// The frame inputs an owner supplies (the renderer's View block, lighting and BVH; an
/// application's own), each with its resources, bound to every plan that declares it.
#[derive(Clone, Default)]
pub struct InputBindings {
    inputs: Vec<(TypeId, &'static str, Binder)>,
}

impl InputBindings {
    /// Supplies `resources` for input `I` from now on (replacing what was supplied before).
    pub fn set<I: FrameInput>(&mut self, resources: I::Resources)
    where
        I::Resources: Sized + Send + Sync,
    {
        let binder: Binder =
            Arc::new(move |exec, plan, declared| declared.bind::<I>(exec, plan, &resources));
        let id = TypeId::of::<I>();
        match self.inputs.iter_mut().find(|(t, _, _)| *t == id) {
            Some(slot) => slot.2 = binder,
            None => self.inputs.push((id, I::NAME, binder)),
        }
    }
    /// Stops supplying input `I` (releasing its resources).
    pub fn remove<I: FrameInput>(&mut self) {
        let id = TypeId::of::<I>();
        self.inputs.retain(|(t, _, _)| *t != id);
    }
    /// Whether input `I` is supplied.
    pub fn supplies<I: FrameInput>(&self) -> bool {
        self.supplies_type(TypeId::of::<I>())
    }
    fn supplies_type(&self, input: TypeId) -> bool {
        self.inputs.iter().any(|(t, _, _)| *t == input)
    }
    /// The name of the first input `declared` lists that nothing here supplies.
    pub fn missing(&self, declared: &DeclaredInputs) -> Option<&'static str> {
        declared
            .iter()
            .find(|(t, _)| !self.supplies_type(*t))
            .map(|(_, name)| name)
    }
    /// Binds, for `plan`, every supplied input it declared.
    pub fn bind(
        &self,
        exec: &mut Executor,
        plan: &CompiledGraph,
        declared: &DeclaredInputs,
    ) -> GraphResult<()> {
        for (_, _, bind) in &self.inputs {
            bind(exec, plan, declared)?;
        }
        Ok(())
    }
}
