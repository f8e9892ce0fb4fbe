// A ray's answer from either GPU tracer backend (common/scene_trace.wgsl and its twin
// common/scene_trace_hardware.wgsl): `hit` false on a miss (the rest unused); else its distance
// along the direction, the scene instance (index into Scene::instances), the primitive (index
// among the mesh's valid triangles) and 1 in `moving` when that instance moves.
struct SceneHit {
    hit: bool,
    t: f32,
    instance: u32,
    primitive: u32,
    moving: u32,
}
