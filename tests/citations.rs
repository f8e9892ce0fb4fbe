//! Citations that stay true: every path into this repository that a comment, a doc page or a
//! manifest cites (`crates/scene/src/views.rs`, `shaders/ao/gtao/ao.wgsl`, `docs/guide/viewer.md`,
//! a Markdown link) names a file or folder that exists. Files move; a stale citation sends the
//! reader nowhere, so it fails here, naming the file and line that cites it.
//!
//! What counts as a citation: in the prose of a file (comments in code, shaders, manifests and
//! scripts; all of a Markdown page), a token that starts at a word boundary with one of the
//! repository's top-level folders (`crates/`, `src/`, `tests/`, `shaders/`, `docs/`,
//! `scripts/`, `benches/`, `examples/`, `configs/`, `.ci/`) and ends in a file extension, or
//! a relative Markdown link target. It resolves against the repository's root, the citing
//! file's crate (a crate-relative `src/lib.rs`), or the citing file's folder (Markdown links).
//! Paths into other projects that happen to share a prefix (`src/` of bevy or NRD) are listed
//! in [`OTHER_PROJECTS`], each with the project it belongs to.

use std::path::{Path, PathBuf};

/// Top-level folders of this repository a citation starts with.
const ROOTS: &[&str] = &[
    "crates/",
    "src/",
    "tests/",
    "shaders/",
    "docs/",
    "scripts/",
    "benches/",
    "examples/",
    "configs/",
    ".ci/",
];

/// Extensions a cited file has (a folder citation ends in `/` and is checked as a folder).
const EXTENSIONS: &[&str] = &[
    "rs", "wgsl", "md", "toml", "sh", "png", "svg", "json", "csv", "glb", "gltf", "bin", "txt",
];

/// Cited paths that are other projects' files, not ours: (path, whose).
const OTHER_PROJECTS: &[(&str, &str)] = &[
    ("src/ssao/mod.rs", "bevy_pbr"),
    ("src/render/mesh_view_bindings.rs", "bevy_pbr"),
];

/// The files whose citations are checked: sources, shaders, docs, manifests, scripts.
fn cited_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            // Build output, version control, vendored scenes and their licences are not ours
            // to cite from.
            if !matches!(
                name.as_str(),
                "target" | ".git" | "shared" | "scenes" | "node_modules"
            ) {
                cited_files(&path, out);
            }
        } else if ["rs", "wgsl", "md", "toml", "sh"]
            .iter()
            .any(|e| name.ends_with(&format!(".{e}")))
            || name == "run"
        {
            out.push(path);
        }
    }
}

/// A character that can be part of a path.
fn path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/')
}

/// The part of `line` that is prose in a file named `name`: comments in code and manifests
/// (after `//`, or `#` in TOML and shell; a string literal holds names, such as shader
/// library names, not citations), the whole line in Markdown.
fn prose<'a>(name: &str, line: &'a str) -> &'a str {
    let marker = if name.ends_with(".rs") || name.ends_with(".wgsl") {
        "//"
    } else if name.ends_with(".md") {
        return line;
    } else {
        "#"
    };
    line.find(marker).map_or("", |at| &line[at..])
}

/// Every repository path cited in the prose of `text` (by prefix, see the module docs), with
/// its line; `name` is the file's name.
fn prefixed_citations(name: &str, text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = prose(name, line);
        for (at, _) in line.char_indices() {
            let before = line[..at].chars().next_back();
            if before.is_some_and(|c| path_char(c) || c == ':' || c == '$') {
                continue;
            }
            let rest = &line[at..];
            if !ROOTS.iter().any(|r| rest.starts_with(r)) {
                continue;
            }
            let token: String = rest.chars().take_while(|&c| path_char(c)).collect();
            let token = token.trim_end_matches(['.', '-']);
            let is_file = EXTENSIONS.iter().any(|e| token.ends_with(&format!(".{e}")));
            // `tests/scenes/` and other folder citations end in a slash.
            let is_folder = token.ends_with('/') && token.len() > 4;
            if is_file || is_folder {
                out.push((n + 1, token.to_owned()));
            }
        }
    }
    out
}

/// Relative Markdown link targets `](target)` in `text` (no scheme, no pure anchor), with
/// their line; the anchor part is dropped.
fn markdown_links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(open) = rest.find("](") {
            rest = &rest[open + 2..];
            let Some(close) = rest.find(')') else {
                break;
            };
            let target = rest[..close].split('#').next().unwrap_or("").trim();
            let external = target.contains("://") || target.starts_with("mailto:");
            if !target.is_empty() && !external && !target.contains(' ') {
                out.push((n + 1, target.to_owned()));
            }
            rest = &rest[close..];
        }
    }
    out
}

/// The folder of the nearest `Cargo.toml` at or above `file`'s folder, below `root`.
fn crate_of(root: &Path, file: &Path) -> PathBuf {
    let mut dir = file.parent().unwrap_or(root);
    while dir.starts_with(root) {
        if dir.join("Cargo.toml").exists() {
            return dir.to_owned();
        }
        dir = dir.parent().unwrap_or(root);
    }
    root.to_owned()
}

/// The citations in the repository that name nothing, as "file:line: path".
fn stale_citations(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    cited_files(root, &mut files);
    files.sort();
    let mut stale = Vec::new();
    for file in &files {
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        let here = file.parent().unwrap_or(root);
        let krate = crate_of(root, file);
        let shown = file
            .strip_prefix(root)
            .unwrap_or(file)
            .display()
            .to_string();
        let mut check = |line: usize, cited: &str, bases: &[&Path]| {
            let other = OTHER_PROJECTS.iter().any(|(p, _)| cited.ends_with(p));
            if !other && !bases.iter().any(|base| base.join(cited).exists()) {
                stale.push(format!("{shown}:{line}: {cited}"));
            }
        };
        for (line, cited) in prefixed_citations(&shown, &text) {
            check(line, &cited, &[root, &krate, here]);
        }
        if shown.ends_with(".md") {
            for (line, cited) in markdown_links(&text) {
                check(line, &cited, &[here]);
            }
        }
    }
    stale
}

#[test]
fn every_path_the_repository_cites_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let stale = stale_citations(root);
    assert!(
        stale.is_empty(),
        "{} citation(s) name no file of the repository (moved or deleted? fix the citation, or \
         list a path of another project in OTHER_PROJECTS):\n{}",
        stale.len(),
        stale.join("\n")
    );
}

#[test]
fn citations_are_found_where_they_start_and_not_inside_other_paths() {
    let text = "see crates/scene/src/views.rs and `shaders/ao/gtao.wgsl`, not bevy_pbr/src/ssao/mod.rs\n\
                nor https://x.org/src/a.rs; the folder tests/scenes/ too. A sentence ends in src/lib.rs.";
    let found: Vec<String> = prefixed_citations("notes.md", text)
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    assert_eq!(
        found,
        [
            "crates/scene/src/views.rs",
            "shaders/ao/gtao.wgsl",
            "tests/scenes/",
            "src/lib.rs"
        ]
    );
    let links =
        markdown_links("[a](docs/x.md#part) [b](https://e.org/y.md) [c](#anchor) [d](../e.png)");
    let targets: Vec<&str> = links.iter().map(|(_, t)| t.as_str()).collect();
    assert_eq!(targets, ["docs/x.md", "../e.png"]);
}
