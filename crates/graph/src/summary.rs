//! A human-readable text summary of a compiled plan: the order, each pass's reads and writes
//! with sizes, the culled passes and why, and texture bytes with and without reuse.

use std::fmt::Write;

use crate::compile::CompiledGraph;
use crate::declaration::ResourceOrigin;
use crate::lifetime::texture_bytes;
use crate::resource::Extent;

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// The plan at output size `output`.
pub fn summary(plan: &CompiledGraph, output: Extent) -> String {
    let decl = &plan.decl;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "plan {:016x}: {} passes kept, {} culled, output {output}",
        plan.hash,
        plan.order.len(),
        plan.culled.len()
    );
    for (pos, p) in plan.order.iter().enumerate() {
        let pass = &decl.passes[p.0];
        let _ = writeln!(s, "{pos:>3}. {} [{:?}]", pass.name, pass.kind);
        for u in &pass.textures {
            let res = &decl.resources[u.resource()];
            let desc = res.texture_desc().copied();
            let size = desc
                .map(|d| d.size.resolve(output).mip(u.mip.unwrap_or(0)))
                .map(|e| e.to_string())
                .unwrap_or_default();
            let fmt = desc.map(|d| format!("{:?}", d.format)).unwrap_or_default();
            let dir = if u.written.is_some() {
                "writes"
            } else {
                "reads "
            };
            let mip = u.mip.map(|m| format!(" mip {m}")).unwrap_or_default();
            let slot = plan.slot_of[u.resource()]
                .map(|t| format!(" -> texture {t}"))
                .unwrap_or_else(|| match res.origin {
                    ResourceOrigin::Imported => " (imported)".into(),
                    ResourceOrigin::Transient => String::new(),
                    _ => " (history)".into(),
                });
            let _ = writeln!(
                s,
                "       {dir} {}{mip} {:?} {size} {fmt}{slot}",
                res.name, u.access
            );
        }
        for u in &pass.buffers {
            let Some(h) = u.read.or(u.written) else {
                continue;
            };
            let dir = if u.written.is_some() {
                "writes"
            } else {
                "reads "
            };
            let _ = writeln!(
                s,
                "       {dir} {} {:?}",
                decl.resources[h.id as usize].name, u.access
            );
        }
    }
    if !plan.culled.is_empty() {
        let _ = writeln!(s, "culled:");
        for c in &plan.culled {
            let _ = writeln!(s, "     - {}: {}", decl.passes[c.pass.0].name, c.reason);
        }
    }
    let (with, without) = texture_bytes(plan, output);
    let _ = writeln!(
        s,
        "physical textures: {} for {} transient resources",
        plan.physical.len(),
        plan.physical
            .iter()
            .map(|p| p.resources.len())
            .sum::<usize>()
    );
    let _ = writeln!(
        s,
        "texture bytes: {} with reuse, {} without ({with} / {without} bytes)",
        mib(with),
        mib(without)
    );
    s
}
