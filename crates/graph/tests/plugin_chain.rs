//! Plugins: registry, TOML config chains, typed parameters.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;
use serde::Deserialize;

/// Creates a texture and fills it; output "color".
struct Fill;

impl GraphPlugin for Fill {
    fn name(&self) -> &str {
        "fill"
    }
    fn description(&self) -> &str {
        "fills a texture"
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        Vec::new()
    }
    fn build(
        &self,
        b: &mut GraphBuilder,
        _inputs: &PluginIo,
        _params: &toml::Table,
    ) -> GraphResult<PluginIo> {
        let t = b.create_texture(
            "fill.color",
            TextureDesc::new(TextureFormat::Rgba16Float, SizeClass::FULL),
        );
        let out = b.custom_pass("fill", NoopPass).write_storage("dst", t);
        Ok(PluginIo::default().with("color", out))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BlurParams {
    #[serde(default = "default_radius")]
    radius: u32,
    #[serde(default)]
    half_res: bool,
}

fn default_radius() -> u32 {
    2
}

/// Reads "color", blurs it `radius` times; output "color".
struct Blur;

impl GraphPlugin for Blur {
    fn name(&self) -> &str {
        "blur"
    }
    fn description(&self) -> &str {
        "box blur"
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "radius",
            default: "2".into(),
            allowed: "1 to 8".into(),
            doc: "passes",
        }]
    }
    fn build(
        &self,
        b: &mut GraphBuilder,
        inputs: &PluginIo,
        params: &toml::Table,
    ) -> GraphResult<PluginIo> {
        let p: BlurParams = parse_params("blur", params)?;
        check_range("blur", "radius", p.radius, 1, 8)?;
        let mut cur = inputs.require("blur", "color")?;
        let size = if p.half_res {
            SizeClass::half_pow(1)
        } else {
            SizeClass::FULL
        };
        for i in 0..p.radius {
            let t = b.create_texture(
                &format!("blur.tmp{i}"),
                TextureDesc::new(TextureFormat::Rgba16Float, size),
            );
            let mut pass = b.custom_pass(&format!("blur{i}"), NoopPass);
            pass.sample("src", cur);
            cur = pass.write_storage("dst", t);
        }
        Ok(PluginIo::default().with("color", cur))
    }
}

fn registry() -> PluginRegistry {
    let mut r = PluginRegistry::new();
    r.register(Fill);
    r.register(Blur);
    r
}

#[test]
fn registry_lists_plugins_by_name_sorted() {
    let r = registry();
    assert_eq!(r.names(), vec!["blur", "fill"]);
    assert_eq!(r.get("blur").unwrap().description(), "box blur");
    assert_eq!(r.iter().count(), 2);
    assert_eq!(r.get("blur").unwrap().parameters()[0].name, "radius");
}

#[test]
fn config_chain_builds_exports_and_compiles() {
    let cfg = GraphConfig::from_toml(
        r#"
        [output]
        width = 640
        height = 480

        [[plugin]]
        name = "fill"

        [[plugin]]
        name = "blur"
        params = { radius = 3 }
        "#,
    )
    .unwrap();
    assert_eq!(
        cfg.output,
        OutputConfig {
            width: 640,
            height: 480
        }
    );
    assert_eq!(cfg.plugins.len(), 2);
    let (b, io) = cfg.build(&registry()).unwrap();
    let out = io.get("color").unwrap();
    let decl = b.build();
    assert!(
        decl.resources[out.resource_index()].exported,
        "last plugin's outputs are exported"
    );
    let plan = compile(
        decl,
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .unwrap();
    assert_eq!(plan.pass_names(), vec!["fill", "blur0", "blur1", "blur2"]);
}

#[test]
fn plugin_parameters_default_when_omitted() {
    let cfg = GraphConfig::from_toml("[output]\nwidth = 8\nheight = 8\n[[plugin]]\nname = \"fill\"\n[[plugin]]\nname = \"blur\"\n").unwrap();
    let (b, _) = cfg.build(&registry()).unwrap();
    let plan = compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .unwrap();
    assert_eq!(plan.pass_names(), vec!["fill", "blur0", "blur1"]);
}

#[test]
fn parse_params_reads_typed_values() {
    let t: toml::Table = toml::from_str("radius = 5\nhalf_res = true").unwrap();
    let p: BlurParams = parse_params("blur", &t).unwrap();
    assert_eq!((p.radius, p.half_res), (5, true));
}

#[test]
fn plugin_io_require_lists_what_was_given() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture(
        "t",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let io = PluginIo::default().with("depth", t).with("normal", t);
    assert_eq!(io.get("depth"), Some(t));
    let e = io.require("ssao", "color").unwrap_err();
    assert_eq!(
        e,
        GraphError::Config(
            "plugin `ssao` needs an input texture named `color`; it was given: [depth, normal]"
                .into()
        )
    );
}

#[test]
fn plugin_without_required_input_fails_the_build() {
    let cfg =
        GraphConfig::from_toml("[output]\nwidth = 8\nheight = 8\n[[plugin]]\nname = \"blur\"\n")
            .unwrap();
    let e = cfg.build(&registry()).err().expect("blur needs an input");
    assert!(
        matches!(&e, GraphError::Config(m) if m.contains("`blur`") && m.contains("`color`")),
        "{e:?}"
    );
}

#[test]
fn registering_the_same_name_replaces_the_plugin() {
    let mut r = registry();
    r.register(Blur);
    assert_eq!(r.names(), vec!["blur", "fill"]);
}
