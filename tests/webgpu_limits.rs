//! `aograph techniques --webgpu-limits` without a browser: every built-in technique's plan, in
//! aograph's own frame, fits a device with WebGPU's default limits and core storage formats
//! (r32float intermediates); r16float intermediates and the hardware ray tracer are refused,
//! naming the pass and what it lacks. A technique that grows past a default limit shows here.

use aograph_ao_passes::TechniqueRegistry;

#[test]
fn every_builtin_technique_fits_webgpu_defaults_and_the_two_variants_that_need_more_are_named() {
    let registry = TechniqueRegistry::with_builtins();
    let lines = aograph::commands::webgpu_fit_lines(&registry).unwrap();
    let fitting: Vec<&str> = lines
        .iter()
        .filter_map(|l| l.strip_suffix(": fits"))
        .collect();
    assert_eq!(
        fitting,
        [
            "gtao",
            "hbao",
            "mssao",
            "none",
            "pyramid-hbao",
            "rtao",
            "ssao",
            "ssdo",
            "tssao",
            "vbao"
        ]
    );
    let refused: Vec<&String> = lines.iter().filter(|l| !l.ends_with(": fits")).collect();
    assert_eq!(refused.len(), 2, "{refused:#?}");
    assert!(
        refused[0].starts_with("gtao (intermediate_format = \"r16float\"): refused: pass `gtao.ao` needs R16Float storage textures with WriteOnly access"),
        "{}",
        refused[0]
    );
    assert!(
        refused[1].starts_with(
            "rtao ([rtao] tracer = \"hardware\"): refused: pass `rtao.trace` needs ray queries"
        ),
        "{}",
        refused[1]
    );
}
