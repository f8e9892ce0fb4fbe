//! The contract every registered technique keeps, the user's own included, checked without a
//! GPU from its parameter descriptions alone: unknown keys are refused with the nearest key
//! suggested; every key of `Params` is described and every description names a key; each
//! default passes its own description; each range's ends pass and a value just past either end
//! is refused with a message naming the key and the range; every choice and flag value is
//! accepted; and the plan compiles against the real WGSL with the defaults and with every
//! choice and flag value. Also the one harness that compiles a technique's plan
//! ([`compile_plan`]), which technique tests use for their pass lists.
//!
//! Invariant: [`check_contract`] needs nothing but the technique and a shader library, so a
//! user technique gets it with one call.

use std::sync::Arc;

use aograph_frame::{DeclaredInputs, GBufferTextures, ViewBlock};
use aograph_graph::{
    CompileOptions, CompiledGraph, GraphBuilder, GraphDecl, ShaderLibrary, SizeClass, TextureDesc,
    compile,
};

use crate::error::{AoError, AoResult};
use crate::param::{ParamDesc, ParamKind};
use crate::technique::{AoBuildContext, ConfiguredTechnique, DynAoTechnique};

/// The compiled plan of `technique` over an imported g-buffer holding the channels it asks
/// for, with R = 1 and no known view (automatic level counts take the paper's default).
pub fn compile_plan(
    technique: &dyn ConfiguredTechnique,
    shaders: &ShaderLibrary,
    intermediate_format: wgpu::TextureFormat,
) -> AoResult<CompiledGraph> {
    let (decl, _) = declare_plan(technique, intermediate_format)?;
    Ok(compile(decl, shaders, CompileOptions::default())?)
}

/// The frame inputs `technique` declares (the scene's BVH or acceleration structures of a
/// technique that traces rays), from its plan as [`compile_plan`] declares it: nothing is
/// compiled and no device is needed.
pub fn declared_inputs(technique: &dyn ConfiguredTechnique) -> AoResult<DeclaredInputs> {
    Ok(declare_plan(technique, wgpu::TextureFormat::R32Float)?.1)
}

/// The declaration behind [`compile_plan`] and what the build declared as frame inputs.
fn declare_plan(
    technique: &dyn ConfiguredTechnique,
    intermediate_format: wgpu::TextureFormat,
) -> AoResult<(GraphDecl, DeclaredInputs)> {
    let mut b = GraphBuilder::new();
    let mut declared = DeclaredInputs::default();
    let view = declared.declare::<ViewBlock>(&mut b);
    let mut gbuffer = GBufferTextures::default();
    for c in technique.channels().iter() {
        let name = format!("gbuffer.{}", c.name());
        gbuffer.set(
            c,
            b.import_texture(&name, TextureDesc::new(c.format(), SizeClass::FULL)),
        );
    }
    let mut ctx = AoBuildContext {
        builder: &mut b,
        gbuffer,
        view,
        radius: 1.0,
        intermediate_format,
        technique: technique.name(),
        radius_pixels: None,
        declared,
        // As for a device with ray queries, so a hardware tracer's plan builds (and its
        // shader variant compiles) here too; compile touches no device.
        tracing: crate::TracingSupport {
            ray_queries: true,
            adapter: "the contract check (no device)".into(),
        },
    };
    let out = technique.build(&mut ctx)?;
    let declared = ctx.declared;
    b.export(out.accessibility);
    for (_, h) in &out.extra {
        b.export(*h);
    }
    Ok((b.build(), declared))
}

/// The pass names of [`compile_plan`] for `params` (a TOML table's text), at R32Float.
pub fn plan_pass_names(
    technique: &Arc<dyn DynAoTechnique>,
    params: &str,
    shaders: &ShaderLibrary,
) -> AoResult<Vec<String>> {
    let table: toml::Table = params
        .parse()
        .map_err(|e| AoError::Config(format!("parameters `{params}`: {e}")))?;
    let configured = technique.clone().configure(&table)?;
    let plan = compile_plan(configured.as_ref(), shaders, wgpu::TextureFormat::R32Float)?;
    Ok(plan.pass_names().into_iter().map(String::from).collect())
}

fn one(key: &str, value: toml::Value) -> toml::Table {
    let mut t = toml::Table::new();
    t.insert(key.to_string(), value);
    t
}

/// A value just past `bound`, away from the range (below the minimum or above the maximum).
fn past(bound: f64, below: bool, integer: bool) -> toml::Value {
    let step = if integer {
        1.0
    } else {
        (bound.abs() * 1e-3).max(1e-6)
    };
    let v = if below { bound - step } else { bound + step };
    if integer {
        toml::Value::Integer(v as i64)
    } else {
        toml::Value::Float(v)
    }
}

fn number(v: f64, integer: bool) -> toml::Value {
    if integer {
        toml::Value::Integer(v as i64)
    } else {
        toml::Value::Float(v)
    }
}

/// Every value of `d` the contract tries that must be accepted (alone, with the other
/// defaults), and every value that must be refused.
fn probes(d: &ParamDesc) -> (Vec<toml::Value>, Vec<toml::Value>) {
    match &d.kind {
        ParamKind::Range {
            min,
            max,
            integer,
            odd,
            above_min,
        } => {
            let mut ok = vec![number(*max, *integer)];
            let mut bad = vec![past(*max, false, *integer)];
            if *above_min {
                bad.push(number(*min, *integer));
                ok.push(past(*min, false, *integer));
            } else {
                ok.push(number(*min, *integer));
                bad.push(past(*min, true, *integer));
            }
            if *odd {
                bad.push(number(*min + 1.0, true));
            }
            if *integer {
                bad.push(toml::Value::Float(*min + 0.5));
            }
            bad.push(toml::Value::String("x".into()));
            (ok, bad)
        }
        ParamKind::Choice(options) => (
            options
                .iter()
                .map(|o| toml::Value::String(o.to_string()))
                .collect(),
            vec![toml::Value::String("not-an-option".into())],
        ),
        ParamKind::Bool => (
            vec![toml::Value::Boolean(true), toml::Value::Boolean(false)],
            vec![toml::Value::Integer(1)],
        ),
        ParamKind::WordOrNumber { word, min, max } => (
            vec![
                toml::Value::String(word.to_string()),
                number(*min, true),
                number(*max, true),
            ],
            vec![
                number(*min - 1.0, true),
                number(*max + 1.0, true),
                toml::Value::String(format!("{word}x")),
            ],
        ),
    }
}

/// Checks the module's contract for `technique`; returns every breach found, empty when it
/// keeps it. Values at a range's end may still be refused by a rule across parameters
/// ([`AoError::ParameterRule`]), never by the range itself.
pub fn check_contract(technique: &Arc<dyn DynAoTechnique>, shaders: &ShaderLibrary) -> Vec<String> {
    let name = technique.name();
    let mut breaches = Vec::new();
    let descs = technique.parameters();
    let defaults = technique.default_params();

    // Every key described, every description a key, defaults inside their descriptions.
    for key in defaults.keys() {
        if !descs.iter().any(|d| d.name == key) {
            breaches.push(format!("{name}: parameter `{key}` has no description"));
        }
    }
    for d in &descs {
        match (&d.default, d.unset) {
            (Some(v), _) => {
                if let Err(allowed) = d.check(v) {
                    breaches.push(format!(
                        "{name}.{}: default {v} is outside its description ({allowed})",
                        d.name
                    ));
                }
            }
            (None, None) => breaches.push(format!(
                "{name}.{}: described, but `Params` has no such key (or no default; mark an \
                 override `.unset(..)`)",
                d.name
            )),
            (None, Some(_)) => {}
        }
        if d.doc.is_empty() {
            breaches.push(format!(
                "{name}.{}: no line of meaning (`.doc(..)`)",
                d.name
            ));
        }
    }

    // Unknown keys, with the nearest suggested.
    let (typo, want) = match descs.first() {
        Some(d) => (format!("{}x", d.name), d.name),
        None => ("unknown_key".to_string(), "unknown_key"),
    };
    match technique.check(&one(&typo, toml::Value::Integer(1))) {
        Ok(()) => breaches.push(format!("{name}: unknown key `{typo}` accepted")),
        Err(e) if !e.to_string().contains(want) => breaches.push(format!(
            "{name}: unknown key `{typo}`: the message does not name `{want}`: {e}"
        )),
        Err(_) => {}
    }

    // Each description's ends and the values just past them.
    for d in &descs {
        let (ok, bad) = probes(d);
        for v in ok {
            match technique.check(&one(d.name, v.clone())) {
                Ok(()) | Err(AoError::ParameterRule { .. }) => {}
                Err(e) => breaches.push(format!("{name}.{} = {v} refused: {e}", d.name)),
            }
        }
        for v in bad {
            match technique.check(&one(d.name, v.clone())) {
                Ok(()) => breaches.push(format!("{name}.{} = {v} accepted", d.name)),
                Err(e) => {
                    let msg = e.to_string();
                    if !(msg.contains(d.name) && msg.contains(&d.allowed())) {
                        breaches.push(format!(
                            "{name}.{} = {v}: the message does not name the key and `{}`: {msg}",
                            d.name,
                            d.allowed()
                        ));
                    }
                }
            }
        }
    }

    // The plan compiles with the defaults and with every choice and flag value.
    let mut tables = vec![toml::Table::new()];
    for d in &descs {
        if matches!(d.kind, ParamKind::Choice(_) | ParamKind::Bool) {
            tables.extend(probes(d).0.into_iter().map(|v| one(d.name, v)));
        }
    }
    for table in tables {
        let built = technique.clone().configure(&table).and_then(|c| {
            compile_plan(c.as_ref(), shaders, wgpu::TextureFormat::R16Float).map(|_| ())
        });
        if let Err(e) = built {
            breaches.push(format!(
                "{name} with {table:?}: the plan does not build: {e}"
            ));
        }
    }
    breaches
}
