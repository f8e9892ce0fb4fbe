//! `#include` expansion: a shader file may start with lines `#include "common/name.wgsl"`;
//! includes (and theirs) are expanded depth first, each file once, before the file's own text.
//!
//! Invariant: a file's own text keeps its line numbers inside its segment of the expanded
//! source (its `#include` lines become blank lines), so [`locate`] maps any line of the
//! expanded source back to the file and line it came from.

use crate::error::{GraphError, GraphResult};

/// A piece of the expanded source: lines `start..` come from `file` starting at its line 1.
pub(super) struct Segment {
    start: u32,
    file: String,
}

impl Segment {
    /// The file this piece of the expansion came from.
    pub(super) fn file(&self) -> &str {
        &self.file
    }
}

/// The expanded source being built, with where each piece came from.
struct Expansion {
    source: String,
    segments: Vec<Segment>,
    line: u32,
    seen: Vec<String>,
}

/// The source of `name` after its includes, and where each piece of it comes from; `read`
/// gives the text of a file by name.
pub(super) fn expand(
    name: &str,
    read: &dyn Fn(&str) -> GraphResult<String>,
) -> GraphResult<(String, Vec<Segment>)> {
    let mut out = Expansion {
        source: String::new(),
        segments: Vec::new(),
        line: 1,
        seen: Vec::new(),
    };
    append(name, read, &mut out)?;
    Ok((out.source, out.segments))
}

/// Appends `name` after its includes (depth first, each file once), keeping the file's own
/// line numbers by blanking its `#include` lines.
fn append(
    name: &str,
    read: &dyn Fn(&str) -> GraphResult<String>,
    out: &mut Expansion,
) -> GraphResult<()> {
    if out.seen.iter().any(|s| s == name) {
        return Ok(());
    }
    out.seen.push(name.to_string());
    let text = read(name)?;
    let mut includes = Vec::new();
    let mut body_start = 0;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("#include") {
            let inc = rest.trim().trim_matches('"').to_string();
            if inc.is_empty() {
                return Err(GraphError::Shader {
                    file: name.into(),
                    line: i as u32 + 1,
                    message: "`#include` needs a file name in quotes".into(),
                });
            }
            includes.push(inc);
            body_start = i + 1;
        } else if !t.is_empty() && !t.starts_with("//") {
            break;
        }
    }
    for inc in &includes {
        append(inc, read, out)?;
    }
    out.segments.push(Segment {
        start: out.line,
        file: name.to_string(),
    });
    for (i, l) in text.lines().enumerate() {
        if i >= body_start {
            out.source.push_str(l);
        }
        out.source.push('\n');
        out.line += 1;
    }
    Ok(())
}

/// Maps a line of the expanded source to (file, line in that file).
pub(super) fn locate(segments: &[Segment], line: u32) -> (String, u32) {
    let seg = segments
        .iter()
        .rev()
        .find(|s| s.start <= line)
        .unwrap_or(&segments[0]);
    (seg.file.clone(), line - seg.start + 1)
}
