//! The frame's Rust blocks against the WGSL structs that read them, member by member (names
//! and byte offsets, not only the total size): `ViewUniforms` against common/view.wgsl's
//! `View` and `LightingUniforms` against ssdo's `Lighting`, as naga lays them out in a shader
//! that binds both (ao/ssdo/direct.wgsl).

use aograph_frame::{LightingUniforms, ViewUniforms};
use aograph_graph::{UniformLayout, uniform_layout_mismatch};

#[test]
fn the_view_and_lighting_blocks_match_their_wgsl_structs_field_by_field() {
    let lib = aograph_ao_passes::shader_library().unwrap();
    let info = lib.load("ao/ssdo/direct.wgsl").unwrap();
    for (global, fields) in [
        ("view", ViewUniforms::FIELDS),
        ("lighting", LightingUniforms::FIELDS),
    ] {
        let members = &info.binding(global).expect("the shader binds it").members;
        assert!(members.len() >= 8, "{global}: {members:?}");
        assert_eq!(uniform_layout_mismatch(fields, members), None, "{global}");
    }
}
