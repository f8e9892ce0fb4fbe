#include "common/view.wgsl"
// The view block of a half-resolution image (crates/ao-passes/src/blocks/half_resolution.rs):
// the frame's block with `size` halved and `inv_size` doubled, so half texel p's centre,
// pixel_uv(p) = (p + 0.5) 2 / W, is full pixel corner 2p + 1, the centre of its 2x2 block (also
// for odd sizes, whose last half texel covers one column), and pixels_per_unit halves. One
// invocation.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read_write> half_view: View;

@compute @workgroup_size(1)
fn main() {
    var v = view;
    v.size = view.size * 0.5;
    v.inv_size = view.inv_size * 2.0;
    half_view = v;
}
