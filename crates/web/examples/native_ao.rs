//! The web page's frames on a native device made as the page makes its own (no features, no
//! limits asked for: WebGPU's defaults), for each technique named: the AO's mean and its value
//! at two probes of the `corner` scene, a crease where the floor meets a wall and open floor
//! far from both walls. scripts/web-test.sh compares the browser's numbers with these.
//!
//! cargo run -p aograph-web --example native_ao -- OUT_DIR [technique ...]
//!
//! Writes OUT_DIR/native.json and OUT_DIR/<technique>.r8 (the AO, one byte per pixel, rows top
//! to bottom).

use std::path::PathBuf;

use aograph_web::{AoPage, ao_mean};

/// What the page's test mode renders: `corner` at 240x135 (16:9, odd height), each technique
/// for this many frames, in the order given, on one page (as the browser's test runs them).
const SCENE: &str = "corner";
const SIZE: (u32, u32) = (240, 135);
const FRAMES: u32 = 4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .ok_or("usage: native_ao OUT_DIR [technique ...]")?,
    );
    let mut techniques: Vec<String> = args.collect();
    if techniques.is_empty() {
        techniques = ["gtao", "hbao", "mssao"].map(String::from).to_vec();
    }
    std::fs::create_dir_all(&out)?;
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default()))?;
    let errors = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
    let sink = errors.clone();
    device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
        if let Ok(mut v) = sink.lock() {
            v.push(e.to_string());
        }
    }));
    let target_format = aograph_web::OFFSCREEN_FORMAT;
    let target = aograph_web::offscreen_target(&device, SIZE);
    let target_view = target.create_view(&Default::default());
    let mut page = AoPage::new(&adapter, &device, &queue, SCENE, SIZE, target_format)?;
    // The crease: floor 0.15 R from both walls, by the corner where the three planes meet; open
    // floor: at least
    // 3 R (and 4 units) from both walls, where nothing occludes within R.
    let r = page.radius();
    let crease = page
        .pixel_of(glam::Vec3::new(0.15 * r, 0.0, 0.15 * r))
        .ok_or("the crease probe is out of view")?;
    let open = (3.0 * r).max(4.0);
    let floor = page
        .pixel_of(glam::Vec3::new(open, 0.0, open))
        .ok_or("the open-floor probe is out of view")?;
    println!("R = {r}; crease probe at {crease:?}, open floor at {floor:?}");
    let mut results = serde_json::Map::new();
    for technique in &techniques {
        page.set_settings(&format!("technique = \"{technique}\""))?;
        for _ in 0..FRAMES {
            let mut encoder = device.create_command_encoder(&Default::default());
            page.record(&mut encoder, &target_view)?;
            queue.submit([encoder.finish()]);
        }
        let texture = page.ao_texture().ok_or("no AO was written")?;
        let bytes = aograph_graph::read_texture(&device, &queue, texture, 0)?.bytes;
        std::fs::write(out.join(format!("{technique}.r8")), &bytes)?;
        let at = |(x, y): (u32, u32)| f64::from(bytes[(y * SIZE.0 + x) as usize]) / 255.0;
        let entry = serde_json::json!({
            "mean": ao_mean(&bytes),
            "crease": at(crease),
            "floor": at(floor),
        });
        println!("{technique}: {entry}");
        results.insert(technique.clone(), entry);
    }
    let errors = errors.lock().map(|e| e.clone()).unwrap_or_default();
    let json = serde_json::json!({
        "device": adapter.get_info().name,
        "scene": SCENE,
        "width": SIZE.0,
        "height": SIZE.1,
        "frames": FRAMES,
        "probes": { "crease": [crease.0, crease.1], "floor": [floor.0, floor.1] },
        "techniques": results,
        "errors": errors,
    });
    std::fs::write(
        out.join("native.json"),
        serde_json::to_string_pretty(&json)?,
    )?;
    if !errors.is_empty() {
        return Err(format!("the device reported errors: {errors:?}").into());
    }
    Ok(())
}
