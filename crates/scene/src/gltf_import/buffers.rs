//! Loads the binary buffers a glTF document refers to (GLB chunk, base64 data URI or external
//! file) and reports referenced images that are missing.
//!
//! We resolve URIs here instead of calling `gltf::import_buffers` so that a missing .bin is
//! reported by name ([`SceneError::MissingBuffer`]) and so a malformed percent-encoded URI cannot
//! reach the `unwrap` in gltf 1.4's URI decoder. Images are never loaded: AO needs no textures.
//! A meshopt fallback buffer (it has no data; its views are decoded into it by
//! `meshopt_views`) is made as zeros of its declared length. A buffer without `uri` that is not
//! a .glb's binary chunk has its data outside the file: refused when aograph reads from it,
//! else left empty with a warning. `data:` URIs are decoded as base64 or, without `;base64`,
//! as percent-encoded bytes (RFC 2397).
//! Invariant: every returned buffer that aograph reads is at least as long as the document
//! declares, padded to a multiple of 4 bytes, in document order, so accessor reads can index
//! by buffer number (accessor reads are bounds-checked, so an empty unread one is harmless).

use std::collections::BTreeSet;

use crate::error::SceneError;
use std::path::{Path, PathBuf};

/// Percent-decodes a relative URI; malformed escapes are kept literally.
fn percent_decode(uri: &str) -> String {
    String::from_utf8_lossy(&percent_decode_bytes(uri)).into_owned()
}

/// The bytes `text` percent-encodes (RFC 3986 §2.1); malformed escapes are kept literally.
fn percent_decode_bytes(text: &str) -> Vec<u8> {
    let bytes = text.as_bytes();
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
    out
}

/// The bytes of a `data:` URI (RFC 2397): `data:[<media type>][;base64],<data>`.
fn data_uri_bytes(uri: &str) -> Result<Vec<u8>, String> {
    let rest = uri.strip_prefix("data:").unwrap_or(uri);
    let Some((header, data)) = rest.split_once(',') else {
        return Err("it has no comma between its media type and its data".into());
    };
    if header.ends_with(";base64") {
        let source = gltf::buffer::Source::Uri(uri);
        let data = gltf::buffer::Data::from_source(source, None)
            .map_err(|e| format!("its base64 does not decode: {e}"))?;
        Ok(data.0)
    } else {
        Ok(percent_decode_bytes(data))
    }
}

/// What the loader knows of a file's buffers before reading them.
pub(super) struct BufferUse<'a> {
    /// Buffers meshopt decodes into (`meshopt_views::fallback_buffers`): made as zeros.
    pub fallbacks: &'a [usize],
    /// Buffers something aograph reads points into.
    pub read: &'a BTreeSet<usize>,
    /// The file is a .glb, so a buffer without `uri` may be its binary chunk.
    pub glb: bool,
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

/// Reads every buffer of `document`; `blob` is the GLB binary chunk, if any. Returns the
/// buffers and warnings (buffers whose data is not in the file but which nothing reads).
pub(super) fn load_buffers(
    path: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    uses: &BufferUse<'_>,
) -> Result<(Vec<gltf::buffer::Data>, Vec<String>), SceneError> {
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let invalid = |message: String| SceneError::InvalidGltf {
        path: path.to_owned(),
        message,
    };
    let mut buffers = Vec::new();
    let mut warnings = Vec::new();
    for buffer in document.buffers() {
        let index = buffer.index();
        let mut data = match buffer.source() {
            _ if uses.fallbacks.contains(&index) => {
                if buffer.length() > MAX_FALLBACK_BYTES {
                    return Err(invalid(format!(
                        "buffer {index} is an EXT_meshopt_compression fallback of {} bytes, more \
                         than the {MAX_FALLBACK_BYTES} aograph decodes",
                        buffer.length()
                    )));
                }
                vec![0; buffer.length()]
            }
            gltf::buffer::Source::Bin if uses.glb && blob.is_some() => {
                blob.take().unwrap_or_default()
            }
            gltf::buffer::Source::Bin => {
                let why = match (uses.glb, index) {
                    (false, _) => "this .gltf file has no binary chunk".to_owned(),
                    (true, 0) => "this .glb file has no binary chunk".to_owned(),
                    (true, _) => "this .glb file's binary chunk is buffer 0's".to_owned(),
                };
                let message =
                    format!("buffer {index} has no uri and {why}, so its data is not in the file");
                if uses.read.contains(&index) {
                    return Err(invalid(message));
                }
                warnings.push(format!(
                    "{message}; nothing aograph reads uses it: continuing"
                ));
                buffers.push(gltf::buffer::Data(Vec::new()));
                continue;
            }
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => data_uri_bytes(uri)
                .map_err(|e| {
                    invalid(format!(
                        "buffer {index} has a data URI that cannot be read: {e}"
                    ))
                })?,
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
    Ok((buffers, warnings))
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

    #[test]
    fn data_uris_decode_as_base64_or_percent_encoded_bytes() {
        assert_eq!(
            data_uri_bytes("data:application/octet-stream;base64,AAEC/w=="),
            Ok(vec![0, 1, 2, 255])
        );
        assert_eq!(
            data_uri_bytes("data:,%00%01AB%ff"),
            Ok(vec![0, 1, b'A', b'B', 255])
        );
        assert!(
            data_uri_bytes("data:application/octet-stream")
                .unwrap_err()
                .contains("no comma")
        );
    }
}
