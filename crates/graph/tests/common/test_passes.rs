//! Shaders and passes the graph's GPU tests share: a full-screen pattern whose values are
//! multiples of 1/16 (so GPU and CPU arithmetic agree exactly), a 1-2-1 blur, a scale-and-offset
//! pass with a uniform block, a squaring pass, a history accumulator, a pass with pipeline
//! constants; and custom passes
//! that record nothing but carry a cache key or a counter.

#![allow(dead_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use aograph_graph::{CustomPass, GraphResult, PassContext, ShaderLibrary};

pub const PATTERN: &str = r#"
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let x = u32(p.x);
    let y = u32(p.y);
    return vec4<f32>(f32((x * 3u + y * 5u) % 17u) / 16.0, 0.0, 0.0, 1.0);
}
"#;

pub const BLUR: &str = r#"
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let xl = max(i32(id.x) - 1, 0);
    let xr = min(i32(id.x) + 1, i32(size.x) - 1);
    let a = textureLoad(src, vec2<i32>(xl, i32(id.y)), 0).r;
    let b = textureLoad(src, vec2<i32>(id.xy), 0).r;
    let c = textureLoad(src, vec2<i32>(xr, i32(id.y)), 0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>((a + 2.0 * b + c) * 0.25, 0.0, 0.0, 0.0));
}
"#;

pub const SCALE: &str = r#"
struct Params { scale: f32, offset: f32, pad0: f32, pad1: f32 }
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(2) var<uniform> params: Params;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(src, vec2<i32>(id.xy), 0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v * params.scale + params.offset, 0.0, 0.0, 0.0));
}
"#;

pub const SQUARE: &str = r#"
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(src, vec2<i32>(id.xy), 0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v * v, 0.0, 0.0, 0.0));
}
"#;

pub const ACCUMULATE: &str = r#"
@group(0) @binding(0) var previous: texture_2d<f32>;
@group(0) @binding(1) var current: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(previous);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(previous, vec2<i32>(id.xy), 0).r;
    textureStore(current, vec2<i32>(id.xy), vec4<f32>(v + 1.0, 0.0, 0.0, 0.0));
}
"#;

/// A gain and a repeat count as pipeline-overridable constants: dst = src * GAIN, added
/// REPEAT times in a loop (REPEAT has no default: every pass must set it).
pub const CONSTANTS: &str = r#"
override GAIN: f32 = 1.0;
override REPEAT: u32;
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(src, vec2<i32>(id.xy), 0).r;
    var sum = 0.0;
    for (var i = 0u; i < REPEAT; i = i + 1u) { sum = sum + v * GAIN; }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(sum, 0.0, 0.0, 0.0));
}
"#;

/// Every shader above, by file name.
pub fn shaders() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("pattern.wgsl", PATTERN);
    lib.add_inline("blur.wgsl", BLUR);
    lib.add_inline("scale.wgsl", SCALE);
    lib.add_inline("square.wgsl", SQUARE);
    lib.add_inline("accumulate.wgsl", ACCUMULATE);
    lib.add_inline("constants.wgsl", CONSTANTS);
    lib
}

/// The pattern's value at pixel (x, y).
pub fn pattern(x: u32, y: u32) -> f32 {
    ((x * 3 + y * 5) % 17) as f32 / 16.0
}

/// The bytes of the scale pass's uniform block.
pub fn params(scale: f32, offset: f32) -> Vec<u8> {
    [scale, offset, 0.0, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect()
}

/// A pass that records nothing, distinct per key (enters the plan's hash).
pub struct KeyedPass(pub u64);

impl CustomPass for KeyedPass {
    fn kind_name(&self) -> &str {
        "keyed"
    }
    fn cache_key(&self) -> u64 {
        self.0
    }
    fn record(&self, _ctx: &mut PassContext<'_>) -> GraphResult<()> {
        Ok(())
    }
}

/// Counts how often it was recorded.
pub struct CountingPass(pub Arc<AtomicU32>);

impl CustomPass for CountingPass {
    fn kind_name(&self) -> &str {
        "counting"
    }
    fn record(&self, _ctx: &mut PassContext<'_>) -> GraphResult<()> {
        self.0.fetch_add(1, Ordering::Relaxed);
        Ok(())
    }
}
