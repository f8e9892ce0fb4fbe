//! Storage-precision variants: a shader name may carry a variant suffix, `file.wgsl?Alias=f16`.
//!
//! For a file that declares a storage texture type once, on a line of its own, as written at
//! 32-bit float precision,
//!
//! ```text
//! alias Alias = texture_storage_2d<r32float, write>;
//! ```
//!
//! and uses `Alias` for the globals it writes, `?Alias=f16` rewrites the format on that line
//! only to the 16-bit float format with the same channels (r32float -> r16float, rg32float ->
//! rg16float, rgba32float -> rgba16float); `?Alias=f32` is the file as written. Several pairs
//! join with `&`. [`storage_precision_variant`] builds the name; `ShaderLibrary::variants`
//! lists the variants a file has (the naga test validates each). The graph gives the alias no
//! meaning: a crate above it chooses which alias follows which setting.
//!
//! Include variants: `file.wgsl?KEY=VALUE` for a key some mount defines as an
//! [`IncludeVariant`] is the file with one include swapped for another (aograph's ray tracer:
//! `RayTracer=hardware`). An `enable ...;` directive the swapped file brings is hoisted to the
//! first line ([`hoist_enables`]), since WGSL wants directives first.
//!
//! Invariant: a variant changes nothing in the file but the format on its alias lines (or the
//! one include it swaps), line numbers of the file's own lines included; naming an alias the
//! file does not declare (at a 32-bit float format), or an include variant of a file that
//! does not include the file it swaps, is an error, since the suffix would silently do nothing.

use super::mount::{IncludeVariant, shader_variant};
use crate::error::{GraphError, GraphResult};

/// The name of `file`'s variant whose storage alias `alias` is at 16-bit float precision
/// (`half`) or as written: `file?alias=f16` or `file` itself.
pub fn storage_precision_variant(file: &str, alias: &str, half: bool) -> String {
    if half {
        shader_variant(file, alias, "f16")
    } else {
        file.to_string()
    }
}

/// What a variant suffix asks for.
pub(super) struct Variant<'a> {
    /// Storage aliases to halve.
    pub halved: Vec<&'a str>,
    /// Include variants to apply (their include swapped).
    pub swaps: Vec<IncludeVariant>,
}

/// The file name and the variant, from `file?A=f16&B=f32&Key=value`, where
/// `include_variants` are the include variants the library's mounts define.
pub(super) fn parse_variant<'a>(
    name: &'a str,
    include_variants: &[IncludeVariant],
) -> GraphResult<(&'a str, Variant<'a>)> {
    let mut variant = Variant {
        halved: Vec::new(),
        swaps: Vec::new(),
    };
    let Some((file, suffix)) = name.split_once('?') else {
        return Ok((name, variant));
    };
    for pair in suffix.split('&') {
        let split = pair.split_once('=');
        let rule = split.and_then(|(key, _)| include_variants.iter().find(|v| v.key == key));
        match (split, rule) {
            (Some((_, value)), Some(rule)) if value == rule.swapped => variant.swaps.push(*rule),
            (Some((_, value)), Some(rule)) if value == rule.written => {}
            (Some((alias, "f16")), None) if is_identifier(alias) => variant.halved.push(alias),
            (Some((alias, "f32")), None) if is_identifier(alias) => {}
            _ => {
                let includes: String = include_variants
                    .iter()
                    .map(|v| format!(", or `{0}={1}` / `{0}={2}`", v.key, v.swapped, v.written))
                    .collect();
                return Err(GraphError::ShaderFile {
                    file: name.into(),
                    message: format!(
                        "unknown shader variant `{pair}`; a variant is `Alias=f16` or \
                         `Alias=f32`, naming a storage alias the file declares{includes} \
                         (pairs joined with `&`)"
                    ),
                });
            }
        }
    }
    Ok((file, variant))
}

/// `source` with every `enable ...;` line moved to the front of the first line, the line it
/// stood on left empty: WGSL wants directives before any declaration, and an included file's
/// directive lands mid-module. Line numbers are unchanged.
pub(super) fn hoist_enables(source: String) -> String {
    let is_enable = |l: &str| {
        let t = l.trim();
        t.starts_with("enable ") && t.ends_with(';')
    };
    if !source.lines().skip(1).any(is_enable) {
        return source;
    }
    let mut directives = String::new();
    let mut rest = String::with_capacity(source.len());
    for line in source.split_inclusive('\n') {
        if is_enable(line) {
            let d = line.trim();
            if !directives.contains(d) {
                directives.push_str(d);
                directives.push(' ');
            }
            rest.push_str(if line.ends_with('\n') { "\n" } else { "" });
        } else {
            rest.push_str(line);
        }
    }
    directives + &rest
}

/// `source` (of `file`, loaded as variant `name`) with every alias of `halved` at 16-bit
/// precision; an alias the file does not declare at a 32-bit float format is an error.
pub(super) fn halve_aliases(
    name: &str,
    file: &str,
    mut source: String,
    halved: &[&str],
) -> GraphResult<String> {
    for alias in halved {
        source = half_storage(&source, alias).ok_or_else(|| GraphError::Shader {
            file: file.into(),
            line: 1,
            message: format!(
                "variant `{name}`: the file has no line `alias {alias} = \
                 texture_storage_2d<r32float, write>;` (or rg32float, rgba32float) to rewrite"
            ),
        })?;
    }
    Ok(source)
}

/// The names of the half-precision variants of `file`, whose expanded source is `source`: one
/// per alias it declares at a 32-bit float storage format.
pub(super) fn half_precision_variants(file: &str, source: &str) -> Vec<String> {
    storage_aliases(source)
        .into_iter()
        .filter(|alias| half_storage(source, alias).is_some())
        .map(|alias| storage_precision_variant(file, alias, true))
        .collect()
}

fn is_identifier(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_alphanumeric() || c == '_')
}

/// The alias named on a line `alias NAME = texture_storage_2d<...>;`, if `line` is one.
fn storage_alias(line: &str) -> Option<&str> {
    let rest = line.trim_start().strip_prefix("alias")?;
    if !rest.starts_with(char::is_whitespace) {
        return None;
    }
    let (name, ty) = rest.split_once('=')?;
    ty.trim_start()
        .starts_with("texture_storage_2d<")
        .then_some(name.trim())
}

/// Every storage alias `source` declares.
fn storage_aliases(source: &str) -> Vec<&str> {
    let mut out: Vec<&str> = source.lines().filter_map(storage_alias).collect();
    out.dedup();
    out
}

/// `source` with the format of its `alias ALIAS = texture_storage_2d<F, A>;` line(s) halved
/// (r32float -> r16float etc.); `None` when no such line names a 32-bit float format. Other
/// lines are untouched.
fn half_storage(source: &str, alias: &str) -> Option<String> {
    let mut out = String::with_capacity(source.len());
    let mut found = false;
    for line in source.split_inclusive('\n') {
        match (
            storage_alias(line) == Some(alias),
            line.find("texture_storage_2d<"),
        ) {
            (true, Some(open)) => {
                let start = open + "texture_storage_2d<".len();
                let len = line[start..].find(',')?;
                let format = line[start..start + len].trim();
                let half = match format {
                    "r32float" => "r16float",
                    "rg32float" => "rg16float",
                    "rgba32float" => "rgba16float",
                    _ => return None,
                };
                out.push_str(&line[..start]);
                out.push_str(half);
                out.push_str(&line[start + len..]);
                found = true;
            }
            _ => out.push_str(line),
        }
    }
    found.then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_included_enable_moves_to_the_first_line_and_no_line_number_changes() {
        let source = "// a\nstruct S { x: f32 }\nenable wgpu_ray_query;\nfn f() {}\n".to_string();
        let hoisted = hoist_enables(source.clone());
        assert_eq!(
            hoisted,
            "enable wgpu_ray_query; // a\nstruct S { x: f32 }\n\nfn f() {}\n"
        );
        assert_eq!(hoisted.lines().count(), source.lines().count());
        // Already first: unchanged.
        let first = "enable wgpu_ray_query;\nfn f() {}\n".to_string();
        assert_eq!(hoist_enables(first.clone()), first);
    }

    const TRACE: IncludeVariant = IncludeVariant {
        key: "Tracer",
        written: "soft",
        swapped: "hard",
        include: "t.wgsl",
        replacement: "t_hard.wgsl",
    };

    #[test]
    fn an_include_variant_parses_composes_and_an_unknown_one_is_named() {
        let (file, v) = parse_variant("r.wgsl?Tracer=hard", &[TRACE]).unwrap();
        assert_eq!(file, "r.wgsl");
        assert!(v.swaps == [TRACE] && v.halved.is_empty());
        let (_, v) = parse_variant("a.wgsl?Tracer=soft&Out=f16", &[TRACE]).unwrap();
        assert!(v.swaps.is_empty());
        assert_eq!(v.halved, ["Out"]);
        let e = parse_variant("a.wgsl?Tracer=rtx", &[TRACE])
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("`Tracer=hard` / `Tracer=soft`"), "{e}");
        // Without the mount that defines it, the key is unknown.
        assert!(parse_variant("r.wgsl?Tracer=hard", &[]).is_err());
        assert_eq!(TRACE.of("a.wgsl", true), "a.wgsl?Tracer=hard");
        assert_eq!(TRACE.of("a.wgsl", false), "a.wgsl");
        // Variants compose: a storage-precision variant with the include swapped.
        let both = TRACE.of(&storage_precision_variant("a.wgsl", "S", true), true);
        assert_eq!(both, "a.wgsl?S=f16&Tracer=hard");
        let (file, v) = parse_variant(&both, &[TRACE]).unwrap();
        assert_eq!(
            (file, v.halved, v.swaps),
            ("a.wgsl", vec!["S"], vec![TRACE])
        );
    }
}
