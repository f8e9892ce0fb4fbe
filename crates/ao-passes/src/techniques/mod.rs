//! The built-in techniques, one file each; registering one is one line here.

pub mod gtao;
pub mod hbao;
pub mod mssao;
pub mod none;
pub mod pyramid_hbao;
pub(crate) mod slices;
pub mod ssao;
pub mod ssdo;
pub mod tssao;
pub mod vbao;

use crate::registry::TechniqueRegistry;

pub(crate) fn register_builtins(r: &mut TechniqueRegistry) {
    r.register(none::NoAo);
    r.register(tssao::Tssao);
    r.register(pyramid_hbao::PyramidHbao);
    r.register(mssao::Mssao);
    r.register(ssao::Ssao);
    r.register(hbao::Hbao);
    r.register(ssdo::Ssdo);
    r.register(gtao::Gtao);
    r.register(vbao::Vbao);
}
