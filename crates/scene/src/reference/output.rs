//! The reference result ([`ReferenceImage`]) and its files: 16-bit grayscale PNG and raw f32.
//!
//! Raw f32 format ("AOREF32"), little-endian throughout:
//! bytes 0..8 the magic `b"AOREF32\0"`, 8..12 width (u32), 12..16 height (u32), then
//! width * height f32 values, row-major, top row first. Invariants: a written file is complete
//! or absent (temporary file + rename); the reader rejects files whose length does not match
//! their header, with the file named in the error; PNG values are round(A * 65535).

use crate::atomic_file::write_atomically;
use crate::error::SceneError;
use std::path::Path;

/// Magic bytes that start a raw f32 image.
pub const RAW_MAGIC: &[u8; 8] = b"AOREF32\0";
const HEADER_LEN: usize = 16;

/// Per-pixel reference accessibility and its standard error, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceImage {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Accessibility in [0, 1], 1 = unoccluded (and sky).
    pub accessibility: Vec<f32>,
    /// Standard error of each pixel's estimate (0 for sky).
    pub std_error: Vec<f32>,
}

/// A single-channel f32 image read from a raw AOREF32 file.
#[derive(Clone, Debug, PartialEq)]
pub struct RawF32Image {
    /// Width from the header, in values per row (three times the pixels for an RGB file).
    pub width: u32,
    /// Height from the header, in rows.
    pub height: u32,
    /// The `width * height` values, row-major, top row first.
    pub values: Vec<f32>,
}

impl ReferenceImage {
    /// Accessibility at pixel (x, y), or `None` outside the image.
    pub fn at(&self, x: u32, y: u32) -> Option<f32> {
        if x >= self.width || y >= self.height {
            return None;
        }
        self.accessibility
            .get(y as usize * self.width as usize + x as usize)
            .copied()
    }

    /// Writes the accessibility as a 16-bit grayscale PNG.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        write_png16(path.as_ref(), self.width, self.height, &self.accessibility)
    }

    /// Writes the standard error, scaled by `scale` (e.g. 10) and clamped to [0, 1], as a
    /// 16-bit grayscale PNG, to see where the estimate is noisy.
    pub fn write_std_error_png(
        &self,
        path: impl AsRef<Path>,
        scale: f32,
    ) -> Result<(), SceneError> {
        let scaled: Vec<f32> = self.std_error.iter().map(|e| e * scale).collect();
        write_png16(path.as_ref(), self.width, self.height, &scaled)
    }

    /// Writes the accessibility in the raw AOREF32 format.
    pub fn write_raw(&self, path: impl AsRef<Path>) -> Result<(), SceneError> {
        write_raw_f32(path.as_ref(), self.width, self.height, &self.accessibility)
    }
}

/// Writes `values` (clamped to [0, 1], NaN as 0) as a 16-bit grayscale PNG.
pub fn write_png16(path: &Path, width: u32, height: u32, values: &[f32]) -> Result<(), SceneError> {
    let png_error = |message: String| SceneError::Png {
        path: path.to_owned(),
        message,
    };
    let pixels: Vec<u16> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16)
        .collect();
    let buffer = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(width, height, pixels)
        .ok_or_else(|| {
            png_error(format!(
                "{} values do not fill a {width}x{height} image",
                values.len()
            ))
        })?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    buffer
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| png_error(e.to_string()))?;
    write_atomically(path, bytes.get_ref())
}

/// Writes `values` in the raw AOREF32 format described in the module docs.
pub fn write_raw_f32(
    path: &Path,
    width: u32,
    height: u32,
    values: &[f32],
) -> Result<(), SceneError> {
    let expected = width as usize * height as usize;
    if values.len() != expected {
        return Err(SceneError::InputSizeMismatch {
            what: "raw image values",
            width,
            height,
            expected,
            actual: values.len(),
        });
    }
    let mut bytes = Vec::with_capacity(HEADER_LEN + 4 * values.len());
    bytes.extend_from_slice(RAW_MAGIC);
    bytes.extend_from_slice(&width.to_le_bytes());
    bytes.extend_from_slice(&height.to_le_bytes());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    write_atomically(path, &bytes)
}

/// Reads a raw AOREF32 file.
pub fn read_raw_f32(path: impl AsRef<Path>) -> Result<RawF32Image, SceneError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => SceneError::MissingFile {
            path: path.to_owned(),
        },
        _ => SceneError::io("read", path, e),
    })?;
    let bad = |reason: String| SceneError::BadReferenceFile {
        path: path.to_owned(),
        reason,
    };
    if bytes.len() < HEADER_LEN || &bytes[..8] != RAW_MAGIC {
        return Err(bad("it does not start with the AOREF32 header".into()));
    }
    let word =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let (width, height) = (word(8), word(12));
    let count = width as usize * height as usize;
    let expected = count.checked_mul(4).and_then(|n| n.checked_add(HEADER_LEN));
    if expected != Some(bytes.len()) {
        return Err(bad(format!(
            "the header says {width}x{height}, which needs {} bytes, but the file has {}",
            expected.map_or_else(|| "too many".to_string(), |n| n.to_string()),
            bytes.len()
        )));
    }
    let values = bytes[HEADER_LEN..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Ok(RawF32Image {
        width,
        height,
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_path(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("aograph-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn raw_round_trip_and_truncation_is_reported() {
        let path = temp_path("round.aoref");
        let values = vec![0.0, 0.25, 0.5, 1.0, 0.75, 0.125];
        write_raw_f32(&path, 3, 2, &values).unwrap();
        let read = read_raw_f32(&path).unwrap();
        assert_eq!((read.width, read.height), (3, 2));
        assert_eq!(read.values, values);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 2]).unwrap();
        let err = read_raw_f32(&path).unwrap_err().to_string();
        assert!(err.contains("round.aoref") && err.contains("3x2"), "{err}");
    }

    #[test]
    fn png_is_sixteen_bit_grayscale() {
        let path = temp_path("ao.png");
        let image = ReferenceImage {
            width: 2,
            height: 1,
            accessibility: vec![0.0, 1.0],
            std_error: vec![0.0, 0.0],
        };
        image.write_png(&path).unwrap();
        let decoded = image::open(&path).unwrap();
        assert_eq!(decoded.color(), image::ColorType::L16);
        let luma = decoded.into_luma16();
        assert_eq!(luma.as_raw(), &vec![0u16, 65535]);
    }
}
