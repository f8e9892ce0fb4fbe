//! A disk cache of reference images, so a long reference run is paid once per input.
//!
//! The key is a 128-bit FNV-1a hash of everything the result depends on: a tracer version tag,
//! the world-space triangles (bit patterns), the camera (position, target, up, projection),
//! the resolution, R, N and the mode (the progress setting is excluded). Entries are two raw
//! AOREF32 files, `<key>.accessibility.aoref` and `<key>.std_error.aoref`, each written
//! atomically. Invariants: a changed input changes the key (up to hash collisions); a
//! truncated or corrupt entry is reported on stderr and treated as a miss, never returned.

use super::ReferenceParams;
use super::output::{ReferenceImage, read_raw_f32, write_raw_f32};
use crate::camera::{Camera, Projection};
use crate::error::SceneError;
use glam::Vec3;
use std::fmt;
use std::path::{Path, PathBuf};

/// Bump when the tracer's output for the same input changes (sampling, epsilon, ...).
const TRACER_VERSION: &str = "aograph-reference-v1";

/// 128-bit FNV-1a hasher over explicit byte sequences (stable across platforms and Rust
/// versions, unlike `std::hash`).
#[derive(Clone, Copy, Debug)]
struct Fnv1a128(u128);

impl Fnv1a128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;

    fn new() -> Self {
        Fnv1a128(Self::OFFSET)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u128::from(b);
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }

    fn vec3(&mut self, v: Vec3) {
        self.f32(v.x);
        self.f32(v.y);
        self.f32(v.z);
    }
}

/// Identifies one reference result; shown as 32 hex digits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey(pub u128);

impl fmt::Display for CacheKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:032x}", self.0)
    }
}

impl CacheKey {
    /// The key of a reference of `triangles` seen by `camera` at `width` x `height`.
    pub fn new(
        triangles: &[[Vec3; 3]],
        camera: &Camera,
        width: u32,
        height: u32,
        params: &ReferenceParams,
    ) -> CacheKey {
        let mut h = Fnv1a128::new();
        h.bytes(TRACER_VERSION.as_bytes());
        h.u32(triangles.len() as u32);
        for tri in triangles {
            tri.iter().for_each(|v| h.vec3(*v));
        }
        h.vec3(camera.position);
        h.vec3(camera.target);
        h.vec3(camera.up);
        match camera.projection {
            Projection::Perspective {
                fov_y,
                near,
                far,
                reversed_z_infinite,
            } => {
                h.u32(1);
                [fov_y, near, far].into_iter().for_each(|v| h.f32(v));
                h.u32(u32::from(reversed_z_infinite));
            }
            Projection::Orthographic { height, near, far } => {
                h.u32(2);
                [height, near, far].into_iter().for_each(|v| h.f32(v));
            }
        }
        h.u32(width);
        h.u32(height);
        h.f32(params.radius);
        h.u32(params.rays_per_pixel);
        h.u32(params.mode as u32);
        CacheKey(h.0)
    }
}

/// A directory of cached reference images.
#[derive(Clone, Debug)]
pub struct ReferenceCache {
    dir: PathBuf,
}

impl ReferenceCache {
    /// A cache in `dir` (created on first store).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ReferenceCache { dir: dir.into() }
    }

    /// The cache directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn paths(&self, key: CacheKey) -> (PathBuf, PathBuf) {
        (
            self.dir.join(format!("{key}.accessibility.aoref")),
            self.dir.join(format!("{key}.std_error.aoref")),
        )
    }

    /// The cached image for `key`, or `None` when absent or unreadable (reported on stderr).
    pub fn load(&self, key: CacheKey) -> Option<ReferenceImage> {
        let (accessibility_path, error_path) = self.paths(key);
        if !accessibility_path.exists() || !error_path.exists() {
            return None;
        }
        let read = || -> Result<ReferenceImage, SceneError> {
            let accessibility = read_raw_f32(&accessibility_path)?;
            let std_error = read_raw_f32(&error_path)?;
            if (accessibility.width, accessibility.height) != (std_error.width, std_error.height) {
                return Err(SceneError::BadReferenceFile {
                    path: error_path.clone(),
                    reason: "its size differs from the accessibility file's".into(),
                });
            }
            Ok(ReferenceImage {
                width: accessibility.width,
                height: accessibility.height,
                accessibility: accessibility.values,
                std_error: std_error.values,
            })
        };
        match read() {
            Ok(image) => Some(image),
            Err(e) => {
                eprintln!("warning: ignoring corrupt reference cache entry: {e}");
                None
            }
        }
    }

    /// Stores `image` under `key`.
    pub fn store(&self, key: CacheKey, image: &ReferenceImage) -> Result<(), SceneError> {
        std::fs::create_dir_all(&self.dir)
            .map_err(|e| SceneError::io("create cache directory", &self.dir, e))?;
        let (accessibility_path, error_path) = self.paths(key);
        // The std_error file goes first: `load` needs both, so a crash in between is a miss.
        write_raw_f32(&error_path, image.width, image.height, &image.std_error)?;
        write_raw_f32(
            &accessibility_path,
            image.width,
            image.height,
            &image.accessibility,
        )
    }

    /// The cached image for `key`, or the result of `trace` (then stored).
    pub fn get_or_trace(
        &self,
        key: CacheKey,
        trace: impl FnOnce() -> Result<ReferenceImage, SceneError>,
    ) -> Result<ReferenceImage, SceneError> {
        if let Some(image) = self.load(key) {
            return Ok(image);
        }
        let image = trace()?;
        self.store(key, &image)?;
        Ok(image)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::ReferenceMode;

    fn camera() -> Camera {
        Camera::perspective(Vec3::Z, Vec3::ZERO, 1.0, 0.1, 10.0)
    }

    #[test]
    fn key_changes_with_each_input_but_not_with_progress() {
        let tris = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let params = ReferenceParams::default();
        let base = CacheKey::new(&tris, &camera(), 8, 8, &params);
        let moved = vec![[Vec3::ZERO, Vec3::X, Vec3::Y * 1.001]];
        assert_ne!(base, CacheKey::new(&moved, &camera(), 8, 8, &params));
        assert_ne!(base, CacheKey::new(&tris, &camera(), 8, 9, &params));
        let obscurance = ReferenceParams {
            mode: ReferenceMode::Obscurance,
            ..params
        };
        assert_ne!(base, CacheKey::new(&tris, &camera(), 8, 8, &obscurance));
        let quiet = ReferenceParams {
            progress: crate::reference::ProgressMode::Never,
            ..params
        };
        assert_eq!(base, CacheKey::new(&tris, &camera(), 8, 8, &quiet));
    }

    #[test]
    fn stored_entry_is_returned_and_corrupt_entry_is_a_miss() {
        let dir = std::env::temp_dir().join(format!("aograph-cache-{}", std::process::id()));
        let cache = ReferenceCache::new(&dir);
        let key = CacheKey(42);
        let image = ReferenceImage {
            width: 2,
            height: 1,
            accessibility: vec![0.5, 1.0],
            std_error: vec![0.01, 0.0],
        };
        let traced = cache.get_or_trace(key, || Ok(image.clone())).unwrap();
        assert_eq!(traced, image);
        let cached = cache
            .get_or_trace(key, || panic!("should come from the cache"))
            .unwrap();
        assert_eq!(cached, image);
        std::fs::write(cache.paths(key).0, b"AOREF32\0garbage").unwrap();
        assert!(cache.load(key).is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
