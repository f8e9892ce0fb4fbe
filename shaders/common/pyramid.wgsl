// Texel centres of a ceil-sized depth pyramid (crates/ao-passes/src/blocks/depth_pyramid.rs),
// in full-resolution pixel coordinates. Level l of a factor-K pyramid over a W x H image is
// ceil(W / K^l) x ceil(H / K^l); texel x of level l averages texels Kx .. min(Kx + K, size) - 1
// of level l - 1. Every texel but the last of a row or column covers K^l full pixels, centre
// (x + 0.5) K^l; the last one covers fewer, and its centre is the mean of its children's
// centres (exact for the average pyramid away from sky).

// One level's last texel (x, y) and that texel's centre. Built level by level, in values
// (no array a loop indexes: on SIMD CPU drivers such an array lives in per-lane memory).
struct PyramidEdge {
    last: vec2<i32>,
    centre: vec2<f32>,
}

// Level 0: the full-resolution image itself.
fn pyramid_edge0(full: vec2<i32>) -> PyramidEdge {
    return PyramidEdge(full - 1, vec2<f32>(full) - 0.5);
}

// Level l, `size` texels (the bound texture's dimensions: no integer division per pixel), from
// level l - 1, whose texels are `prev_scale` full pixels wide.
fn pyramid_next_edge(prev: PyramidEdge, size: vec2<i32>, factor: i32, prev_scale: f32) -> PyramidEdge {
    let prev_size = prev.last + 1;
    // The last texel's children: first .. prev_size - 1; all but the final one are interior,
    // centre (j + 0.5) scale; m = their count, sum_j (j + 0.5) = m (first + 0.5) + m (m - 1) / 2.
    let first = (size - 1) * factor;
    let n = vec2<f32>(prev_size - first);
    let m = n - 1.0;
    let c = ((m * (vec2<f32>(first) + 0.5) + m * (m - 1.0) * 0.5) * prev_scale + prev.centre) / n;
    return PyramidEdge(size - 1, c);
}

// Centre of texel t of a level whose texels are `scale` full pixels wide.
fn pyramid_texel_centre(e: PyramidEdge, t: vec2<i32>, scale: f32) -> vec2<f32> {
    let interior = (vec2<f32>(t) + 0.5) * scale;
    return select(interior, e.centre, t == e.last);
}
