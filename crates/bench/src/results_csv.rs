//! results.csv's columns: the header and one line per finished run, every text field quoted
//! by the one rule of [`crate::csv`]. Invariant: [`csv_row`] writes exactly the columns
//! [`CSV_HEADER`] names, in its order.

use crate::csv;
use crate::metrics::nonfinite::format as num;
use crate::run::RunRecord;

/// results.csv's header: one column per value of a [`csv_row`] line. Times are in ms
/// (`total_ms_*`: the technique's passes; `frame_ms_median`: the whole frame), texture sizes in
/// bytes, errors in accessibility units (0..1) except PSNR (dB); `passes` holds
/// `name=median ms` and `roofline` `pass=load fraction/byte fraction`, `;`-separated.
pub const CSV_HEADER: &str = "scene,view,technique,params,width,height,radius,radius_px,reach_px,radius_reached,reference_mean,rays,frames,warmup,timing_source,total_ms_median,total_ms_min,total_ms_max,total_ms_q1,total_ms_q3,frame_ms_median,texture_bytes,texture_bytes_unshared,pixels,mae,rmse,psnr,ssim,signed_error,edge_mae,edge_pixels,flicker,passes,roofline,image,radiance_direct_rmse,radiance_direct_psnr,radiance_full_rmse,radiance_full_psnr,signed_error_left,signed_error_right,ceiling_gbuffer_mae,ceiling_gbuffer_ssim,ceiling_seen_mae,ceiling_seen_ssim,ceiling_guard_mae,ceiling_guard_ssim,ceiling_two_layer_mae,ceiling_two_layer_ssim";

fn opt(v: Option<f64>, d: usize) -> String {
    v.map(|v| num(v, d)).unwrap_or_default()
}

/// The roofline column: `pass=load fraction/byte fraction` per pass (load fraction empty when
/// the pass declares no loads).
fn roofline_field(r: &RunRecord) -> String {
    r.roofline
        .iter()
        .map(|p| {
            format!(
                "{}={}/{}",
                p.pass,
                opt(p.load_fraction, 4),
                num(p.byte_fraction, 4)
            )
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// One CSV line (no newline) for `r`.
pub fn csv_row(r: &RunRecord) -> String {
    let t = &r.times;
    let m = &r.metrics;
    let passes = t
        .passes
        .iter()
        .map(|p| format!("{}={}", p.name, num(p.ms.median, 5)))
        .collect::<Vec<_>>()
        .join(";");
    let f32opt = |v: Option<f32>, d: usize| opt(v.map(f64::from), d);
    [
        csv::field(&r.scene),
        csv::field(&r.view),
        csv::field(&r.technique),
        csv::field(&r.label),
        r.width.to_string(),
        r.height.to_string(),
        r.radius.to_string(),
        f32opt(r.radius_px, 3),
        f32opt(r.reach_px, 3),
        num(f64::from(r.radius_reached()), 4),
        f32opt(r.reference_mean, 5),
        r.rays.to_string(),
        r.frames.to_string(),
        r.warmup.to_string(),
        t.timing_source.clone(),
        num(t.total_ms.median, 5),
        num(t.total_ms.min, 5),
        num(t.total_ms.max, 5),
        num(t.total_ms.q1, 5),
        num(t.total_ms.q3, 5),
        num(t.frame_ms.median, 5),
        r.texture_bytes.to_string(),
        r.texture_bytes_unshared.to_string(),
        m.pixels.to_string(),
        num(m.mae, 6),
        num(m.rmse, 6),
        num(m.psnr, 4),
        num(m.ssim, 6),
        num(m.signed_error, 6),
        opt(m.edge_mae, 6),
        m.edge_pixels.to_string(),
        opt(m.flicker, 6),
        csv::field(&passes),
        csv::field(&roofline_field(r)),
        csv::field(r.image.as_deref().unwrap_or("")),
        opt(r.radiance.map(|x| x.direct_rmse), 6),
        opt(r.radiance.map(|x| x.direct_psnr), 3),
        opt(r.radiance.map(|x| x.full_rmse), 6),
        opt(r.radiance.map(|x| x.full_psnr), 3),
        opt(m.signed_error_left, 6),
        opt(m.signed_error_right, 6),
        opt(r.ceilings.map(|c| c.gbuffer_mae), 6),
        opt(r.ceilings.map(|c| c.gbuffer_ssim), 6),
        opt(r.ceilings.map(|c| c.seen_mae), 6),
        opt(r.ceilings.map(|c| c.seen_ssim), 6),
        opt(r.ceilings.map(|c| c.guard_mae), 6),
        opt(r.ceilings.map(|c| c.guard_ssim), 6),
        opt(r.ceilings.map(|c| c.two_layer_mae), 6),
        opt(r.ceilings.map(|c| c.two_layer_ssim), 6),
    ]
    .join(",")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::tests::record;

    #[test]
    fn a_scene_view_or_label_with_commas_and_quotes_keeps_every_column() {
        let mut r = record(
            "scenes/hall, east.gltf",
            "hbao",
            "say \"hi\", twice",
            10.0,
            0.05,
        );
        r.view = "Camera \"A\"".into();
        let fields = csv::split_row(&csv_row(&r));
        assert_eq!(fields.len(), CSV_HEADER.split(',').count());
        assert_eq!(
            fields[..4],
            [
                "scenes/hall, east.gltf",
                "Camera \"A\"",
                "hbao",
                "say \"hi\", twice"
            ]
        );
    }
}
