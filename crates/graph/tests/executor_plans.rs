//! Many plans in one executor: pipelines cached across plans, textures pooled across plans,
//! history kept per plan and invalid when its plan comes back after another ran, read-back
//! naming the plan, parameter changes that rebuild nothing, and bounded plan state. Results
//! are checked against the same CPU arithmetic as gpu_execute.rs.

use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use aograph_graph::*;
use wgpu::TextureFormat::R32Float;

#[path = "common/test_passes.rs"]
mod test_passes;
use test_passes::{CountingPass, KeyedPass, params, pattern, shaders};

const SIZE: Extent = Extent::new(24, 16);

fn expected(f: impl Fn(f32) -> f32) -> Vec<f32> {
    (0..SIZE.height)
        .flat_map(|y| (0..SIZE.width).map(move |x| (x, y)))
        .map(|(x, y)| f(pattern(x, y)))
        .collect()
}

/// A graph with the full-screen pattern drawn: the builder, the R32Float full-size
/// descriptor, the pattern texture.
fn pattern_graph() -> (GraphBuilder, TextureDesc, TextureHandle) {
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(R32Float, SizeClass::FULL);
    let img = b.create_texture("pattern", desc);
    let img = b
        .fullscreen_pass("pattern", "pattern.wgsl", "vs", "fs")
        .color_attachment(img);
    (b, desc, img)
}

/// pattern -> scale(scale, offset) -> exported.
fn scale_decl(scale: f32, offset: f32) -> (GraphDecl, TextureHandle) {
    let (mut b, desc, img) = pattern_graph();
    let out = b.create_texture("scaled", desc);
    let mut p = b.compute_pass("scale", "scale.wgsl", "main");
    p.sample("src", img);
    p.uniform("params", &params(scale, offset));
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    (b.build(), out)
}

/// pattern -> square -> exported (another structure, another pipeline).
fn square_decl() -> (GraphDecl, TextureHandle) {
    let (mut b, desc, img) = pattern_graph();
    let out = b.create_texture("squared", desc);
    let mut p = b.compute_pass("square", "square.wgsl", "main");
    p.sample("src", img);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    (b.build(), out)
}

fn accumulate_decl() -> (GraphDecl, TextureHandle) {
    let mut b = GraphBuilder::new();
    let hist = b.history_texture("count", TextureDesc::new(R32Float, SizeClass::FULL));
    let mut p = b.compute_pass("accumulate", "accumulate.wgsl", "main");
    p.sample("previous", hist.previous);
    let cur = p.write_storage("current", hist.current);
    p.dispatch_over(cur);
    (b.build(), cur)
}

/// pattern -> constants(GAIN, REPEAT) -> exported; `constants` as (name, value) pairs.
fn constants_decl(constants: &[(&str, f64)]) -> (GraphDecl, TextureHandle) {
    let (mut b, desc, img) = pattern_graph();
    let out = b.create_texture("gained", desc);
    let mut p = b.compute_pass("gain", "constants.wgsl", "main");
    p.sample("src", img);
    for (name, value) in constants {
        p.constant(name, *value);
    }
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    (b.build(), out)
}

fn plan(decl: GraphDecl) -> Arc<CompiledGraph> {
    Arc::new(compile(decl, &shaders(), CompileOptions::default()).expect("compiles"))
}

fn read(exec: &Executor, plan: &CompiledGraph, h: TextureHandle) -> Vec<f32> {
    exec.read_texture(plan, h).unwrap().to_f32().unwrap()
}

#[test]
fn switching_a_b_a_b_creates_no_pipeline_or_texture_after_the_first_two_frames() {
    let Some(gpu) = test_gpu() else { return };
    let (da, out_a) = scale_decl(2.0, 1.0);
    let (db, out_b) = square_decl();
    let (a, b) = (plan(da), plan(db));
    let mut exec = Executor::new(gpu.clone());
    exec.execute(&a, SIZE).unwrap();
    exec.execute(&b, SIZE).unwrap();
    let pipelines = exec.pipeline_created_count();
    let textures = exec.pool_created_count();
    assert_eq!(
        pipelines, 3,
        "pattern (shared by both plans), scale and square"
    );
    for round in 0..4 {
        exec.execute(&a, SIZE).unwrap();
        assert_eq!(
            read(&exec, &a, out_a),
            expected(|v| v * 2.0 + 1.0),
            "round {round}"
        );
        exec.execute(&b, SIZE).unwrap();
        assert_eq!(read(&exec, &b, out_b), expected(|v| v * v), "round {round}");
    }
    assert_eq!(
        exec.pipeline_created_count(),
        pipelines,
        "switching created pipelines"
    );
    assert_eq!(
        exec.pool_created_count(),
        textures,
        "switching created textures"
    );
    assert_eq!(exec.plan_count(), 2);
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn textures_are_pooled_across_plans() {
    let Some(gpu) = test_gpu() else { return };
    let (da, _) = scale_decl(2.0, 1.0);
    let (db, _) = square_decl();
    let (a, b) = (plan(da), plan(db));
    // Alone, each plan needs two textures (pattern, output).
    let mut exec = Executor::new(gpu.clone());
    exec.execute(&a, SIZE).unwrap();
    assert_eq!(exec.pool_created_count(), 2);
    // B's pattern texture is A's, which went back to the pool at the end of A's frame; only
    // B's output is new, because A keeps its exported output readable.
    exec.execute(&b, SIZE).unwrap();
    assert_eq!(exec.pool_created_count(), 3);
}

#[test]
fn plans_taking_turns_at_different_sizes_keep_their_pooled_textures() {
    // Free textures wait `TexturePool::IDLE_FRAMES` frames for a taker, so a plan's
    // intermediates survive a frame of another plan whose textures are all of other sizes.
    let Some(gpu) = test_gpu() else { return };
    let (da, _) = scale_decl(2.0, 1.0);
    let (db, _) = square_decl();
    let (a, b) = (plan(da), plan(db));
    let mut exec = Executor::new(gpu);
    exec.execute(&a, SIZE).unwrap();
    exec.execute(&b, Extent::new(8, 8)).unwrap();
    let textures = exec.pool_created_count();
    for _ in 0..5 {
        exec.execute(&a, SIZE).unwrap();
        exec.execute(&b, Extent::new(8, 8)).unwrap();
    }
    assert_eq!(exec.pool_created_count(), textures);
}

#[test]
fn read_texture_reads_the_plan_it_names_whatever_ran_since() {
    let Some(gpu) = test_gpu() else { return };
    let (da, out_a) = scale_decl(2.0, 1.0);
    let (db, out_b) = square_decl();
    let (a, b) = (plan(da), plan(db));
    let mut exec = Executor::new(gpu);
    let err = exec.read_texture(&a, out_a).unwrap_err();
    assert!(err.to_string().contains("has not executed"), "{err}");
    exec.execute(&a, SIZE).unwrap();
    exec.execute(&b, SIZE).unwrap();
    exec.execute(&b, SIZE).unwrap();
    assert_eq!(read(&exec, &a, out_a), expected(|v| v * 2.0 + 1.0));
    assert_eq!(read(&exec, &b, out_b), expected(|v| v * v));
}

#[test]
fn history_is_invalid_when_its_plan_comes_back_after_another_ran() {
    let Some(gpu) = test_gpu() else { return };
    let (dh, count) = accumulate_decl();
    let (da, _) = scale_decl(2.0, 1.0);
    let (h, a) = (plan(dh), plan(da));
    let mut exec = Executor::new(gpu);
    for n in 1..=3 {
        assert_eq!(exec.history_valid(&h, "count", SIZE), n > 1);
        exec.execute(&h, SIZE).unwrap();
        assert!(read(&exec, &h, count).iter().all(|&v| v == n as f32));
    }
    exec.execute(&a, SIZE).unwrap();
    assert!(
        !exec.history_valid(&h, "count", SIZE),
        "another plan ran: the history is a frame stale"
    );
    exec.execute(&h, SIZE).unwrap();
    assert!(
        read(&exec, &h, count).iter().all(|&v| v == 1.0),
        "stale history must read as zero"
    );
    assert!(exec.history_valid(&h, "count", SIZE));
    exec.execute(&h, SIZE).unwrap();
    assert!(read(&exec, &h, count).iter().all(|&v| v == 2.0));
}

#[test]
fn history_of_a_plan_that_stopped_running_is_evicted() {
    let Some(gpu) = test_gpu() else { return };
    let (dh, _) = accumulate_decl();
    let (da, _) = scale_decl(2.0, 1.0);
    let (h, a) = (plan(dh), plan(da));
    // What A alone holds after many frames.
    let mut alone = Executor::new(gpu.clone());
    for _ in 0..20 {
        alone.execute(&a, SIZE).unwrap();
    }
    let a_only = alone.texture_count();
    let mut exec = Executor::new(gpu);
    exec.execute(&h, SIZE).unwrap();
    exec.execute(&a, SIZE).unwrap();
    assert!(
        exec.texture_count() >= a_only + 2,
        "the history's two textures are held"
    );
    for _ in 0..20 {
        exec.execute(&a, SIZE).unwrap();
    }
    assert_eq!(
        exec.texture_count(),
        a_only,
        "an unused history's textures return to the pool, which drops them"
    );
}

#[test]
fn a_new_parameter_value_rebuilds_nothing_and_takes_effect() {
    let Some(gpu) = test_gpu() else { return };
    let lib = shaders();
    let mut compiler = GraphCompiler::new();
    let (d1, out) = scale_decl(2.0, 1.0);
    let p1 = compiler
        .compile(d1, &lib, CompileOptions::default())
        .unwrap();
    let mut exec = Executor::new(gpu);
    exec.execute(&p1, SIZE).unwrap();
    let pipelines = exec.pipeline_created_count();
    let textures = exec.pool_created_count();
    let (d2, _) = scale_decl(-1.0, 0.5);
    let p2 = compiler
        .compile(d2, &lib, CompileOptions::default())
        .unwrap();
    assert_eq!(
        compiler.compile_count(),
        1,
        "a parameter value is not structure"
    );
    exec.execute(&p2, SIZE).unwrap();
    assert_eq!(read(&exec, &p2, out), expected(|v| -v + 0.5));
    // Back to the first declaration: its own values are written again.
    exec.execute(&p1, SIZE).unwrap();
    assert_eq!(read(&exec, &p1, out), expected(|v| v * 2.0 + 1.0));
    assert_eq!(exec.pipeline_created_count(), pipelines);
    assert_eq!(exec.pool_created_count(), textures);
    assert_eq!(exec.plan_count(), 1, "one structure, one plan state");
}

#[test]
fn a_rebuilt_custom_pass_records_not_the_cached_declarations_pass() {
    let Some(gpu) = test_gpu() else { return };
    let lib = shaders();
    let mut compiler = GraphCompiler::new();
    let build = |counter: &Arc<AtomicU32>| {
        let mut b = GraphBuilder::new();
        b.custom_pass("count", CountingPass(counter.clone()))
            .side_effect();
        b.build()
    };
    let (first, second) = (Arc::new(AtomicU32::new(0)), Arc::new(AtomicU32::new(0)));
    let p1 = compiler
        .compile(build(&first), &lib, CompileOptions::default())
        .unwrap();
    let p2 = compiler
        .compile(build(&second), &lib, CompileOptions::default())
        .unwrap();
    let mut exec = Executor::new(gpu);
    exec.execute(&p1, SIZE).unwrap();
    exec.execute(&p2, SIZE).unwrap();
    exec.execute(&p2, SIZE).unwrap();
    assert_eq!(first.load(Ordering::Relaxed), 1);
    assert_eq!(second.load(Ordering::Relaxed), 2);
}

#[test]
fn plan_state_is_bounded() {
    let Some(gpu) = test_gpu() else { return };
    let lib = shaders();
    let mut exec = Executor::new(gpu);
    for key in 0..40u64 {
        let mut b = GraphBuilder::new();
        b.custom_pass("p", KeyedPass(key)).side_effect();
        let p = Arc::new(compile(b.build(), &lib, CompileOptions::default()).unwrap());
        exec.execute(&p, SIZE).unwrap();
        assert!(exec.plan_count() <= 16, "{} plans held", exec.plan_count());
    }
    assert_eq!(exec.plan_count(), 16);
}

#[test]
fn pipeline_constants_are_compiled_in_and_each_value_set_is_one_cached_pipeline() {
    let Some(gpu) = test_gpu() else { return };
    let (d6, out6) = constants_decl(&[("GAIN", 2.0), ("REPEAT", 3.0)]);
    let (d1, out1) = constants_decl(&[("REPEAT", 2.0), ("GAIN", 0.5)]);
    assert_ne!(
        d6.structure_hash(),
        d1.structure_hash(),
        "constants are structure: they change the pipeline"
    );
    let (a, b) = (plan(d6), plan(d1));
    let mut exec = Executor::new(gpu.clone());
    exec.execute(&a, SIZE).unwrap();
    exec.execute(&b, SIZE).unwrap();
    assert_eq!(read(&exec, &a, out6), expected(|v| v * 6.0));
    assert_eq!(read(&exec, &b, out1), expected(|v| v));
    assert_eq!(
        exec.pipeline_created_count(),
        3,
        "pattern, and gain once per value set"
    );
    // The same values in another plan (set in another order, one set twice) reuse it.
    let (again, out) = constants_decl(&[("REPEAT", 3.0), ("GAIN", 9.0), ("GAIN", 2.0)]);
    assert_eq!(again.structure_hash(), a.decl.structure_hash());
    let again = plan(again);
    exec.execute(&again, SIZE).unwrap();
    assert_eq!(read(&exec, &again, out), expected(|v| v * 6.0));
    assert_eq!(exec.pipeline_created_count(), 3);
    // GAIN has a default (1.0): leaving it out is allowed.
    let (default_gain, out) = constants_decl(&[("REPEAT", 4.0)]);
    let default_gain = plan(default_gain);
    exec.execute(&default_gain, SIZE).unwrap();
    assert_eq!(read(&exec, &default_gain, out), expected(|v| v * 4.0));
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn pipeline_constants_the_shader_does_not_declare_or_needs_are_compile_errors() {
    let compile_err = |constants: &[(&str, f64)]| {
        compile(
            constants_decl(constants).0,
            &shaders(),
            CompileOptions::default(),
        )
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
    };
    let e = compile_err(&[("REPEAT", 1.0), ("GIAN", 2.0)]);
    assert!(
        e.contains("`GIAN`") && e.contains("declares: GAIN, REPEAT") && e.contains("gain"),
        "{e}"
    );
    let e = compile_err(&[("GAIN", 2.0)]);
    assert!(
        e.contains("`override REPEAT` without a default") && e.contains("constant"),
        "{e}"
    );
    let e = compile_err(&[("REPEAT", 1.0), ("GAIN", f64::NAN)]);
    assert!(e.contains("`GAIN` = NaN") && e.contains("finite"), "{e}");
    assert_eq!(compile_err(&[("REPEAT", 1.0)]), "");
}

/// Records a command wgpu refuses: a buffer clear at an offset that is not a multiple of 4.
struct InvalidCommandPass;

impl CustomPass for InvalidCommandPass {
    fn kind_name(&self) -> &str {
        "invalid command"
    }
    fn record(&self, ctx: &mut PassContext<'_>) -> GraphResult<()> {
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("unaligned clear"),
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.encoder.clear_buffer(&buffer, 3, None);
        Ok(())
    }
}

#[test]
fn a_command_the_device_refuses_is_a_device_error_naming_the_frame() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    b.custom_pass("bad", InvalidCommandPass).side_effect();
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    match exec.execute(&plan, SIZE) {
        Err(GraphError::Device { during, message }) => {
            assert_eq!(during, "executing a frame");
            assert!(!message.is_empty());
        }
        other => panic!("expected a device error, got {other:?}"),
    }
    assert!(
        gpu.take_errors().is_empty(),
        "the frame's errors were taken"
    );
}
