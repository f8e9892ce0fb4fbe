// The viewer's picture: a full-screen triangle into the view texture (an sRGB target, so the
// values written here are linear and the stored bytes are display values). Modes:
// 0 AO (gray = accessibility, the bytes ao.png holds), 1 shaded (shaded.png's colour),
// 2 split (the technique left of `split`, the ray-traced reference right of it, a thin line
// between), 3 signed error (technique minus reference: red where the technique is too bright,
// blue where too dark, full colour at +-`error_scale`), 4 temporal split (the accumulated image
// left of `split`, the technique's own image of this frame right of it: temporal on against
// off; `per_frame` may be at half size, read at the pixel's half-size texel). Reference texels
// below 0 are not traced yet: shown as a dim checkerboard in split and heat-map modes.

struct Display { mode: u32, split: f32, error_scale: f32, pad: f32 }

@group(0) @binding(0) var ao: texture_2d<f32>;
@group(0) @binding(1) var shaded: texture_2d<f32>;
@group(0) @binding(2) var reference: texture_2d<f32>;
@group(0) @binding(3) var<uniform> display: Display;
@group(0) @binding(4) var per_frame: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

fn to_linear(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(pow((x + 0.055) / 1.055, vec3<f32>(2.4)), x / 12.92, x <= vec3<f32>(0.04045));
}

fn gray(v: f32) -> vec4<f32> {
    return vec4<f32>(to_linear(vec3<f32>(clamp(v, 0.0, 1.0))), 1.0);
}

fn pending(p: vec2<i32>) -> vec4<f32> {
    let c = f32(((p.x / 8) + (p.y / 8)) % 2);
    return gray(0.15 + 0.1 * c);
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let a = textureLoad(ao, p, 0).r;
    let r = textureLoad(reference, p, 0).r;
    let width = f32(textureDimensions(ao).x);
    switch display.mode {
        case 1u: {
            return vec4<f32>(to_linear(textureLoad(shaded, p, 0).rgb), 1.0);
        }
        case 2u: {
            let x = display.split * width;
            if (abs(frag.x - x) < 1.0) { return vec4<f32>(1.0, 0.8, 0.0, 1.0); }
            if (frag.x < x) { return gray(a); }
            if (r < 0.0) { return pending(p); }
            return gray(r);
        }
        case 3u: {
            if (r < 0.0) { return pending(p); }
            let e = clamp((a - r) / max(display.error_scale, 1e-6), -1.0, 1.0);
            let too_bright = vec3<f32>(1.0, 1.0 - e, 1.0 - e);
            let too_dark = vec3<f32>(1.0 + e, 1.0 + e, 1.0);
            return vec4<f32>(to_linear(select(too_dark, too_bright, e >= 0.0)), 1.0);
        }
        case 4u: {
            let x = display.split * width;
            if (abs(frag.x - x) < 1.0) { return vec4<f32>(1.0, 0.8, 0.0, 1.0); }
            if (frag.x < x) { return gray(a); }
            let q = p * vec2<i32>(textureDimensions(per_frame)) / vec2<i32>(textureDimensions(ao));
            return gray(textureLoad(per_frame, q, 0).r);
        }
        default: {
            return gray(a);
        }
    }
}
