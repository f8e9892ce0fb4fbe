//! aograph's AO in a bevy app with a window: a glTF scene loaded by bevy, seen from the camera
//! aograph's tools choose for the file, with the technique cycled by the space bar and a line
//! of text naming it and its GPU time.
//!
//! ```text
//! cargo run --release --features window-example --example bevy_ao -- [SCENE.gltf]
//! ```
//! (default: the repository's tests/scenes/teapot.gltf). Space: next technique (the last is
//! bevy's own SSAO, for comparison). With `BEVY_AO_SCREENSHOT=file.png` set it saves the
//! window at frame 90 and exits (docs/guide/bevy.md's picture).

use std::path::PathBuf;

#[path = "common/aograph_view.rs"]
mod aograph_view;

use aograph_bevy::{AographAo, AographAoPlugin, AographAoStatus};
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass, NormalPrepass};
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel};
use bevy::prelude::*;

use aograph_view::AographView;

/// What the space bar steps through: aograph's techniques by their `[ao]` settings, then
/// bevy's own SSAO (`None`).
const CYCLE: [Option<&str>; 9] = [
    Some("technique = \"gtao\""),
    Some("technique = \"gtao\"\n[gtao]\nresolution = \"half\"\ntemporal = true"),
    Some("technique = \"vbao\""),
    Some("technique = \"mssao\""),
    Some("technique = \"hbao\""),
    Some("technique = \"pyramid-hbao\""),
    Some("technique = \"ssao\""),
    Some("technique = \"tssao\""),
    None,
];

#[derive(Resource)]
struct Cycle {
    index: usize,
    radius: f32,
}

#[derive(Component)]
struct Caption;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes/teapot.gltf")
        });
    let file = file.canonicalize()?;
    // aograph's view of the file: the camera and radius `aograph render` would use (bevy
    // keeps the projection's aspect ratio the window's).
    let view = AographView::of(&file)?;
    let (transform, radius) = (view.transform(), view.radius);
    let projection = view.projection(16.0 / 9.0)?;
    println!("aograph's radius: {}", view.prepared.radius_note);
    let folder = file
        .parent()
        .ok_or("a file in a folder")?
        .to_string_lossy()
        .into_owned();
    let name = file
        .file_name()
        .ok_or("a file name")?
        .to_string_lossy()
        .into_owned();

    App::new()
        .add_plugins(DefaultPlugins.set(AssetPlugin {
            file_path: folder,
            ..default()
        }))
        .add_plugins(AographAoPlugin)
        .insert_resource(Cycle { index: 0, radius })
        .add_systems(
            Startup,
            move |mut commands: Commands, assets: Res<AssetServer>| {
                commands.spawn(bevy::world_serialization::WorldAssetRoot(
                    assets.load(GltfAssetLabel::Scene(0).from_asset(name.clone())),
                ));
                commands.spawn((
                    DirectionalLight::default(),
                    Transform::from_xyz(2.0, 5.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
                ));
                let ao = settings(CYCLE[0], radius).expect("the first settings are valid");
                commands.spawn((
                    Camera3d::default(),
                    Msaa::Off,
                    transform,
                    projection.clone(),
                    DepthPrepass,
                    NormalPrepass,
                    MotionVectorPrepass,
                    ao,
                ));
                commands.spawn((
                    Caption,
                    Text::new(""),
                    Node {
                        position_type: PositionType::Absolute,
                        top: px(8),
                        left: px(8),
                        ..default()
                    },
                ));
            },
        )
        .add_systems(Update, (cycle, caption, screenshot))
        .run();
    Ok(())
}

fn settings(toml: Option<&str>, radius: f32) -> Option<AographAo> {
    let toml = toml?;
    match AographAo::from_toml(&format!("radius = {radius}\n{toml}")) {
        Ok(ao) => Some(ao),
        Err(e) => {
            error!("{e}");
            None
        }
    }
}

fn cycle(
    keys: Res<ButtonInput<KeyCode>>,
    mut state: ResMut<Cycle>,
    mut commands: Commands,
    cameras: Query<Entity, With<Camera3d>>,
) {
    if !keys.just_pressed(KeyCode::Space) {
        return;
    }
    state.index = (state.index + 1) % CYCLE.len();
    for camera in &cameras {
        let mut camera = commands.entity(camera);
        match settings(CYCLE[state.index], state.radius) {
            Some(ao) => {
                camera.insert(ao);
            }
            None => {
                camera
                    .remove::<AographAo>()
                    .insert(ScreenSpaceAmbientOcclusion {
                        quality_level: ScreenSpaceAmbientOcclusionQualityLevel::High,
                        radius: state.radius,
                        ..default()
                    });
            }
        }
    }
}

fn caption(
    status: Res<AographAoStatus>,
    cameras: Query<(Entity, Option<&AographAo>), With<Camera3d>>,
    mut text: Single<&mut Text, With<Caption>>,
) {
    let Some((camera, ao)) = cameras.iter().next() else {
        return;
    };
    text.0 = match (ao, status.camera(camera)) {
        (None, _) => "bevy's own SSAO (High) [space: next]".into(),
        (Some(_), Some(s)) => {
            let time = s.gpu_ms.map_or("GPU time: no timestamps".into(), |ms| {
                format!("{ms:.2} ms GPU (timestamps)")
            });
            let preparing = if s.preparing {
                ", preparing the next"
            } else {
                ""
            };
            format!("aograph {}: {time}{preparing} [space: next]", s.technique)
        }
        (Some(ao), None) => format!("aograph {} [space: next]", ao.technique()),
    };
}

/// With `BEVY_AO_SCREENSHOT` set: the window at frame 90 to that file, then exit.
fn screenshot(
    frames: Res<bevy::diagnostic::FrameCount>,
    mut commands: Commands,
    mut exit: MessageWriter<AppExit>,
) {
    use bevy::render::view::screenshot::{Screenshot, save_to_disk};
    let Some(path) = std::env::var_os("BEVY_AO_SCREENSHOT") else {
        return;
    };
    match frames.0 {
        90 => {
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(PathBuf::from(path)));
        }
        100 => {
            exit.write(AppExit::Success);
        }
        _ => {}
    }
}
