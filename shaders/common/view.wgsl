// The per-frame view block (Rust mirror: aograph_frame::ViewUniforms). Right-handed view space,
// camera looking down -Z, linear depth = -z_view > 0; linear depth 0 marks sky.
struct View {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
    inv_proj: mat4x4<f32>,
    inv_view: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    view_to_prev_clip: mat4x4<f32>,
    // Output width, height in pixels.
    size: vec2<f32>,
    // 1/width, 1/height (one pixel in UV).
    inv_size: vec2<f32>,
    // Near plane distance (view-space units).
    near: f32,
    // Far plane distance (view-space units); 0 = infinite.
    far: f32,
    // Reversed-Z depth, 0/1 (1: near maps to clip depth 1).
    reversed_z: f32,
    // Orthographic projection, 0/1 (0: perspective).
    orthographic: f32,
    // Frame index (counts rendered frames, wrapping).
    frame_index: u32,
    // History valid, 0/1 (1: the previous frame's history may be read).
    history_valid: u32,
    // Camera cut, 0/1 (1: the camera jumped this frame).
    camera_cut: u32,
    // Unused; the four scalars above fill one 16-byte row.
    pad0: u32,
    // Scene time in seconds.
    time: f32,
    // Frame time dt in seconds.
    dt: f32,
    pad1: f32,
    pad2: f32,
}

// Linear depth of a clip-space point (the current projection's: the previous frame's is the
// same): w for a perspective camera; from z for an orthographic one (clip.z = proj[2][2]
// z_view + proj[3][2], w = 1).
fn clip_linear_depth(c: vec4<f32>, view: View) -> f32 {
    if (view.orthographic > 0.5) {
        let a = view.proj[2][2];
        return select(0.0, -(c.z - view.proj[3][2]) / a, abs(a) > 1e-30);
    }
    return c.w;
}

// Pixel centre of integer pixel `p` in UV (0..1, y down).
fn pixel_uv(p: vec2<i32>, view: View) -> vec2<f32> {
    return (vec2<f32>(p) + 0.5) * view.inv_size;
}

// View-space position of the surface at `uv` with linear depth `z` (> 0), from the projection's
// x and y rows only: for a perspective, ndc.x = (P00 x + P20 z_view) / z with z = -z_view, so
// x = z (ndc.x + P20) / P00 (and y alike with P11, P21); an orthographic camera has
// x = (ndc.x - P30) / P00. Neither the near nor the far plane enters, so reconstruction keeps
// full precision at any depth range (inverting the whole projection, or unprojecting a point on
// the far plane, loses it when far / near reaches 1e8, and fails for an infinite far plane).
fn view_position(uv: vec2<f32>, z: f32, view: View) -> vec3<f32> {
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let scale = vec2<f32>(view.proj[0][0], view.proj[1][1]);
    if (view.orthographic > 0.5) {
        let offset = vec2<f32>(view.proj[3][0], view.proj[3][1]);
        return vec3<f32>((ndc - offset) / scale, -z);
    }
    let shear = vec2<f32>(view.proj[2][0], view.proj[2][1]);
    return vec3<f32>(z * (ndc + shear) / scale, -z);
}

// UV of a view-space point (y down).
fn project_uv(p: vec3<f32>, view: View) -> vec2<f32> {
    let c = view.proj * vec4<f32>(p, 1.0);
    let ndc = c.xy / max(abs(c.w), 1e-30) * sign(c.w + 1e-30);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// Pixels covered by a view-space length `r` at linear depth `z` (along the image's y axis).
fn pixels_per_unit(z: f32, view: View) -> f32 {
    let scale = view.proj[1][1] * 0.5 * view.size.y;
    if (view.orthographic > 0.5) {
        return scale;
    }
    return scale / max(z, 1e-30);
}

// `view_position` as an affine map of pixel coordinates, for loops that rebuild many samples
// (one multiply-add per axis instead of the NDC round trip): with uv = pixel * inv_size,
// xy = (pixel * scale + offset) * (z for a perspective, 1 for an orthographic camera), z = -z.
struct PixelToView {
    scale: vec2<f32>,
    offset: vec2<f32>,
    // 1 for a perspective camera (xy grows with depth), 0 for an orthographic one.
    perspective: f32,
}

fn pixel_to_view(view: View, inv_size: vec2<f32>) -> PixelToView {
    let s = vec2<f32>(view.proj[0][0], view.proj[1][1]);
    var m: PixelToView;
    m.scale = vec2<f32>(2.0, -2.0) * inv_size / s;
    if (view.orthographic > 0.5) {
        let offset = vec2<f32>(view.proj[3][0], view.proj[3][1]);
        m.offset = (vec2<f32>(-1.0, 1.0) - offset) / s;
        m.perspective = 0.0;
    } else {
        let shear = vec2<f32>(view.proj[2][0], view.proj[2][1]);
        m.offset = (vec2<f32>(-1.0, 1.0) + shear) / s;
        m.perspective = 1.0;
    }
    return m;
}

// The view-space position of the surface at `pixel` (full-resolution pixel coordinates, not
// rounded) with linear depth `z`: `view_position(pixel * inv_size, z, view)`.
fn pixel_view_position(m: PixelToView, pixel: vec2<f32>, z: f32) -> vec3<f32> {
    let depth_scale = mix(1.0, z, m.perspective);
    return vec3<f32>((pixel * m.scale + m.offset) * depth_scale, -z);
}
