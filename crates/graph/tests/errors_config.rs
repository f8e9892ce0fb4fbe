//! Errors from plugins and configs: unknown plugin, invalid parameter, invalid config.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;
use serde::Deserialize;

struct Named(&'static str);

impl GraphPlugin for Named {
    fn name(&self) -> &str {
        self.0
    }
    fn description(&self) -> &str {
        "test plugin"
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        Vec::new()
    }
    fn build(
        &self,
        b: &mut GraphBuilder,
        _inputs: &PluginIo,
        params: &toml::Table,
    ) -> GraphResult<PluginIo> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct P {
            #[serde(default)]
            radius: f32,
        }
        let p: P = parse_params(self.0, params)?;
        check_range(self.0, "radius", p.radius, 0.0, 2.0)?;
        let t = b.create_texture(
            self.0,
            TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
        );
        let out = b.custom_pass(self.0, NoopPass).write_storage("dst", t);
        Ok(PluginIo::default().with("ao", out))
    }
}

fn registry() -> PluginRegistry {
    let mut r = PluginRegistry::new();
    r.register(Named("ssao"));
    r.register(Named("hbao"));
    r.register(Named("gtao"));
    r
}

const HEADER: &str = "[output]\nwidth = 64\nheight = 32\n";

#[test]
fn unknown_plugin_lists_the_known_ones() {
    let e = registry().get("ssoa").err().unwrap();
    assert_eq!(
        e,
        GraphError::UnknownPlugin {
            name: "ssoa".into(),
            known: vec!["gtao".into(), "hbao".into(), "ssao".into()]
        }
    );
    assert_eq!(
        e.to_string(),
        "unknown plugin `ssoa`; known plugins: gtao, hbao, ssao"
    );
}

#[test]
fn unknown_plugin_in_a_config_fails_the_build() {
    let cfg = GraphConfig::from_toml(&format!("{HEADER}[[plugin]]\nname = \"vxao\"\n")).unwrap();
    let e = cfg.build(&registry()).err().unwrap();
    assert!(
        matches!(&e, GraphError::UnknownPlugin { name, known } if name == "vxao" && known.len() == 3)
    );
    assert!(e.to_string().contains("gtao, hbao, ssao"));
}

#[test]
fn check_range_reports_name_value_and_allowed_range() {
    assert_eq!(check_range("ssao", "samples", 16, 1, 64), Ok(()));
    assert_eq!(check_range("ssao", "samples", 1, 1, 64), Ok(()));
    assert_eq!(check_range("ssao", "samples", 64, 1, 64), Ok(()));
    let e = check_range("ssao", "radius", 5.5, 0.0, 2.0).unwrap_err();
    assert_eq!(
        e,
        GraphError::InvalidParameter {
            owner: "ssao".into(),
            name: "radius".into(),
            value: "5.5".into(),
            allowed: "0 to 2".into()
        }
    );
    assert_eq!(
        e.to_string(),
        "invalid parameter `radius` = 5.5 for `ssao`: allowed 0 to 2"
    );
    assert!(check_range("ssao", "samples", 0, 1, 64).is_err());
    assert!(
        check_range("ssao", "bias", f32::NAN, 0.0, 1.0).is_err(),
        "NaN is out of every range"
    );
}

#[test]
fn out_of_range_parameter_in_a_config_fails_the_build() {
    let cfg = GraphConfig::from_toml(&format!(
        "{HEADER}[[plugin]]\nname = \"hbao\"\nparams = {{ radius = 3.0 }}\n"
    ))
    .unwrap();
    let e = cfg.build(&registry()).err().unwrap();
    assert!(
        matches!(&e, GraphError::InvalidParameter { owner, name, value, .. } if owner == "hbao" && name == "radius" && value == "3"),
        "{e:?}"
    );
}

#[test]
fn unknown_plugin_parameter_is_a_config_error_naming_plugin_and_key() {
    let cfg = GraphConfig::from_toml(&format!(
        "{HEADER}[[plugin]]\nname = \"gtao\"\nparams = {{ raduis = 1.0 }}\n"
    ))
    .unwrap();
    let e = cfg.build(&registry()).err().unwrap();
    match &e {
        GraphError::Config(m) => assert!(
            m.contains("`gtao`") && m.contains("raduis") && m.contains("radius"),
            "{m}"
        ),
        other => panic!("expected Config, got {other:?}"),
    }
}

#[test]
fn wrongly_typed_plugin_parameter_is_a_config_error() {
    let cfg = GraphConfig::from_toml(&format!(
        "{HEADER}[[plugin]]\nname = \"gtao\"\nparams = {{ radius = \"big\" }}\n"
    ))
    .unwrap();
    assert!(
        matches!(cfg.build(&registry()).err().unwrap(), GraphError::Config(m) if m.contains("`gtao`"))
    );
}

#[test]
fn unknown_key_in_output_section_is_a_config_error() {
    let e = GraphConfig::from_toml(
        "[output]\nwidth = 64\nheight = 32\ndepth = 3\n[[plugin]]\nname = \"ssao\"\n",
    )
    .unwrap_err();
    match &e {
        GraphError::Config(m) => assert!(m.contains("depth"), "{m}"),
        other => panic!("expected Config, got {other:?}"),
    }
}

#[test]
fn unknown_top_level_key_is_a_config_error() {
    let e = GraphConfig::from_toml(&format!(
        "title = \"x\"\n{HEADER}[[plugin]]\nname = \"ssao\"\n"
    ))
    .unwrap_err();
    assert!(
        matches!(&e, GraphError::Config(m) if m.contains("title")),
        "{e:?}"
    );
}

#[test]
fn unknown_key_in_a_plugin_entry_is_a_config_error() {
    let e = GraphConfig::from_toml(&format!(
        "{HEADER}[[plugin]]\nname = \"ssao\"\nparms = {{ radius = 1.0 }}\n"
    ))
    .unwrap_err();
    assert!(
        matches!(&e, GraphError::Config(m) if m.contains("parms")),
        "{e:?}"
    );
}

#[test]
fn zero_output_size_is_rejected_naming_the_output() {
    let e =
        GraphConfig::from_toml("[output]\nwidth = 0\nheight = 32\n[[plugin]]\nname = \"ssao\"\n")
            .unwrap_err();
    assert_eq!(
        e,
        GraphError::InvalidParameter {
            owner: "output".into(),
            name: "width/height".into(),
            value: "0x32".into(),
            allowed: "at least 1 pixel a side".into()
        }
    );
}

#[test]
fn config_without_plugins_is_a_config_error() {
    let e = GraphConfig::from_toml(&format!("plugin = []\n{HEADER}")).unwrap_err();
    assert!(
        matches!(&e, GraphError::Config(m) if m.contains("[[plugin]]")),
        "{e:?}"
    );
}

#[test]
fn missing_output_section_and_bad_toml_are_config_errors_not_panics() {
    assert!(
        matches!(GraphConfig::from_toml("[[plugin]]\nname = \"ssao\"\n"), Err(GraphError::Config(m)) if m.contains("output"))
    );
    assert!(matches!(
        GraphConfig::from_toml("[output\nwidth = "),
        Err(GraphError::Config(_))
    ));
    assert!(matches!(
        GraphConfig::from_toml("[output]\nwidth = -4\nheight = 2\n[[plugin]]\nname = \"ssao\"\n"),
        Err(GraphError::Config(_))
    ));
}
