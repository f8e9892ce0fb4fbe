//! Resource lifetimes over the execution order and reuse of physical textures.
//!
//! wgpu has no memory aliasing, so reuse means whole textures: two transient resources share a
//! physical texture only when their descriptors are equal and their lifetimes (first to last
//! use in the order) do not overlap. Exported resources live to the end of the frame; imported
//! and history resources are never pooled here.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use crate::declaration::{GraphDecl, PassId, ResourceKind, ResourceOrigin};
use crate::resource::{Extent, TextureDesc};

/// First and last position in the execution order that uses a resource (inclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lifetime {
    /// Position in `CompiledGraph::order` of the first pass that uses the resource.
    pub first: usize,
    /// Position of the last pass that uses it (the last position for exported resources).
    pub last: usize,
}

impl Lifetime {
    /// True when the two ranges share a position, so the resources cannot share a texture.
    pub fn overlaps(&self, o: &Lifetime) -> bool {
        self.first <= o.last && o.first <= self.last
    }
}

/// One physical texture and the resources that take turns in it.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalTexture {
    /// The descriptor every resource placed in it has.
    pub desc: TextureDesc,
    /// The union of the usages its resources need: the texture is created with these.
    pub usage: wgpu::TextureUsages,
    /// Indices in `GraphDecl::resources` of the resources that take turns in it, in order of
    /// first use.
    pub resources: Vec<usize>,
    /// The union of the lifetimes placed in it (for the summary).
    pub busy_until: usize,
}

/// The slots of one descriptor during planning.
#[derive(Default)]
struct DescSlots {
    busy: BinaryHeap<Reverse<(usize, usize)>>,
    free: BinaryHeap<Reverse<usize>>,
}

pub(crate) struct LifetimePlan {
    pub lifetimes: Vec<Option<Lifetime>>,
    pub physical: Vec<PhysicalTexture>,
    pub slot_of: Vec<Option<usize>>,
    pub usage: Vec<wgpu::TextureUsages>,
}

pub(crate) fn plan_lifetimes(decl: &GraphDecl, order: &[PassId], reuse: bool) -> LifetimePlan {
    let n = decl.resources.len();
    let mut lifetimes: Vec<Option<Lifetime>> = vec![None; n];
    let mut usage = vec![wgpu::TextureUsages::empty(); n];
    for (pos, p) in order.iter().enumerate() {
        let pass = &decl.passes[p.0];
        let ids = pass
            .textures
            .iter()
            .map(|u| (u.resource(), u.access.usage()))
            .chain(pass.buffers.iter().map(|u| {
                (
                    u.read.or(u.written).map(|h| h.id as usize).unwrap_or(0),
                    wgpu::TextureUsages::empty(),
                )
            }));
        for (r, u) in ids {
            usage[r] |= u;
            let l = lifetimes[r].get_or_insert(Lifetime {
                first: pos,
                last: pos,
            });
            l.last = l.last.max(pos);
        }
    }
    let end = order.len().saturating_sub(1);
    for (r, res) in decl.resources.iter().enumerate() {
        if res.exported {
            usage[r] |= wgpu::TextureUsages::COPY_SRC;
            if let Some(l) = &mut lifetimes[r] {
                l.last = end;
            }
        }
    }

    // Greedy interval assignment, in order of first use.
    let mut transient: Vec<usize> = (0..n)
        .filter(|&r| {
            lifetimes[r].is_some()
                && decl.resources[r].origin == ResourceOrigin::Transient
                && matches!(decl.resources[r].kind, ResourceKind::Texture(_))
        })
        .collect();
    transient.sort_by_key(|&r| (lifetimes[r].map(|l| l.first), r));
    let mut physical: Vec<PhysicalTexture> = Vec::new();
    let mut slot_of = vec![None; n];
    // Per descriptor: slots still busy (by the last position that uses them) and free slots
    // (lowest index first), so each resource takes the lowest-numbered free slot of its
    // descriptor without scanning every slot.
    let mut by_desc: HashMap<TextureDesc, DescSlots> = HashMap::new();
    for r in transient {
        let (Some(life), Some(desc)) = (lifetimes[r], decl.resources[r].texture_desc().copied())
        else {
            continue;
        };
        let slots = by_desc.entry(desc).or_default();
        while let Some(&Reverse((until, slot))) = slots.busy.peek() {
            if until >= life.first {
                break;
            }
            slots.busy.pop();
            slots.free.push(Reverse(slot));
        }
        let free = if reuse {
            slots.free.pop().map(|Reverse(s)| s)
        } else {
            None
        };
        let slot = match free {
            Some(s) => s,
            None => {
                physical.push(PhysicalTexture {
                    desc,
                    usage: wgpu::TextureUsages::empty(),
                    resources: Vec::new(),
                    busy_until: 0,
                });
                physical.len() - 1
            }
        };
        let s = &mut physical[slot];
        s.usage |= usage[r];
        s.resources.push(r);
        s.busy_until = life.last;
        slots.busy.push(Reverse((life.last, slot)));
        slot_of[r] = Some(slot);
    }
    LifetimePlan {
        lifetimes,
        physical,
        slot_of,
        usage,
    }
}

/// Texture bytes of a plan at an output size: (with reuse as planned, if every transient
/// resource had its own texture). Imported and history textures are counted in both.
pub fn texture_bytes(plan: &crate::CompiledGraph, output: Extent) -> (u64, u64) {
    let decl = &plan.decl;
    let mut unshared = 0;
    let mut persistent = 0;
    for (r, res) in decl.resources.iter().enumerate() {
        let (Some(desc), Some(_)) = (res.texture_desc(), plan.lifetimes[r]) else {
            continue;
        };
        match res.origin {
            ResourceOrigin::Transient => unshared += desc.bytes(output),
            ResourceOrigin::Imported => persistent += desc.bytes(output),
            // History keeps two textures (previous and current) per name; count it once per half.
            ResourceOrigin::HistoryPrevious { .. } | ResourceOrigin::HistoryCurrent { .. } => {
                persistent += desc.bytes(output)
            }
        }
    }
    let shared: u64 = plan.physical.iter().map(|s| s.desc.bytes(output)).sum();
    (shared + persistent, unshared + persistent)
}
