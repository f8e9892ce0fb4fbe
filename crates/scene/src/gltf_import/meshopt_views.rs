//! Decodes buffer views compressed with EXT_meshopt_compression (gltfpack `-c`) or its
//! Khronos successor KHR_meshopt_compression into their buffer, so every accessor reads them
//! like uncompressed data.
//!
//! The extensions (KhronosGroup/glTF, extensions/2.0/Vendor/EXT_meshopt_compression and
//! Khronos/KHR_meshopt_compression: the same JSON; the KHR one adds the COLOR filter and the
//! codecs' version 1, both of which meshoptimizer 0.25 decodes) give each
//! compressed view a source range in another buffer, an element `count` and `byteStride`, a
//! `mode` (ATTRIBUTES: meshopt vertex codec; TRIANGLES: index codec; INDICES: index sequence)
//! and an optional `filter` (OCTAHEDRAL, QUATERNION, EXPONENTIAL) undone after decoding. The
//! view's own buffer is usually a "fallback" buffer without data, which `buffers` creates as
//! zeros (see `buffers::load_buffers`).
//! Invariant: meshoptimizer's decoders are called only with the sizes they assert on (stride a
//! multiple of 4 up to 256 for attributes, 2 or 4 for indices, the filter's stride), and with a
//! destination exactly `count * byteStride` bytes long inside the view; anything else is an
//! `Err` naming the view. The decoders reject malformed streams themselves (safe on untrusted
//! input, per meshoptimizer's documentation).

use serde_json::Value;

/// The JSON names of the extensions, vendor one first.
pub(super) const EXTENSIONS: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// How a compressed view's stream was encoded.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

/// What to undo on the decoded attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    /// KHR_meshopt_compression only: YCoCg colours (meshopt_decodeFilterColor).
    Color,
}

/// One compressed buffer view, as the extension object describes it.
#[derive(Clone, Debug, PartialEq)]
struct CompressedView {
    view: usize,
    /// Which of [`EXTENSIONS`] compressed it.
    extension: &'static str,
    source_buffer: usize,
    source_offset: usize,
    source_length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

/// Indices of the fallback buffers: those the extension marks `fallback` (they hold no data of
/// their own), and those without a `uri` that only compressed views use (a writer that left
/// the flag out made the same buffer: its bytes are never read, only decoded into).
pub(super) fn fallback_buffers(json: &Value) -> Vec<usize> {
    let views = array(json, "bufferViews");
    let sources: Vec<usize> = (views.iter())
        .filter_map(|v| extension(v).and_then(|(_, e)| usize_field(e, "buffer")))
        .collect();
    let only_compressed_views = |buffer: usize| {
        let mut on_it = views
            .iter()
            .filter(|v| usize_field(v, "buffer") == Some(buffer))
            .peekable();
        on_it.peek().is_some() && on_it.all(|v| extension(v).is_some())
    };
    array(json, "buffers")
        .iter()
        .enumerate()
        .filter(|(i, b)| {
            let flagged = extension(b)
                .and_then(|(_, e)| e.get("fallback"))
                .and_then(Value::as_bool)
                == Some(true);
            let unflagged =
                b.get("uri").is_none() && !sources.contains(i) && only_compressed_views(*i);
            flagged || unflagged
        })
        .map(|(i, _)| i)
        .collect()
}

/// Decodes every compressed view of `json` into `buffers`.
pub(super) fn decode_views(json: &Value, buffers: &mut [gltf::buffer::Data]) -> Result<(), String> {
    let views = array(json, "bufferViews");
    for (index, view) in views.iter().enumerate() {
        let Some((name, ext)) = extension(view) else {
            continue;
        };
        let compressed = parse_view(index, name, ext)?;
        let target_buffer =
            usize_field(view, "buffer").ok_or_else(|| no_field(index, name, "buffer"))?;
        let target_offset = usize_field(view, "byteOffset").unwrap_or(0);
        let target_length =
            usize_field(view, "byteLength").ok_or_else(|| no_field(index, name, "byteLength"))?;
        let decoded = decode(&compressed, buffers)?;
        if decoded.len() > target_length {
            return Err(format!(
                "buffer view {index}: {name} decodes to {} bytes, more than its byteLength {target_length}",
                decoded.len()
            ));
        }
        let target = buffers
            .get_mut(target_buffer)
            .and_then(|b| {
                let end = target_offset.checked_add(decoded.len())?;
                b.0.get_mut(target_offset..end)
            })
            .ok_or_else(|| {
                format!("buffer view {index} reaches past the end of buffer {target_buffer}")
            })?;
        target.copy_from_slice(&decoded);
    }
    Ok(())
}

fn array<'v>(json: &'v Value, key: &str) -> &'v [Value] {
    json.get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// The object's meshopt extension (either name) and its JSON.
fn extension(object: &Value) -> Option<(&'static str, &Value)> {
    let extensions = object.get("extensions")?;
    EXTENSIONS
        .iter()
        .find_map(|name| extensions.get(*name).map(|e| (*name, e)))
}

fn usize_field(object: &Value, key: &str) -> Option<usize> {
    object
        .get(key)
        .and_then(Value::as_u64)
        .and_then(|v| usize::try_from(v).ok())
}

fn no_field(view: usize, extension: &str, field: &str) -> String {
    format!("buffer view {view}: {extension} needs a whole-number `{field}`")
}

/// Reads and checks the extension object of view `view`.
fn parse_view(view: usize, name: &'static str, ext: &Value) -> Result<CompressedView, String> {
    let field = |key: &str| usize_field(ext, key).ok_or_else(|| no_field(view, name, key));
    let mode = match ext.get("mode").and_then(Value::as_str) {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        _ => {
            let written = ext.get("mode").map_or("missing".into(), Value::to_string);
            return Err(format!(
                "buffer view {view}: {name} mode {written} is not ATTRIBUTES, TRIANGLES or INDICES"
            ));
        }
    };
    let filter = match ext.get("filter").and_then(Value::as_str) {
        None | Some("NONE") => Filter::None,
        Some("OCTAHEDRAL") => Filter::Octahedral,
        Some("QUATERNION") => Filter::Quaternion,
        Some("EXPONENTIAL") => Filter::Exponential,
        Some("COLOR") if name == EXTENSIONS[1] => Filter::Color,
        Some(other) => {
            return Err(format!(
                "buffer view {view}: {name} filter \"{other}\" is not NONE, OCTAHEDRAL, \
                 QUATERNION, EXPONENTIAL{}",
                if name == EXTENSIONS[1] {
                    " or COLOR"
                } else {
                    " (COLOR is KHR_meshopt_compression's)"
                }
            ));
        }
    };
    let compressed = CompressedView {
        view,
        extension: name,
        source_buffer: field("buffer")?,
        source_offset: usize_field(ext, "byteOffset").unwrap_or(0),
        source_length: field("byteLength")?,
        stride: field("byteStride")?,
        count: field("count")?,
        mode,
        filter,
    };
    check_sizes(&compressed)?;
    Ok(compressed)
}

/// The extension's size rules, which are also meshoptimizer's asserts.
fn check_sizes(c: &CompressedView) -> Result<(), String> {
    let stride_ok = match c.mode {
        Mode::Attributes => c.stride.is_multiple_of(4) && (4..=256).contains(&c.stride),
        Mode::Triangles | Mode::Indices => c.stride == 2 || c.stride == 4,
    };
    let filter_ok = match c.filter {
        Filter::None => true,
        _ if c.mode != Mode::Attributes => false,
        Filter::Octahedral => c.stride == 4 || c.stride == 8,
        Filter::Quaternion => c.stride == 8,
        Filter::Exponential => c.stride.is_multiple_of(4),
        Filter::Color => c.stride == 4 || c.stride == 8,
    };
    let count_ok = c.mode != Mode::Triangles || c.count.is_multiple_of(3);
    if !(stride_ok && filter_ok && count_ok) {
        return Err(format!(
            "buffer view {}: {} {:?} with filter {:?}, byteStride {} and count {} breaks \
             the extension's rules (attributes: stride a multiple of 4 up to 256; indices: stride \
             2 or 4; triangles: count a multiple of 3)",
            c.view, c.extension, c.mode, c.filter, c.stride, c.count
        ));
    }
    if c.count.checked_mul(c.stride).is_none_or(|n| n > 1 << 30) {
        return Err(format!(
            "buffer view {}: {} declares {} elements of {} bytes, more than a file can hold",
            c.view, c.extension, c.count, c.stride
        ));
    }
    Ok(())
}

/// Without the `meshopt` feature (a build for a target meshoptimizer's C++ has no compiler
/// for, such as wasm32): a compressed view is refused by name.
#[cfg(not(feature = "meshopt"))]
fn decode(c: &CompressedView, _buffers: &[gltf::buffer::Data]) -> Result<Vec<u8>, String> {
    Err(format!(
        "buffer view {} is {}-compressed, and this build of aograph-scene has no meshopt \
         decoder (enable its `meshopt` feature, or re-save the file uncompressed: `gltfpack -i IN -o OUT` without `-c`)",
        c.view, c.extension
    ))
}

/// Decodes one view's stream: `count * stride` bytes.
#[cfg(feature = "meshopt")]
fn decode(c: &CompressedView, buffers: &[gltf::buffer::Data]) -> Result<Vec<u8>, String> {
    let Some(buffer) = buffers.get(c.source_buffer) else {
        return Err(format!(
            "buffer view {}: {} names buffer {}, but the file has {} buffer(s)",
            c.view,
            c.extension,
            c.source_buffer,
            buffers.len()
        ));
    };
    let source = Some(buffer)
        .and_then(|b| {
            let end = c.source_offset.checked_add(c.source_length)?;
            b.0.get(c.source_offset..end)
        })
        .ok_or_else(|| {
            format!(
                "buffer view {}: {}'s source reaches past the end of buffer {}",
                c.view, c.extension, c.source_buffer
            )
        })?;
    let mut out = vec![0u8; c.count * c.stride];
    // SAFETY: `out` holds exactly `count * stride` bytes, `source` is a live slice of
    // `source.len()` bytes, and `check_sizes` enforced the strides meshoptimizer asserts on;
    // the decoders bound every read by `source.len()` and return non-zero on a bad stream.
    let status = unsafe {
        let (dst, src) = (out.as_mut_ptr().cast(), source.as_ptr());
        match c.mode {
            Mode::Attributes => {
                meshopt::ffi::meshopt_decodeVertexBuffer(dst, c.count, c.stride, src, source.len())
            }
            Mode::Triangles => {
                meshopt::ffi::meshopt_decodeIndexBuffer(dst, c.count, c.stride, src, source.len())
            }
            Mode::Indices => {
                meshopt::ffi::meshopt_decodeIndexSequence(dst, c.count, c.stride, src, source.len())
            }
        }
    };
    if status != 0 {
        return Err(format!(
            "buffer view {}: its {} {:?} stream is malformed (meshoptimizer error {status})",
            c.view, c.extension, c.mode
        ));
    }
    // SAFETY: the filters rewrite `count` elements of `stride` bytes in place, the stride
    // checked against each filter's rule in `check_sizes`.
    unsafe {
        let (buffer, count, stride) = (out.as_mut_ptr().cast(), c.count, c.stride);
        match c.filter {
            Filter::None => {}
            Filter::Octahedral => meshopt::ffi::meshopt_decodeFilterOct(buffer, count, stride),
            Filter::Quaternion => meshopt::ffi::meshopt_decodeFilterQuat(buffer, count, stride),
            Filter::Exponential => meshopt::ffi::meshopt_decodeFilterExp(buffer, count, stride),
            Filter::Color => meshopt::ffi::meshopt_decodeFilterColor(buffer, count, stride),
        }
    }
    Ok(out)
}

#[cfg(all(test, feature = "meshopt"))]
mod tests {
    use super::*;

    fn view(mode: Mode, filter: Filter, stride: usize, count: usize) -> CompressedView {
        CompressedView {
            view: 0,
            extension: EXTENSIONS[0],
            source_buffer: 0,
            source_offset: 0,
            source_length: 0,
            stride,
            count,
            mode,
            filter,
        }
    }

    #[test]
    fn sizes_meshoptimizer_asserts_on_are_refused() {
        assert!(check_sizes(&view(Mode::Attributes, Filter::None, 12, 5)).is_ok());
        assert!(check_sizes(&view(Mode::Attributes, Filter::None, 6, 5)).is_err());
        assert!(check_sizes(&view(Mode::Attributes, Filter::None, 260, 5)).is_err());
        assert!(check_sizes(&view(Mode::Triangles, Filter::None, 2, 6)).is_ok());
        assert!(check_sizes(&view(Mode::Triangles, Filter::None, 2, 7)).is_err());
        assert!(check_sizes(&view(Mode::Indices, Filter::None, 3, 7)).is_err());
        assert!(check_sizes(&view(Mode::Attributes, Filter::Octahedral, 4, 1)).is_ok());
        assert!(check_sizes(&view(Mode::Attributes, Filter::Octahedral, 12, 1)).is_err());
        assert!(check_sizes(&view(Mode::Attributes, Filter::Quaternion, 4, 1)).is_err());
        assert!(check_sizes(&view(Mode::Indices, Filter::Exponential, 4, 1)).is_err());
        assert!(check_sizes(&view(Mode::Attributes, Filter::Color, 8, 1)).is_ok());
        assert!(check_sizes(&view(Mode::Attributes, Filter::Color, 12, 1)).is_err());
    }

    #[test]
    fn an_encoded_vertex_stream_decodes_to_its_bytes() {
        let vertices: Vec<[u16; 2]> = (0..37).map(|i| [i * 3, 1000 - i * 7]).collect();
        let encoded = meshopt::encoding::encode_vertex_buffer(&vertices).expect("encodes");
        let mut c = view(Mode::Attributes, Filter::None, 4, vertices.len());
        c.source_length = encoded.len();
        let decoded = decode(&c, &[gltf::buffer::Data(encoded.clone())]).expect("decodes");
        assert_eq!(decoded, bytemuck::cast_slice::<[u16; 2], u8>(&vertices));
        // A truncated stream is an error, not garbage or a crash.
        c.source_length = encoded.len() / 2;
        let truncated = gltf::buffer::Data(encoded[..encoded.len() / 2].to_vec());
        assert!(decode(&c, &[truncated]).is_err());
    }
}
