//! Loads the binary buffers a glTF document refers to (GLB chunk, base64 data URI or external
//! file) and reports referenced images that are missing.
//!
//! We resolve URIs here instead of calling `gltf::import_buffers` so that a missing .bin is
//! reported by name ([`SceneError::MissingBuffer`]) and so a malformed percent-encoded URI cannot
//! reach the `unwrap` in gltf 1.4's URI decoder. Images are never loaded: AO needs no textures.
//! A buffer EXT_meshopt_compression marks as a `fallback` (it has no data; its views are
//! decoded into it by `meshopt_views`) is made as zeros of its declared length.
//! Invariant: every returned buffer is at least as long as the document declares, padded to a
//! multiple of 4 bytes, in document order, so accessor reads can index by buffer number.

use crate::error::SceneError;
use std::path::{Path, PathBuf};

/// Percent-decodes a relative URI; malformed escapes are kept literally.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Where a non-data URI points on disk, or `None` for an unsupported scheme (http:, ...).
fn resolve_uri(base_dir: &Path, uri: &str) -> Option<PathBuf> {
    if let Some(rest) = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
    {
        return Some(PathBuf::from(percent_decode(rest)));
    }
    if uri.contains(':') {
        return None;
    }
    Some(base_dir.join(percent_decode(uri)))
}

/// The largest fallback buffer made (2 GiB): a declared length is not allocated unchecked.
const MAX_FALLBACK_BYTES: usize = 1 << 31;

/// Reads every buffer of `document`; `blob` is the GLB binary chunk, if any.
pub(super) fn load_buffers(
    path: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    fallbacks: &[usize],
) -> Result<Vec<gltf::buffer::Data>, SceneError> {
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let invalid = |message: String| SceneError::InvalidGltf {
        path: path.to_owned(),
        message,
    };
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let index = buffer.index();
        let mut data = match buffer.source() {
            _ if fallbacks.contains(&index) => {
                if buffer.length() > MAX_FALLBACK_BYTES {
                    return Err(invalid(format!(
                        "buffer {index} is an EXT_meshopt_compression fallback of {} bytes, more \
                         than the {MAX_FALLBACK_BYTES} aograph decodes",
                        buffer.length()
                    )));
                }
                vec![0; buffer.length()]
            }
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                invalid(format!(
                    "buffer {index} refers to the GLB binary chunk, but the file has none"
                ))
            })?,
            source @ gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                gltf::buffer::Data::from_source(source, None)
                    .map_err(|e| invalid(format!("buffer {index} has a bad data URI: {e}")))?
                    .0
            }
            gltf::buffer::Source::Uri(uri) => {
                let resolved = resolve_uri(base_dir, uri).ok_or_else(|| {
                    invalid(format!(
                        "buffer {index} has URI \"{uri}\" with an unsupported scheme \
                         (only relative paths, file: and data: URIs are read)"
                    ))
                })?;
                match std::fs::read(&resolved) {
                    Ok(bytes) => bytes,
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                        return Err(SceneError::MissingBuffer {
                            path: path.to_owned(),
                            uri: uri.to_owned(),
                            resolved,
                        });
                    }
                    Err(e) => return Err(SceneError::io("read buffer file", resolved, e)),
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(invalid(format!(
                "buffer {index} holds {} bytes but declares {} (truncated .bin or data URI?)",
                data.len(),
                buffer.length()
            )));
        }
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        buffers.push(gltf::buffer::Data(data));
    }
    Ok(buffers)
}

/// The image URIs of `document` that point to files that do not exist.
pub(super) fn missing_images(path: &Path, document: &gltf::Document) -> Vec<String> {
    let base_dir = path.parent().unwrap_or(Path::new("."));
    document
        .as_json()
        .images
        .iter()
        .filter_map(|image| image.uri.as_deref())
        .filter(|uri| !uri.starts_with("data:"))
        .filter(|uri| resolve_uri(base_dir, uri).is_none_or(|p| !p.exists()))
        .map(str::to_owned)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding_keeps_malformed_escapes() {
        assert_eq!(percent_decode("a%20b.bin"), "a b.bin");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz%4"), "%zz%4");
    }
}
