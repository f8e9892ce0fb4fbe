//! `aograph techniques --webgpu-limits` without a browser: which built-in techniques' plans, in
//! aograph's own frame, fit a device with WebGPU's default limits and core storage formats
//! (r32float intermediates), and what the others are refused for, by pass and limit: ssdo's
//! and rtao's g-buffer raster writes more colour bytes per sample than the default 32, and
//! r16float intermediates are not core WebGPU. A technique that grows past a limit shows here.

use aograph_ao_passes::TechniqueRegistry;

#[test]
fn which_builtin_techniques_fit_webgpu_defaults_and_why_the_others_do_not() {
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
            "ssao",
            "tssao",
            "vbao"
        ]
    );
    let refused: Vec<&String> = lines.iter().filter(|l| !l.ends_with(": fits")).collect();
    // The g-buffer's targets, by WebGPU's rule: ssdo's normals, positions, albedo and direct
    // light are 40 bytes, rtao's channels 44.
    let expected = [
        "rtao: refused: pass `gbuffer` needs 44 bytes per sample across its colour attachments, \
         and a WebGPU device with default limits allows 32",
        "ssdo: refused: pass `gbuffer` needs 40 bytes per sample across its colour attachments, \
         and a WebGPU device with default limits allows 32",
        "gtao (intermediate_format = \"r16float\"): refused: pass `gtao.ao` needs R16Float \
         storage textures with WriteOnly access",
        "rtao ([rtao] tracer = \"hardware\"): refused: pass `gbuffer` needs 44 bytes",
    ];
    assert_eq!(refused.len(), expected.len(), "{refused:#?}");
    for (line, start) in refused.iter().zip(expected) {
        assert!(
            line.starts_with(start),
            "{line}\nshould start with\n{start}"
        );
    }
}
