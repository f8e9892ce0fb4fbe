//! An application outside aograph's workspace: it depends on aograph-embed as published (the
//! packaged .crate files, unpacked), makes its own device and a linear-depth buffer of a floor
//! meeting a wall, and runs every screen-space technique on it. It fails, naming the problem,
//! when a technique cannot run (a shader a crate did not embed, say) or writes AO outside
//! [0, 1] or no darker crease than open floor.

use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use glam::{Mat4, Vec3};

const W: u32 = 160;
const H: u32 = 90;
const FOV_Y: f32 = 1.0;
/// The wall's distance and the floor's height below the camera, in metres.
const WALL: f32 = 5.0;
const FLOOR: f32 = 1.0;

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("packaged-app: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("packaged app"),
        // R16Float storage for aograph's intermediates, where the adapter has it.
        required_features: adapter.features()
            & wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES,
        ..Default::default()
    }))?;
    println!("device: {}", adapter.get_info().name);

    // Linear view depth, row 0 at the top: the floor (y = -FLOOR) up to the wall (z = -WALL).
    let tan = (FOV_Y * 0.5).tan();
    let aspect = W as f32 / H as f32;
    let mut depth = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        let v = 1.0 - 2.0 * (y as f32 + 0.5) / H as f32;
        for _ in 0..W {
            let floor = if v < 0.0 { FLOOR / (-v * tan) } else { f32::INFINITY };
            depth.push(floor.min(WALL));
        }
    }
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("linear depth"),
        size: wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bytes: Vec<u8> = depth.iter().flat_map(|d| d.to_le_bytes()).collect();
    queue.write_texture(
        texture.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(W * 4),
            rows_per_image: None,
        },
        texture.size(),
    );
    let projection = Mat4::perspective_infinite_rh(FOV_Y, aspect, 0.1);
    let view = Mat4::look_to_rh(Vec3::ZERO, -Vec3::Z, Vec3::Y);
    // The row where the floor meets the wall, and one far below it (open floor).
    let crease = (0..H as usize)
        .find(|&y| depth[y * W as usize] < WALL)
        .ok_or("no floor in view")?;
    let open = H as usize - 2;

    let mut ao = AmbientOcclusion::from_toml(
        &adapter,
        &device,
        &queue,
        "technique = \"gtao\"\nradius = 0.5",
    )?;
    for (technique, extra) in [
        ("ssao", ""),
        ("hbao", ""),
        ("pyramid-hbao", "\n[pyramid-hbao]\nlevels = 4"),
        ("mssao", "\n[mssao]\nlevels = 4"),
        ("gtao", ""),
        ("vbao", ""),
        ("tssao", ""),
    ] {
        ao.set_config_toml(&format!("technique = \"{technique}\"\nradius = 0.5{extra}"))?;
        let mut encoder = device.create_command_encoder(&Default::default());
        let out = ao.encode(
            &mut encoder,
            &AoInputs::new(DepthInput::Linear(&texture), projection, view),
        )?;
        queue.submit([encoder.finish()]);
        let values = read_r(&device, &queue, &out.texture)?;
        let row_mean = |y: usize| {
            values[y * W as usize..(y + 1) * W as usize].iter().sum::<f32>() / W as f32
        };
        if let Some(bad) = values.iter().find(|a| !(0.0..=1.0).contains(*a)) {
            return Err(format!("{technique}: AO {bad} outside [0, 1]").into());
        }
        let (at_crease, on_floor) = (row_mean(crease), row_mean(open));
        println!("{technique}: AO {at_crease:.3} at the crease, {on_floor:.3} on open floor");
        if at_crease >= on_floor {
            return Err(format!(
                "{technique}: the crease ({at_crease}) is not darker than open floor ({on_floor})"
            )
            .into());
        }
    }
    println!("every technique ran from the packaged crates");
    Ok(())
}

/// The first channel of `texture` (R8Unorm, R16Float or R32Float), row by row.
fn read_r(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<f32>, Box<dyn std::error::Error>> {
    let texel = texture
        .format()
        .block_copy_size(None)
        .ok_or("an uncopyable output format")?;
    let row = (W * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: (row * H) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let data = buffer.slice(..).get_mapped_range()?;
    let mut out = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        for x in 0..W {
            let at = (y * row + x * texel) as usize;
            let t = &data[at..at + texel as usize];
            out.push(match texel {
                1 => t[0] as f32 / 255.0,
                2 => f16_to_f32(u16::from_le_bytes([t[0], t[1]])),
                _ => f32::from_le_bytes([t[0], t[1], t[2], t[3]]),
            });
        }
    }
    Ok(out)
}

/// An IEEE half to f32 (normal, subnormal and zero; AO has no infinities).
fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    sign * if exp == 0 {
        frac * 2f32.powi(-24)
    } else {
        (1.0 + frac / 1024.0) * 2f32.powi(exp - 15)
    }
}
