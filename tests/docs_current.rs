//! The text of README.md and docs/ that a tool owns is what the tool makes from the committed
//! inputs (`aograph docs --check`): every technique's settings table from its parameter
//! descriptors, every results table from the bench output committed under docs/results/.
//! A number typed by hand into a generated region, or a results file changed without
//! regenerating, fails here. And no committed results file names a path of the machine that
//! made it.

use std::path::Path;

#[test]
fn generated_text_in_readme_and_docs_is_current() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if let Err(e) = aograph::commands::docs::regenerate_all(root, true) {
        panic!("{e}");
    }
}

#[test]
fn committed_results_name_no_path_of_the_machine_that_made_them() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/results");
    let mut checked = 0;
    for study in std::fs::read_dir(&root).unwrap().flatten() {
        for file in std::fs::read_dir(study.path())
            .into_iter()
            .flatten()
            .flatten()
        {
            let text = std::fs::read_to_string(file.path()).unwrap_or_default();
            for bad in ["\"/", " /home/", " /tmp/", " /work/", ":\\\\", "/Users/"] {
                assert!(
                    !text.contains(bad),
                    "{} holds an absolute path ({bad:?})",
                    file.path().display()
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 0, "no committed results under docs/results/*/");
}
