// Texel centres of a ceil-sized depth pyramid (crates/ao-passes/src/blocks/depth_pyramid.rs),
// in full-resolution pixel coordinates. Level l of a factor-K pyramid over a W x H image is
// ceil(W / K^l) x ceil(H / K^l); texel x of level l averages texels Kx .. min(Kx + K, size) - 1
// of level l - 1. Every texel but the last of a row or column covers K^l full pixels, centre
// (x + 0.5) K^l; the last one covers fewer, and its centre is the mean of its children's
// centres (exact for the average pyramid away from sky).

struct PyramidEdges {
    // Per level: index of the last texel (x, y) and its centre.
    last: array<vec2<i32>, 8>,
    centre: array<vec2<f32>, 8>,
}

fn pyramid_edges(full: vec2<i32>, factor: i32, levels: u32) -> PyramidEdges {
    var e: PyramidEdges;
    var size = full;
    var c = vec2<f32>(full) - 0.5;
    var scale = 1.0;
    e.last[0] = full - 1;
    e.centre[0] = c;
    for (var l = 1u; l < min(levels, 8u); l = l + 1u) {
        let prev = size;
        size = (prev + factor - 1) / factor;
        // The last texel's children: first .. prev - 1; all but the final one are interior,
        // centre (j + 0.5) scale; m = their count, sum_j (j + 0.5) = m (first + 0.5) + m (m - 1) / 2.
        let first = (size - 1) * factor;
        let n = vec2<f32>(prev - first);
        let m = n - 1.0;
        c = ((m * (vec2<f32>(first) + 0.5) + m * (m - 1.0) * 0.5) * scale + c) / n;
        scale = scale * f32(factor);
        e.last[l] = size - 1;
        e.centre[l] = c;
    }
    return e;
}

// Centre of texel t of level `level` (scale = factor^level).
fn pyramid_texel_centre(e: ptr<function, PyramidEdges>, t: vec2<i32>, level: u32, scale: f32) -> vec2<f32> {
    let interior = (vec2<f32>(t) + 0.5) * scale;
    return select(interior, (*e).centre[level], t == (*e).last[level]);
}
