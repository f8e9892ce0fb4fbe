#include "common/view.wgsl"
// Embedding input adapter: an application's normals to aograph's view-space normals channel
// (Rgba16Float, xyz unit, w = 1 on geometry, 0 on sky; sky is where linear depth is 0).
// ENCODING: 0 = xyz as stored (a float or snorm format), 1 = xyz packed to [0, 1]
// (n * 0.5 + 0.5: Rgb10a2Unorm, Rgba8Unorm), 2 = octahedral xy in [-1, 1] (Rg16Float,
// Rg16Snorm), 3 = octahedral xy packed to [0, 1]. WORLD_SPACE: the normals are world-space
// and are turned into view space with the view matrix (a rotation: no inverse transpose).

override ENCODING: u32 = 0u;
override WORLD_SPACE: bool = false;

@group(0) @binding(0) var normals_in: texture_2d<f32>;
@group(0) @binding(1) var linear_depth: texture_2d<f32>;
@group(0) @binding(2) var<uniform> view: View;
@group(0) @binding(3) var normals: texture_storage_2d<rgba16float, write>;
// The viewport's top-left corner in normals_in (0, 0 without one): see adapters.rs.
@group(0) @binding(4) var<uniform> viewport: vec4<u32>;

// Octahedral decoding (Cigolle et al., "A Survey of Efficient Representations for Independent
// Unit Vectors", JCGT 2014, Listing 2), the inverse of shaders/common/normal_oct.wgsl's wrap.
fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var v = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) {
        let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), v.xy >= vec2<f32>(0.0));
        v = vec3<f32>((1.0 - abs(v.yx)) * s, v.z);
    }
    return v;
}

fn decode(t: vec4<f32>) -> vec3<f32> {
    switch ENCODING {
        case 1u: { return t.xyz * 2.0 - 1.0; }
        case 2u: { return oct_decode(t.xy); }
        case 3u: { return oct_decode(t.xy * 2.0 - 1.0); }
        default: { return t.xyz; }
    }
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(normals);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    if (textureLoad(linear_depth, p, 0).r <= 0.0) {
        textureStore(normals, p, vec4<f32>(0.0));
        return;
    }
    var n = decode(textureLoad(normals_in, p + vec2<i32>(viewport.xy), 0));
    if (WORLD_SPACE) {
        n = (view.view * vec4<f32>(n, 0.0)).xyz;
    }
    let len = length(n);
    // A zero or non-finite normal on geometry: face the camera (no hemisphere is better).
    let ok = len > 1e-20 && len < 3.0e38;
    let facing = -normalize(view_position(pixel_uv(p, view), textureLoad(linear_depth, p, 0).r, view));
    textureStore(normals, p, vec4<f32>(select(facing, n / len, ok), 1.0));
}
