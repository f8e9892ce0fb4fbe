#include "common/view.wgsl"
// Shading for shaded.png: albedo * ambient * accessibility + unshadowed direct light, with a
// sky colour where the g-buffer is empty, encoded to sRGB.

@group(0) @binding(0) var albedo: texture_2d<f32>;
@group(0) @binding(1) var direct_light: texture_2d<f32>;
@group(0) @binding(2) var ao: texture_2d<f32>;
@group(0) @binding(3) var<uniform> view: View;
@group(0) @binding(4) var<uniform> ambient: vec4<f32>;
@group(0) @binding(5) var shaded: texture_storage_2d<rgba8unorm, write>;

fn to_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shaded);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let a = textureLoad(albedo, p, 0);
    var color: vec3<f32>;
    if (a.a < 0.5) {
        // Sky: a gradient from horizon to zenith.
        let uv = pixel_uv(p, view);
        color = mix(vec3<f32>(0.75, 0.82, 0.9), vec3<f32>(0.35, 0.5, 0.75), 1.0 - uv.y);
    } else {
        let occ = clamp(textureLoad(ao, p, 0).r, 0.0, 1.0);
        // Scale so a fully lit, unoccluded white surface lands near 1 before clamping.
        color = 0.35 * (a.rgb * ambient.rgb * occ * 2.0 + textureLoad(direct_light, p, 0).rgb);
    }
    textureStore(shaded, p, vec4<f32>(to_srgb(color), 1.0));
}
