//! The page's frame on the test device (lavapipe in CI): aograph's AO from the page's own
//! depth and normals is dark at the corner of `corner` and exactly 1 on open floor, settings a
//! user gets wrong are refused by name and leave the running technique in place, and a
//! zero-sized page is refused.

use aograph_web::{AoPage, PageError, technique_catalogue};

const SIZE: (u32, u32) = (96, 54);

fn page() -> Option<(AoPage, aograph_graph::GpuContext)> {
    let gpu = aograph_graph::test_gpu()?;
    let (a, d, q) = (gpu.adapter.clone(), gpu.device.clone(), gpu.queue.clone());
    let page = AoPage::new(&a, &d, &q, "corner", SIZE, wgpu::TextureFormat::Rgba8Unorm).unwrap();
    Some((page, aograph_graph::GpuContext::from_device(a, d, q)))
}

fn frame(page: &mut AoPage, gpu: &aograph_graph::GpuContext) -> Vec<u8> {
    let target = aograph_web::offscreen_target(&gpu.device, SIZE);
    let view = target.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    page.record(&mut encoder, &view).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let ao = page.ao_texture().unwrap();
    aograph_graph::read_texture(&gpu.device, &gpu.queue, ao, 0)
        .unwrap()
        .bytes
}

#[test]
fn the_corner_is_dark_and_open_floor_is_exactly_one() {
    let Some((mut page, gpu)) = page() else {
        return;
    };
    let r = page.radius();
    let corner = page
        .pixel_of(glam::Vec3::new(0.15 * r, 0.0, 0.15 * r))
        .unwrap();
    let open = (3.0 * r).max(4.0);
    let floor = page.pixel_of(glam::Vec3::new(open, 0.0, open)).unwrap();
    let ao = frame(&mut page, &gpu);
    let at = |(x, y): (u32, u32)| ao[(y * SIZE.0 + x) as usize];
    // Nothing lies within R of the open floor: every sample is unoccluded, 255 exactly.
    assert_eq!(at(floor), 255);
    // Three planes meet at the corner: gtao's slices find walls on both sides.
    assert!(at(corner) < 160, "corner reads {}", at(corner));
}

#[test]
fn a_wrong_setting_is_refused_by_name_and_the_technique_keeps_running() {
    let Some((mut page, gpu)) = page() else {
        return;
    };
    let before = frame(&mut page, &gpu);
    let err = page
        .set_settings("technique = \"gtoa\"")
        .unwrap_err()
        .to_string();
    assert!(err.contains("gtoa") && err.contains("gtao"), "{err}");
    let err = page
        .set_settings("technique = \"gtao\"\n[gtao]\nslices = 0")
        .unwrap_err()
        .to_string();
    assert!(err.contains("slices") && err.contains("1 to 32"), "{err}");
    assert_eq!(page.technique(), "gtao");
    assert_eq!(frame(&mut page, &gpu).len(), before.len());
}

#[test]
fn the_settings_get_the_scenes_radius_and_a_format_the_device_can_store() {
    let Some((mut page, gpu)) = page() else {
        return;
    };
    let r16 = gpu.supports(
        wgpu::TextureFormat::R16Float,
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    // A table first and a second table: the keys still go to the top level.
    let applied = page
        .set_settings("  [gtao]\npreset = \"low\"\n[hbao]\nsteps = 4\n")
        .unwrap();
    let table: toml::Table = applied.parse().unwrap();
    assert_eq!(table["radius"].as_float(), Some(f64::from(page.radius())));
    assert_eq!(
        table.get("intermediate_format").and_then(|v| v.as_str()),
        (!r16).then_some("r32float")
    );
    assert_eq!(table["gtao"]["preset"].as_str(), Some("low"));
    // The user's own radius and format stay.
    let applied = page
        .set_settings("technique = \"hbao\"\nradius = 0.25\nintermediate_format = \"r32float\"")
        .unwrap();
    let table: toml::Table = applied.parse().unwrap();
    assert_eq!(table["radius"].as_float(), Some(0.25));
    assert_eq!(table["intermediate_format"].as_str(), Some("r32float"));
    assert_eq!(page.technique(), "hbao");
    let err = page.set_settings("technique = ").unwrap_err().to_string();
    assert!(err.contains("not valid TOML"), "{err}");
}

#[test]
fn a_zero_sized_page_is_refused() {
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    let made = AoPage::new(
        &gpu.adapter,
        &gpu.device,
        &gpu.queue,
        "corner",
        (0, 54),
        wgpu::TextureFormat::Rgba8Unorm,
    );
    assert!(matches!(
        made,
        Err(PageError::Size {
            width: 0,
            height: 54
        })
    ));
}

#[test]
fn the_catalogue_lists_what_the_embedding_can_feed_with_every_parameter() {
    let registry = aograph_ao_passes::TechniqueRegistry::with_builtins();
    let catalogue = technique_catalogue(&registry);
    let names: Vec<&str> = catalogue
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, aograph_embed::feedable_techniques(&registry));
    for t in catalogue.as_array().unwrap() {
        let technique = registry.get(t["name"].as_str().unwrap()).unwrap();
        let params: Vec<&str> = t["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["name"].as_str().unwrap())
            .collect();
        let expected: Vec<&str> = technique.parameters().iter().map(|p| p.name).collect();
        assert_eq!(params, expected);
    }
}

#[test]
fn a_glb_from_its_bytes_draws_and_a_truncated_one_is_refused_by_name() {
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    let Some(path) = aograph_scene::test_scene("the web page's glTF test", "CesiumMan.glb") else {
        return;
    };
    let bytes = std::fs::read(&path).unwrap();
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let (a, d, q) = (&gpu.adapter, &gpu.device, &gpu.queue);
    let mut page = AoPage::from_gltf(a, d, q, ("CesiumMan.glb", &bytes), SIZE, format).unwrap();
    let ctx = aograph_graph::GpuContext::from_device(a.clone(), d.clone(), q.clone());
    let ao = frame(&mut page, &ctx);
    assert_eq!(ao.len(), (SIZE.0 * SIZE.1) as usize);
    // The figure stands in the middle of the view: some pixel is occluded, and the top row is
    // sky, exactly 1 (it read 250-254 while the page drew a standard-Z projection into a
    // reversed-Z buffer: the sky was then a surface at the near plane).
    assert!(ao.iter().any(|&v| v < 255));
    assert!(ao[..SIZE.0 as usize].iter().all(|&v| v == 255));
    let Err(err) = AoPage::from_gltf(
        a,
        d,
        q,
        ("cut.glb", &bytes[..bytes.len() / 2]),
        SIZE,
        format,
    ) else {
        panic!("half a glb was accepted");
    };
    let err = err.to_string();
    assert!(err.contains("cut.glb"), "{err}");
}
