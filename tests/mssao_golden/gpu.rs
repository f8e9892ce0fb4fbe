//! The real `mssao` technique on an uploaded g-buffer, with every pass's output read back.

use super::*;

// ---------------------------------------------------------------------------------------------
// The technique on the GPU

/// `mssao` built through the registry on imported g-buffer channels, every pass output
/// exported so it can be read back.
pub(crate) struct Mssao {
    pub(crate) gpu: Arc<GpuContext>,
    pub(crate) exec: Executor,
    pub(crate) plan: Arc<CompiledGraph>,
    pub(crate) size: Extent,
    pub(crate) view: wgpu::Buffer,
    pub(crate) inputs: Vec<(GBufferChannel, wgpu::Texture)>,
    /// (pass, binding, written handle) of every texture write.
    pub(crate) writes: Vec<(String, String, TextureHandle)>,
    pub(crate) output: TextureHandle,
    pub(crate) frame: u32,
    pub(crate) prev: Option<Camera>,
    /// The view block of the last frame.
    pub(crate) uniforms: ViewUniforms,
}

impl Mssao {
    /// `params`: the `[ao.mssao]` table as TOML. Intermediates are R32Float (tuples
    /// Rgba32Float), so the tuples hold the shader's f32 values.
    pub(crate) fn new(w: usize, h: usize, radius: f32, params: &str) -> Option<Self> {
        let gpu = test_gpu()?;
        let registry = TechniqueRegistry::with_builtins();
        let table: toml::Table = params.parse().expect("test params are TOML");
        let technique = registry
            .get("mssao")
            .expect("mssao is registered")
            .clone()
            .configure(&table)
            .expect("params are valid");
        let channels = technique.channels();
        let mut b = GraphBuilder::new();
        let view = b.import_buffer(
            VIEW_BUFFER,
            BufferDesc {
                size: std::mem::size_of::<ViewUniforms>() as u64,
            },
        );
        // No Motion channel: a static scene, reprojected through the camera (as the renderer
        // does when nothing moves).
        let imported: Vec<GBufferChannel> = channels
            .iter()
            .filter(|c| *c != GBufferChannel::Motion)
            .collect();
        let mut gbuffer = GBufferTextures::default();
        for c in &imported {
            let desc = TextureDesc::new(c.format(), SizeClass::FULL);
            gbuffer.set(*c, b.import_texture(c.name(), desc));
        }
        let out = technique
            .build(&mut AoBuildContext {
                builder: &mut b,
                gbuffer,
                view,
                radius,
                intermediate_format: wgpu::TextureFormat::R32Float,
                technique: "mssao",
                radius_pixels: None,
                declared: Default::default(),
                tracing: Default::default(),
            })
            .expect("mssao builds");
        b.export(out.accessibility);
        let mut decl = b.build();
        let writes: Vec<(String, String, TextureHandle)> = decl
            .passes
            .iter()
            .flat_map(|p| {
                p.textures
                    .iter()
                    .filter_map(|t| Some((p.name.clone(), t.binding.clone()?, t.written?)))
            })
            .collect();
        for (_, _, h) in &writes {
            let r = &mut decl.resources[h.resource_index()];
            if r.origin == ResourceOrigin::Transient {
                r.exported = true;
            }
        }
        let shaders = aograph::shader_library();
        let plan = Arc::new(
            compile(decl, &shaders, CompileOptions::default()).expect("mssao graph compiles"),
        );
        let mut exec = Executor::with_shaders(gpu.clone(), shaders);
        let view_buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view"),
            size: std::mem::size_of::<ViewUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        exec.import_buffer(VIEW_BUFFER, view_buffer.clone());
        let inputs = imported
            .iter()
            .map(|c| {
                let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(c.name()),
                    size: wgpu::Extent3d {
                        width: w as u32,
                        height: h as u32,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: c.format(),
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                });
                exec.import_texture(c.name(), tex.clone());
                (*c, tex)
            })
            .collect();
        Some(Self {
            gpu,
            exec,
            plan,
            size: Extent::new(w as u32, h as u32),
            view: view_buffer,
            inputs,
            writes,
            output: out.accessibility,
            frame: 0,
            prev: None,
            uniforms: bytemuck::Zeroable::zeroed(),
        })
    }

    /// Uploads `g` and runs one frame seen from `camera` (the previous frame's camera is the
    /// last one given).
    pub(crate) fn frame(&mut self, g: &GBuffer, camera: Camera) {
        assert_eq!(
            (g.w as u32, g.h as u32),
            (self.size.width, self.size.height)
        );
        for (c, tex) in &self.inputs {
            let bytes: Vec<u8> = match c {
                GBufferChannel::NormalsOct => {
                    g.normals_oct.iter().flat_map(|v| v.to_le_bytes()).collect()
                }
                // The temporal filter's (tests/mssao_golden/temporal.rs).
                GBufferChannel::Normals => g
                    .normals
                    .iter()
                    .flatten()
                    .flat_map(|v| f16_bits(*v).to_le_bytes())
                    .collect(),
                GBufferChannel::LinearDepth => g
                    .linear_depth()
                    .iter()
                    .flat_map(|v| v.to_le_bytes())
                    .collect(),
                other => panic!("mssao does not read {other:?}"),
            };
            self.gpu.queue.write_texture(
                tex.as_image_copy(),
                &bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(bytes.len() as u32 / self.size.height),
                    rows_per_image: None,
                },
                tex.size(),
            );
        }
        let history_valid = self.exec.all_history_valid(&self.plan, self.size);
        self.uniforms = view_uniforms(&ViewFrame {
            camera,
            prev_camera: self.prev.unwrap_or(camera),
            output: self.size,
            frame_index: self.frame,
            history_valid,
            camera_cut: false,
            time: 0.0,
            dt: 0.0,
        });
        self.gpu
            .queue
            .write_buffer(&self.view, 0, self.uniforms.bytes());
        self.exec
            .execute(&self.plan, self.size)
            .expect("mssao frame runs");
        self.frame += 1;
        self.prev = Some(camera);
    }

    pub(crate) fn read_handle(&self, h: TextureHandle) -> Vec<V4> {
        let r = self.exec.read_texture(&self.plan, h).expect("reads back");
        let n = r.channels();
        r.to_f32()
            .unwrap()
            .chunks_exact(n)
            .map(|c| {
                let mut v = [0.0; 4];
                v[..n].copy_from_slice(c);
                v
            })
            .collect()
    }

    /// The texture `pass` wrote to its `binding`.
    pub(crate) fn written(&self, pass: &str, binding: &str) -> TextureHandle {
        self.writes
            .iter()
            .find(|(p, b, _)| p == pass && b == binding)
            .unwrap_or_else(|| panic!("no pass {pass} writes {binding}"))
            .2
    }

    /// What `pass` wrote to its `binding`, as RGBA (missing channels 0).
    pub(crate) fn read(&self, pass: &str, binding: &str) -> Vec<V4> {
        self.read_handle(self.written(pass, binding))
    }

    /// The technique's output (after the temporal filter where it is on).
    pub(crate) fn output(&self) -> Vec<f32> {
        self.read_handle(self.output).iter().map(|v| v[0]).collect()
    }

    /// MSSAO's spatial accessibility (`mssao.ao0`, before any temporal filter).
    pub(crate) fn spatial(&self) -> Vec<f32> {
        let a = self.read("mssao.ao0", "accessibility");
        a.iter().map(|v| v[0]).collect()
    }

    /// Pyramid level `l` as the GPU holds it (level 0 is the g-buffer `g`).
    pub(crate) fn level(&self, l: u32, g: &GBuffer) -> Level {
        if l == 0 {
            return g.level(&self.grid(0));
        }
        let pass = format!("mssao.downsample{l}");
        let e = self.size.mip(l);
        let depth = self.read(&pass, "dst_depth").iter().map(|v| v[0]).collect();
        let h = self.written(&pass, "dst_normals");
        let bits = self
            .exec
            .read_texture(&self.plan, h)
            .expect("reads back")
            .to_u32()
            .expect("normals are R32Uint");
        Level::rebuild(
            e.width as usize,
            e.height as usize,
            depth,
            bits,
            &self.grid(l),
        )
    }

    /// Where level `l`'s texels lie in the last frame's view.
    pub(crate) fn grid(&self, l: u32) -> Grid {
        Grid::new(&self.uniforms, l)
    }

    pub(crate) fn consts(&self, radius: f32, p: &Params) -> Consts {
        Consts {
            d_max: radius,
            r_max: p.r_max,
            t_n: p.t_n,
            t_z: p.t_z,
            bilateral_blur: p.bilateral_blur,
            upsampling: p.upsampling,
            proj11: self.uniforms.proj[1][1],
            height: self.uniforms.size[1],
        }
    }
}

/// The parameters a test sets (the rest at their defaults, which these mirror).
pub(crate) struct Params {
    pub(crate) r_max: f32,
    pub(crate) t_n: f32,
    pub(crate) t_z: f32,
    pub(crate) bilateral_blur: bool,
    /// 0 nearest, 1 bilinear, 2 bilateral (`upsampling`).
    pub(crate) upsampling: u32,
}

pub(crate) const DEFAULTS: Params = Params {
    r_max: 5.0,
    t_n: 8.0,
    t_z: 16.0,
    bilateral_blur: true,
    upsampling: 2,
};

/// Runs one frame of the box scene from [`front_camera`] with `levels` and extra `params`.
pub(crate) fn box_scene_run(levels: u32, radius: f32, params: &str) -> Option<(Mssao, GBuffer)> {
    let camera = front_camera();
    let (g, _) = cast(&camera, W, H, &boxes());
    let mut m = Mssao::new(W, H, radius, &format!("levels = {levels}\n{params}"))?;
    m.frame(&g, camera);
    Some((m, g))
}
