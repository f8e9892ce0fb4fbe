// Unit normals in 32 bits: the octahedral map (Cigolle et al., "A Survey of Efficient
// Representations for Independent Unit Vectors", JCGT 2014), two snorm16 components packed in
// one u32 (the g-buffer's `normals_oct` channel, R32Uint, and MSSAO's pyramid). Half the bytes
// of an Rgba16Float normal and finer: each component is quantised to 1/32767 of the square,
// an angular error below 1e-4 rad, where f16 rounds each coordinate by up to 2^-11.
// Invariant: decode(encode(n)) is a unit vector within that error of n; 0u (a cleared target)
// decodes to +z, so validity comes from the depth (0 = sky), not from the normal.

fn normal_oct_wrap(v: vec2<f32>) -> vec2<f32> {
    return (vec2<f32>(1.0) - abs(v.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

fn normal_oct_encode(n: vec3<f32>) -> u32 {
    let m = n / max(abs(n.x) + abs(n.y) + abs(n.z), 1e-30);
    let e = select(normal_oct_wrap(m.xy), m.xy, m.z >= 0.0);
    return pack2x16snorm(e);
}

fn normal_oct_decode(bits: u32) -> vec3<f32> {
    let e = unpack2x16snorm(bits);
    let z = 1.0 - abs(e.x) - abs(e.y);
    let t = max(-z, 0.0);
    let xy = e + select(vec2<f32>(t), vec2<f32>(-t), e >= vec2<f32>(0.0));
    return normalize(vec3<f32>(xy, z));
}
