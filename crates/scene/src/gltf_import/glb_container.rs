//! Splits a `.glb` (glTF 2.0 §4: a 12-byte header, a JSON chunk, an optional BIN chunk) into
//! its JSON and binary parts, leniently where the validator only warns.
//!
//! Lenient: chunks of unknown types are skipped (§4.4.1: "client implementations MUST ignore
//! chunks with unknown types"), and bytes after the last chunk or past the header's declared
//! length are ignored with a warning. Refused, with a message naming the problem: a header that
//! is not "glTF", version 1 (glTF 1.0: convert it), any other version, a first chunk that is not
//! JSON, and a chunk longer than the file.
//! Invariant: every slice returned lies inside the file; nothing is computed with unchecked
//! arithmetic on the file's lengths.

/// The parts of a `.glb`.
pub(super) struct GlbParts<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
    pub warnings: Vec<String>,
}

/// Why a `.glb` cannot be read.
pub(super) enum GlbProblem {
    /// Version 1: a glTF 1.0 binary file.
    Version1,
    /// Anything else, in words.
    Invalid(String),
}

const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits `bytes`, which start with the "glTF" magic.
pub(super) fn split_glb(bytes: &[u8]) -> Result<GlbParts<'_>, GlbProblem> {
    let invalid = |m: String| GlbProblem::Invalid(format!("bad .glb container: {m}"));
    let (Some(version), Some(declared)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(invalid("the 12-byte header is cut short".into()));
    };
    match version {
        2 => {}
        1 => return Err(GlbProblem::Version1),
        v => {
            return Err(invalid(format!(
                "version {v}; glTF 2.0 files have version 2"
            )));
        }
    }
    let mut warnings = Vec::new();
    let declared = declared as usize;
    let end = if declared > bytes.len() {
        return Err(invalid(format!(
            "the header declares {declared} bytes but the file has {}",
            bytes.len()
        )));
    } else {
        if declared < bytes.len() {
            warnings.push(format!(
                "the .glb has {} bytes after the length its header declares: ignored",
                bytes.len() - declared
            ));
        }
        declared
    };
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    while at < end {
        let (Some(length), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            warnings.push(format!(
                "the .glb has {} bytes after its last chunk: ignored",
                end - at
            ));
            break;
        };
        let start = at + 8;
        let chunk_end = start
            .checked_add(length as usize)
            .filter(|&e| e <= end)
            .ok_or_else(|| {
                invalid(format!(
                    "a chunk at byte {at} declares {length} bytes, past the end of the file"
                ))
            })?;
        let chunk = &bytes[start..chunk_end];
        match (kind, json.is_some()) {
            (JSON_CHUNK, false) => json = Some(chunk),
            (_, false) => return Err(invalid("the first chunk is not the JSON chunk".into())),
            (BIN_CHUNK, true) if bin.is_none() => bin = Some(chunk),
            // §4.4.1: unknown chunk types (and repeated ones) are skipped.
            _ => {}
        }
        at = chunk_end;
    }
    let json = json.ok_or_else(|| invalid("it has no JSON chunk".into()))?;
    Ok(GlbParts {
        json,
        bin,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(version: u32, chunks: &[(u32, &[u8])], trailing: &[u8]) -> Vec<u8> {
        let mut body = Vec::new();
        for (kind, data) in chunks {
            body.extend((data.len() as u32).to_le_bytes());
            body.extend(kind.to_le_bytes());
            body.extend(*data);
        }
        let mut out = b"glTF".to_vec();
        out.extend(version.to_le_bytes());
        out.extend((12 + body.len() as u32).to_le_bytes());
        out.extend(body);
        out.extend(trailing);
        out
    }

    #[test]
    fn chunks_are_split_and_unknown_ones_and_trailing_bytes_skipped() {
        let file = glb(
            2,
            &[
                (JSON_CHUNK, b"{}  "),
                (0x1234, b"xxxx"),
                (BIN_CHUNK, b"abcd"),
            ],
            b"zz",
        );
        let parts = split_glb(&file).ok().expect("splits");
        assert_eq!(parts.json, b"{}  ");
        assert_eq!(parts.bin, Some(&b"abcd"[..]));
        assert_eq!(parts.warnings.len(), 1, "{:?}", parts.warnings);
    }

    #[test]
    fn version_1_and_cut_chunks_are_refused() {
        assert!(matches!(
            split_glb(&glb(1, &[], b"")),
            Err(GlbProblem::Version1)
        ));
        let mut file = glb(2, &[(JSON_CHUNK, b"{}  ")], b"");
        file[12] = 200; // the JSON chunk now claims 200 bytes
        assert!(
            matches!(split_glb(&file), Err(GlbProblem::Invalid(m)) if m.contains("past the end"))
        );
        assert!(matches!(
            split_glb(b"glTF\x02\0\0"),
            Err(GlbProblem::Invalid(_))
        ));
    }
}
