//! Image files: 8-bit grayscale PNGs of accessibility, RGBA PNGs, and an output directory that
//! is written atomically (files go to a temporary sibling first, so a failed run leaves
//! nothing partial behind and never clobbers a previous good file).

use std::path::{Path, PathBuf};

use aograph_app_config::error::{AppError, AppResult};

/// Creates `dir` (and parents) and checks it is writable by writing a probe file.
pub fn prepare_output_dir(dir: &Path) -> AppResult<()> {
    std::fs::create_dir_all(dir).map_err(|e| AppError::io("create output directory", dir, e))?;
    let probe = dir.join(".aograph-write-test");
    std::fs::write(&probe, b"").map_err(|e| AppError::io("write to output directory", dir, e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial"))
}

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> AppResult<()> {
    let tmp = temp_path(path);
    std::fs::write(&tmp, bytes).map_err(|e| AppError::io("write", &tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        AppError::io("write", path, e)
    })
}

fn encode_png(
    width: u32,
    height: u32,
    color: image::ExtendedColorType,
    data: &[u8],
    path: &Path,
) -> AppResult<Vec<u8>> {
    let mut out = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut out),
        data,
        width,
        height,
        color,
    )
    .map_err(|e| AppError::Image {
        path: path.into(),
        message: e.to_string(),
    })?;
    Ok(out)
}

/// Accessibility (or any [0, 1] value) as an 8-bit grayscale PNG; values are clamped and
/// non-finite values written as 0 (they never should occur).
pub fn write_gray_png(path: &Path, width: u32, height: u32, values: &[f32]) -> AppResult<()> {
    let data: Vec<u8> = values
        .iter()
        .map(|v| {
            if v.is_finite() {
                (v.clamp(0.0, 1.0) * 255.0).round() as u8
            } else {
                0
            }
        })
        .collect();
    write_atomic(
        path,
        &encode_png(width, height, image::ExtendedColorType::L8, &data, path)?,
    )
}

/// RGBA8 pixels as a PNG.
pub fn write_rgba_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> AppResult<()> {
    write_atomic(
        path,
        &encode_png(width, height, image::ExtendedColorType::Rgba8, rgba, path)?,
    )
}

/// RGB8 pixels as a PNG.
pub fn write_rgb_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> AppResult<()> {
    write_atomic(
        path,
        &encode_png(width, height, image::ExtendedColorType::Rgb8, rgb, path)?,
    )
}
