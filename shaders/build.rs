//! Writes `$OUT_DIR/embedded.rs`: for each top-level folder beside this file, a table
//! `pub static FOLDER: &[(&str, &str)]` of every `.wgsl` file under it (path relative to this
//! folder, with `/`; the text through `include_str!`), sorted by path.
//!
//! Invariant: every .wgsl file under a top-level folder is in exactly one table, the folder's,
//! and cargo reruns this script when any file or folder under them changes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut folders: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("the crate folder is readable")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir() && !p.ends_with("src") && !p.ends_with("target"))
        .collect();
    folders.sort();
    // A new top-level folder (a new table) changes the crate folder itself.
    println!("cargo:rerun-if-changed={}", root.display());
    let mut out = String::new();
    let mut names = Vec::new();
    for folder in &folders {
        println!("cargo:rerun-if-changed={}", folder.display());
        let mut files = Vec::new();
        collect_wgsl(folder, &mut files);
        if files.is_empty() {
            continue;
        }
        files.sort();
        let folder_name = folder
            .file_name()
            .and_then(|n| n.to_str())
            .expect("utf-8 folder name");
        let ident = folder_name.to_uppercase().replace(['-', '.'], "_");
        writeln!(
            out,
            "/// Every .wgsl file under `{folder_name}/`: (path, source)."
        )
        .unwrap();
        writeln!(out, "pub static {ident}: &[(&str, &str)] = &[").unwrap();
        for file in &files {
            let rel = file
                .strip_prefix(&root)
                .expect("under the crate folder")
                .to_str()
                .expect("utf-8 shader path")
                .replace('\\', "/");
            writeln!(
                out,
                "    ({rel:?}, include_str!({:?})),",
                file.display().to_string()
            )
            .unwrap();
        }
        writeln!(out, "];").unwrap();
        names.push((folder_name.to_string(), ident));
    }
    writeln!(out, "/// Every folder's table, by folder name.").unwrap();
    writeln!(out, "pub static FOLDERS: &[(&str, &[(&str, &str)])] = &[").unwrap();
    for (name, ident) in &names {
        writeln!(out, "    ({name:?}, {ident}),").unwrap();
    }
    writeln!(out, "];").unwrap();
    let dest = PathBuf::from(std::env::var("OUT_DIR").expect("set by cargo")).join("embedded.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}

fn collect_wgsl(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            println!("cargo:rerun-if-changed={}", p.display());
            collect_wgsl(&p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            println!("cargo:rerun-if-changed={}", p.display());
            out.push(p);
        }
    }
}
