//! aograph's WGSL, compiled in: one table per top-level folder of this crate (`COMMON` for
//! common/, `AO` for ao/, ...), each a list of `(path, source)` with the path relative to the
//! shaders folder (`"ao/gtao/ao.wgsl"`), which is also the name shaders `#include` each other by.
//!
//! The tables are data only. The crate that owns a folder wraps its table in an
//! `aograph_graph::ShaderMount` (README.md lists the owners), and a `ShaderLibrary` is
//! assembled from the mounts an application needs, its own included.
//!
//! Invariant: every `.wgsl` file under a folder is in that folder's table, byte for byte as it
//! was when the crate was built; nothing here reads a file at run time.

#![warn(missing_docs)]

include!(concat!(env!("OUT_DIR"), "/embedded.rs"));

/// The table of top-level folder `name` (`"ao"`, `"common"`, ...), if it has any .wgsl file.
pub fn folder(name: &str) -> Option<&'static [(&'static str, &'static str)]> {
    FOLDERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, files)| *files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Walks the folder on disk (the test runs in the source tree) and compares it with the
    /// tables: the same paths, the same bytes.
    #[test]
    fn every_wgsl_file_on_disk_is_embedded_with_its_text() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut on_disk = Vec::new();
        walk(root, root, &mut on_disk);
        on_disk.sort();
        let mut embedded: Vec<(String, String)> = FOLDERS
            .iter()
            .flat_map(|(_, files)| files.iter())
            .map(|(p, s)| (p.to_string(), s.to_string()))
            .collect();
        embedded.sort();
        assert_eq!(
            on_disk.iter().map(|(p, _)| p).collect::<Vec<_>>(),
            embedded.iter().map(|(p, _)| p).collect::<Vec<_>>()
        );
        assert_eq!(on_disk, embedded);
        assert!(folder("ao").is_some_and(|f| f.iter().any(|(p, _)| *p == "ao/gtao/ao.wgsl")));
        assert!(folder("common").is_some_and(|f| f.iter().all(|(p, _)| p.starts_with("common/"))));
        assert!(folder("src").is_none());
    }

    fn walk(root: &std::path::Path, dir: &std::path::Path, out: &mut Vec<(String, String)>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                if p != root.join("target") {
                    walk(root, &p, out);
                }
            } else if p.extension().is_some_and(|x| x == "wgsl") {
                let rel = p
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.push((rel, std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
}
