// Texel centres of a centred 3x3 depth pyramid (crates/ao-passes/src/blocks/depth_pyramid.rs),
// in full-resolution pixel coordinates. Level l's texel x averages texels
// Kx - o_l .. Kx - o_l + K - 1 of level l - 1 (those inside it), o_l = (K m_l - m_{l-1}) / 2 the
// grid's overhang (`aograph_graph::centred_step`). So texel x of level l covers full pixels
// [x K^l - c_l, (x + 1) K^l - c_l), c_l = c_{l-1} + o_l K^(l-1) the level's offset; every texel
// but the first and last of a row or column lies inside the image, centre (x + 0.5) K^l - c_l;
// the first and last cover fewer pixels, and their centre is the mean of their children's
// centres (exact for the average pyramid away from sky). The two edges mirror each other.

// One level's offset c_l, last texel, and the centres of its first and last texels. Built
// level by level, in values (no array a loop indexes: on SIMD CPU drivers such an array lives
// in per-lane memory).
struct PyramidEdge {
    last: vec2<i32>,
    offset: vec2<f32>,
    first_centre: vec2<f32>,
    centre: vec2<f32>,
}

// Level 0: the full-resolution image itself.
fn pyramid_edge0(full: vec2<i32>) -> PyramidEdge {
    return PyramidEdge(full - 1, vec2<f32>(0.0), vec2<f32>(0.5), vec2<f32>(full) - 0.5);
}

// Centre of texel t (per axis) of level `e`, whose texels are `scale` full pixels wide.
fn pyramid_texel_centre(e: PyramidEdge, t: vec2<i32>, scale: f32) -> vec2<f32> {
    let interior = (vec2<f32>(t) + 0.5) * scale - e.offset;
    return select(select(interior, e.first_centre, t == vec2<i32>(0)), e.centre, t == e.last);
}

// The texel of level `e` that covers full-resolution position q (clamped into the level).
fn pyramid_texel(e: PyramidEdge, q: vec2<f32>, inv_scale: f32) -> vec2<i32> {
    return clamp(vec2<i32>(floor((q + e.offset) * inv_scale)), vec2<i32>(0), e.last);
}

// Mean centre of the in-level children first .. first + factor - 1 of level `prev`.
fn pyramid_children_centre(prev: PyramidEdge, first: vec2<i32>, factor: i32, prev_scale: f32) -> vec2<f32> {
    var sum = vec2<f32>(0.0);
    var n = vec2<f32>(0.0);
    for (var i = 0; i < factor; i = i + 1) {
        let j = first + vec2<i32>(i);
        let inside = (j >= vec2<i32>(0)) & (j <= prev.last);
        let c = pyramid_texel_centre(prev, clamp(j, vec2<i32>(0), prev.last), prev_scale);
        sum = sum + select(vec2<f32>(0.0), c, inside);
        n = n + select(vec2<f32>(0.0), vec2<f32>(1.0), inside);
    }
    return sum / max(n, vec2<f32>(1.0));
}

// Level l, `size` texels (the bound texture's dimensions: no integer division per pixel), from
// level l - 1, whose texels are `prev_scale` full pixels wide.
fn pyramid_next_edge(prev: PyramidEdge, size: vec2<i32>, factor: i32, prev_scale: f32) -> PyramidEdge {
    let overhang = (size * factor - (prev.last + 1)) / 2;
    let offset = prev.offset + vec2<f32>(overhang) * prev_scale;
    let first = pyramid_children_centre(prev, -overhang, factor, prev_scale);
    let last = pyramid_children_centre(prev, (size - 1) * factor - overhang, factor, prev_scale);
    return PyramidEdge(size - 1, offset, first, last);
}
