// Non-finite values (NaN, +-infinity) detected by their bit pattern. WGSL lets an
// implementation assume float arithmetic and comparisons never see NaN or infinity, so a guard
// written `select(fallback, a, a == a)` may be folded to `a` by an optimising compiler. Integer
// operations on the bits cannot be: a float is finite exactly when its exponent bits
// (0x7f800000) are not all ones.

fn is_finite_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_finite_vec3(v: vec3<f32>) -> bool {
    return all((bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u)) != vec3<u32>(0x7f800000u));
}

// `x` when finite, else `fallback`.
fn finite_or(x: f32, fallback: f32) -> f32 {
    return select(fallback, x, is_finite_f32(x));
}

// Accessibility from a raw estimate: clamped to [0, 1], exactly 1 when not finite (a NaN or
// infinite input occludes nothing rather than poisoning the frame).
fn accessibility_or_one(a: f32) -> f32 {
    return select(1.0, clamp(a, 0.0, 1.0), is_finite_f32(a));
}
