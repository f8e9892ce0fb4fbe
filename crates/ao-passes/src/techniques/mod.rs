//! The built-in techniques, one file each; registering one is one line here.

pub mod gtao;
pub mod hbao;
pub mod mssao;
pub mod none;
pub mod pyramid_hbao;
pub mod rtao;
pub(crate) mod slices;
pub mod ssao;
pub mod ssdo;
pub mod tssao;
pub mod vbao;

use std::sync::Arc;

use aograph_frame::{GBufferChannel, GBufferChannels};

use crate::technique::DynAoTechnique;

/// Linear depth and view-space normals: what the depth-buffer estimators (ssao, hbao,
/// pyramid-hbao, and gtao's and vbao's slices) read.
pub(crate) fn depth_and_normals() -> GBufferChannels {
    GBufferChannels::of(&[GBufferChannel::LinearDepth, GBufferChannel::Normals])
}

/// Every built-in technique (the registry's `with_builtins`).
pub(crate) fn builtins() -> Vec<Arc<dyn DynAoTechnique>> {
    vec![
        Arc::new(none::NoAo),
        Arc::new(tssao::Tssao),
        Arc::new(pyramid_hbao::PyramidHbao),
        Arc::new(mssao::Mssao),
        Arc::new(ssao::Ssao),
        Arc::new(hbao::Hbao),
        Arc::new(ssdo::Ssdo),
        Arc::new(gtao::Gtao),
        Arc::new(vbao::Vbao),
        Arc::new(rtao::Rtao),
    ]
}
