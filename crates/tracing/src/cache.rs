//! A disk cache of reference images, so a long reference run is paid once per input.
//!
//! The key is a 128-bit FNV-1a hash of everything the result depends on, and nothing else:
//! - the traced surfaces: every pixel's point, normal and valid flag (bit patterns), so a
//!   changed g-buffer (a fixed normal transform, another normal choice, another camera or
//!   resolution) is a miss;
//! - the world-space triangles the rays are traced against (bit patterns);
//! - R, rays per pixel and the mode (the progress setting is excluded: it changes no value);
//! - the tracer itself: the source text of the estimator, its sampling and its BVH, compiled
//!   in, so editing the tracer's code invalidates old entries without a hand-bumped version.
//!
//! Entries are two raw AOREF32 files, `<key>.accessibility.aoref` and
//! `<key>.std_error.aoref`, each written atomically. Radiance references (SSDO's, see
//! [`crate::radiance::trace_radiance`]) have keys of their own ([`CacheKey::radiance`]: also the sky,
//! every albedo and the radiance code) and two files, `<key>.radiance_direct.aoref` and
//! `<key>.radiance_indirect.aoref`, RGB interleaved in rows three times as wide. Invariants: a changed input changes the
//! key (up to hash collisions); a truncated or corrupt entry is reported on stderr and treated
//! as a miss, never returned.

pub use crate::cache_key::CacheKey;
#[cfg(test)]
use crate::cache_key::{gpu_tracer_sources, hardware_tracer_sources};
use crate::error::TracingError;
use crate::radiance::RadianceImage;
use aograph_scene::error::SceneError;
use aograph_scene::reference::{ReferenceImage, read_raw_f32, write_raw_f32};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// A directory of cached reference images, keyed by [`CacheKey`]: AO references as two
/// AOREF32 files each, radiance references as two RGB ones. Cheap to clone (just the path).
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
        let read = || -> Result<ReferenceImage, TracingError> {
            let accessibility = read_raw_f32(&accessibility_path)?;
            let std_error = read_raw_f32(&error_path)?;
            if (accessibility.width, accessibility.height) != (std_error.width, std_error.height) {
                return Err(SceneError::BadReferenceFile {
                    path: error_path.clone(),
                    reason: "its size differs from the accessibility file's".into(),
                }
                .into());
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
    pub fn store(&self, key: CacheKey, image: &ReferenceImage) -> Result<(), TracingError> {
        std::fs::create_dir_all(&self.dir)
            .map_err(|e| SceneError::io("create cache directory", &self.dir, e))?;
        let (accessibility_path, error_path) = self.paths(key);
        // The std_error file goes first: `load` needs both, so a crash in between is a miss.
        write_raw_f32(&error_path, image.width, image.height, &image.std_error)?;
        Ok(write_raw_f32(
            &accessibility_path,
            image.width,
            image.height,
            &image.accessibility,
        )?)
    }

    /// The two files of radiance entry `key`: direct, then indirect.
    fn radiance_paths(&self, key: CacheKey) -> [PathBuf; 2] {
        [
            self.dir.join(format!("{key}.radiance_direct.aoref")),
            self.dir.join(format!("{key}.radiance_indirect.aoref")),
        ]
    }

    /// The radiance entry for `key`, if present and whole (a corrupt one warns and misses).
    pub fn load_radiance(&self, key: CacheKey) -> Option<RadianceImage> {
        let paths = self.radiance_paths(key);
        if !paths.iter().all(|p| p.exists()) {
            return None;
        }
        let read = |path: &PathBuf| -> Result<(u32, u32, Vec<Vec3>), TracingError> {
            let raw = read_raw_f32(path)?;
            if raw.width % 3 != 0 {
                return Err(SceneError::BadReferenceFile {
                    path: path.clone(),
                    reason: "its width is not three channels a pixel".into(),
                }
                .into());
            }
            let rgb = raw.values.chunks_exact(3).map(Vec3::from_slice).collect();
            Ok((raw.width / 3, raw.height, rgb))
        };
        match (read(&paths[0]), read(&paths[1])) {
            (Ok((w, h, direct)), Ok((w2, h2, indirect))) if (w, h) == (w2, h2) => {
                Some(RadianceImage {
                    width: w,
                    height: h,
                    direct,
                    indirect,
                })
            }
            (Err(e), _) | (_, Err(e)) => {
                eprintln!("warning: ignoring corrupt radiance cache entry: {e}");
                None
            }
            _ => {
                eprintln!(
                    "warning: ignoring radiance cache entry {key}: its two files differ in size"
                );
                None
            }
        }
    }

    /// Writes `image` under `key` (each file atomically).
    pub fn store_radiance(&self, key: CacheKey, image: &RadianceImage) -> Result<(), TracingError> {
        std::fs::create_dir_all(&self.dir)
            .map_err(|e| SceneError::io("create cache directory", &self.dir, e))?;
        let [direct, indirect] = self.radiance_paths(key);
        let flat = |v: &[Vec3]| v.iter().flat_map(|c| c.to_array()).collect::<Vec<f32>>();
        write_raw_f32(
            &indirect,
            image.width * 3,
            image.height,
            &flat(&image.indirect),
        )?;
        Ok(write_raw_f32(
            &direct,
            image.width * 3,
            image.height,
            &flat(&image.direct),
        )?)
    }

    /// The radiance entry for `key`, traced by `trace` (and stored) when missing.
    pub fn get_or_trace_radiance(
        &self,
        key: CacheKey,
        trace: impl FnOnce() -> Result<RadianceImage, TracingError>,
    ) -> Result<RadianceImage, TracingError> {
        if let Some(image) = self.load_radiance(key) {
            return Ok(image);
        }
        let image = trace()?;
        self.store_radiance(key, &image)?;
        Ok(image)
    }

    /// The cached image for `key`, or the result of `trace` (then stored); a corrupt entry
    /// warns on stderr and is traced again.
    pub fn get_or_trace(
        &self,
        key: CacheKey,
        trace: impl FnOnce() -> Result<ReferenceImage, TracingError>,
    ) -> Result<ReferenceImage, TracingError> {
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
    use aograph_scene::environment::SkyEnvironment;
    use aograph_scene::reference::ReferenceMode;
    use aograph_scene::reference::{ReferenceParams, SurfaceBuffer};

    fn surfaces() -> SurfaceBuffer {
        SurfaceBuffer {
            width: 2,
            height: 1,
            points: vec![Vec3::new(0.1, 0.2, 0.0), Vec3::ZERO],
            normals: vec![Vec3::Z, Vec3::ZERO],
            valid: vec![true, false],
        }
    }

    #[test]
    fn key_changes_with_each_input_but_not_with_progress() {
        let tris = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let params = ReferenceParams::default();
        let base = CacheKey::new(&tris, &surfaces(), &params);
        assert_eq!(base, CacheKey::new(&tris, &surfaces(), &params));
        let moved = vec![[Vec3::ZERO, Vec3::X, Vec3::Y * 1.001]];
        assert_ne!(base, CacheKey::new(&moved, &surfaces(), &params));
        let obscurance = ReferenceParams {
            mode: ReferenceMode::Obscurance,
            ..params
        };
        assert_ne!(base, CacheKey::new(&tris, &surfaces(), &obscurance));
        let wider = ReferenceParams {
            radius: 1.5,
            ..params
        };
        assert_ne!(base, CacheKey::new(&tris, &surfaces(), &wider));
        let quiet = ReferenceParams {
            progress: aograph_scene::reference::ProgressMode::Never,
            ..params
        };
        assert_eq!(base, CacheKey::new(&tris, &surfaces(), &quiet));
    }

    #[test]
    fn gpu_keys_cover_the_rust_that_builds_what_the_tracers_trace() {
        // An edit to how the BVH or the acceleration structures are built must change the
        // keys (it was missed once: stale images were served after a builder change).
        let covers = |sources: &[&str], file: &str| sources.contains(&file);
        assert!(covers(
            &gpu_tracer_sources(),
            include_str!("gpu/scene_bvh.rs")
        ));
        assert!(covers(
            &gpu_tracer_sources(),
            include_str!("gpu/gpu_bvh.rs")
        ));
        assert!(covers(
            &hardware_tracer_sources(),
            include_str!("gpu/hardware.rs")
        ));
        assert!(!covers(
            &gpu_tracer_sources(),
            include_str!("gpu/hardware.rs")
        ));
    }

    #[test]
    fn the_key_names_the_tracer_and_auto_is_the_cpu_only_on_a_software_device() {
        use aograph_scene::reference::ReferenceTracer;
        let tris = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let base = CacheKey::new(&tris, &surfaces(), &ReferenceParams::default());
        assert_ne!(base, base.gpu_traced());
        assert_eq!(base.gpu_traced(), base.gpu_traced());
        assert_eq!(
            ReferenceTracer::Auto.resolve(true, true),
            ReferenceTracer::Cpu
        );
        assert_eq!(
            ReferenceTracer::Auto.resolve(false, false),
            ReferenceTracer::Gpu
        );
        assert_eq!(
            ReferenceTracer::Auto.resolve(false, true),
            ReferenceTracer::Hardware
        );
        assert_eq!(
            ReferenceTracer::Cpu.resolve(false, true),
            ReferenceTracer::Cpu
        );
        assert_eq!(
            ReferenceTracer::Gpu.resolve(true, true),
            ReferenceTracer::Gpu
        );
        assert_eq!(
            ReferenceTracer::Hardware.resolve(true, false),
            ReferenceTracer::Hardware
        );
        assert_eq!(ReferenceTracer::parse("compute"), Ok(ReferenceTracer::Gpu));
        assert_eq!(
            ReferenceTracer::parse("hardware"),
            Ok(ReferenceTracer::Hardware)
        );
        let e = ReferenceTracer::parse("embree").unwrap_err();
        assert!(e.contains("auto, cpu, gpu"), "{e}");
    }

    #[test]
    fn radiance_entries_have_keys_of_their_own_and_round_trip() {
        let tris = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let params = ReferenceParams::default();
        let sky = SkyEnvironment::for_scene(&aograph_scene::procedural_scene("plane").unwrap());
        let (tri_albedo, px_albedo) = (vec![Vec3::splat(0.5)], vec![Vec3::ONE, Vec3::ZERO]);
        let key = |t: &[Vec3], p: &[Vec3], s: &SkyEnvironment| {
            CacheKey::radiance(&tris, &surfaces(), &params, t, p, s)
        };
        let base = key(&tri_albedo, &px_albedo, &sky);
        assert_ne!(base, CacheKey::new(&tris, &surfaces(), &params));
        assert_ne!(base, key(&[Vec3::splat(0.6)], &px_albedo, &sky));
        assert_ne!(base, key(&tri_albedo, &[Vec3::ONE, Vec3::X], &sky));
        let warmer = SkyEnvironment {
            sun_exponent: 9.0,
            ..sky
        };
        assert_ne!(base, key(&tri_albedo, &px_albedo, &warmer));

        let dir =
            std::env::temp_dir().join(format!("aograph-radiance-cache-{}", std::process::id()));
        let cache = ReferenceCache::new(&dir);
        let image = RadianceImage {
            width: 2,
            height: 1,
            direct: vec![Vec3::new(0.1, 0.2, 0.3), Vec3::ZERO],
            indirect: vec![Vec3::new(0.01, 0.0, 0.5), Vec3::ZERO],
        };
        assert_eq!(cache.load_radiance(base), None);
        let mut traced = 0;
        let first = cache
            .get_or_trace_radiance(base, || {
                traced += 1;
                Ok(image.clone())
            })
            .unwrap();
        let second = cache
            .get_or_trace_radiance(base, || {
                traced += 1;
                Ok(image.clone())
            })
            .unwrap();
        assert_eq!((first, second.clone(), traced), (image.clone(), image, 1));
        // A truncated file is a miss, not an error or a wrong image.
        let direct = dir.join(format!("{base}.radiance_direct.aoref"));
        let bytes = std::fs::read(&direct).unwrap();
        std::fs::write(&direct, &bytes[..bytes.len() - 4]).unwrap();
        assert_eq!(cache.load_radiance(base), None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn one_changed_surface_value_is_a_cache_miss() {
        // A g-buffer fixed in one pixel (one normal component, one point coordinate, or one
        // pixel turned sky) must not be served the old entry.
        let tris = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let params = ReferenceParams::default();
        let base = CacheKey::new(&tris, &surfaces(), &params);
        let dir = std::env::temp_dir().join(format!("aograph-cache-miss-{}", std::process::id()));
        let cache = ReferenceCache::new(&dir);
        let image = ReferenceImage {
            width: 2,
            height: 1,
            accessibility: vec![0.25, 1.0],
            std_error: vec![0.01, 0.0],
        };
        cache.store(base, &image).unwrap();
        assert_eq!(cache.load(base), Some(image));
        let mut normal = surfaces();
        normal.normals[0] = Vec3::new(0.0, 1e-3, 1.0).normalize();
        let mut point = surfaces();
        point.points[0].x = f32::from_bits(point.points[0].x.to_bits() + 1);
        let mut sky = surfaces();
        sky.valid[0] = false;
        for changed in [normal, point, sky] {
            let key = CacheKey::new(&tris, &changed, &params);
            assert_ne!(key, base);
            assert!(
                cache.load(key).is_none(),
                "a changed surface was served the old entry"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
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
