//! Who declared each pass of a frame: the g-buffer, the AO technique or the shading pass. A
//! frame's timings total by owner, so "the technique's time" is one rule, read from how the
//! frame graph was declared, never from a pass's name.
//!
//! Invariant: a pass has at most one owner; passes a caller adds to a built frame graph (a
//! user pass, say) have none and count under no owner.

use std::collections::BTreeMap;

use aograph_graph::{GraphBuilder, PassTimings};

/// The part of the frame a pass belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PassOwner {
    /// The g-buffer node (rasterising the scene's channels).
    GBuffer,
    /// The AO technique's passes, its adapters and blocks included.
    Technique,
    /// The shading pass behind shaded.png.
    Shading,
}

/// Every declared pass's owner, by pass name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassOwners {
    by_pass: BTreeMap<String, PassOwner>,
}

impl PassOwners {
    /// Declares the passes `declare` adds to `b` as `owner`'s.
    pub fn record<T>(
        &mut self,
        b: &mut GraphBuilder,
        owner: PassOwner,
        declare: impl FnOnce(&mut GraphBuilder) -> T,
    ) -> T {
        let before = std::mem::take(b).build();
        let first = before.passes.len();
        *b = GraphBuilder::from_decl(before);
        let out = declare(b);
        let after = std::mem::take(b).build();
        for p in &after.passes[first..] {
            self.by_pass.insert(p.name.clone(), owner);
        }
        *b = GraphBuilder::from_decl(after);
        out
    }
    /// The owner of the pass `name`, if the frame graph declared it.
    pub fn of(&self, name: &str) -> Option<PassOwner> {
        self.by_pass.get(name).copied()
    }
    /// Milliseconds of `owner`'s passes in `t`.
    pub fn total_ms(&self, t: &PassTimings, owner: PassOwner) -> f64 {
        t.passes
            .iter()
            .filter(|(name, _)| self.of(name) == Some(owner))
            .map(|(_, ms)| ms)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_graph::{SizeClass, TextureDesc};

    fn fill(b: &mut GraphBuilder, name: &str) {
        let t = b.create_texture(
            name,
            TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
        );
        let mut p = b.compute_pass(name, "ao/none.wgsl", "main");
        let t = p.write_storage("ao", t);
        p.dispatch_over(t);
    }

    #[test]
    fn passes_belong_to_the_phase_that_declared_them_and_times_total_by_owner() {
        let mut owners = PassOwners::default();
        let mut b = GraphBuilder::new();
        owners.record(&mut b, PassOwner::GBuffer, |b| fill(b, "gbuffer"));
        owners.record(&mut b, PassOwner::Technique, |b| {
            fill(b, "a");
            fill(b, "gbuffer_like_name");
        });
        fill(&mut b, "user");
        assert_eq!(
            b.build().passes.len(),
            4,
            "declaring through record loses nothing"
        );
        assert_eq!(owners.of("gbuffer"), Some(PassOwner::GBuffer));
        assert_eq!(owners.of("gbuffer_like_name"), Some(PassOwner::Technique));
        assert_eq!(owners.of("user"), None);
        let t = PassTimings {
            frame: None,
            source: None,
            passes: vec![
                ("gbuffer".into(), 1.0),
                ("a".into(), 2.0),
                ("gbuffer_like_name".into(), 4.0),
                ("user".into(), 8.0),
            ],
        };
        assert_eq!(owners.total_ms(&t, PassOwner::Technique), 6.0);
        assert_eq!(owners.total_ms(&t, PassOwner::GBuffer), 1.0);
        assert_eq!(owners.total_ms(&t, PassOwner::Shading), 0.0);
    }
}
