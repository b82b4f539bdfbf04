//! `sssbake profile --model stam --plot`: a layer's R(θi) and T(θi) per
//! channel, and its BRDF in the plane of incidence for light arriving at
//! about 45°, drawn as SVG (rasterised to PNG by `plot::render_png`).

use crate::plot::{COLOURS, escape, tick};
use sssbake_profile::stam::StamResponse;
use std::f64::consts::PI;
use std::fmt::Write;

const PANEL_W: f64 = 440.0;
const PANEL_H: f64 = 300.0;
const MARGIN_L: f64 = 70.0;
const MARGIN_T: f64 = 60.0;
const GAP_X: f64 = 90.0;

/// One line of a panel: (x, y) points, its channel and whether dashed.
struct Line {
    points: Vec<(f64, f64)>,
    channel: usize,
    dashed: bool,
}

/// The SVG: left, R (solid) and T (dashed) against the incidence angle;
/// right, the BRDF (1/sr) against the exit angle in the plane of incidence
/// (positive on the specular side) for the ordinate nearest 45°.
pub fn render_svg(title: &str, responses: &[StamResponse; 3]) -> String {
    let first = &responses[0];
    let angle = |cos: f64| cos.clamp(-1.0, 1.0).acos() * 180.0 / PI;
    let mut totals = Vec::new();
    for (c, r) in responses.iter().enumerate() {
        for (values, dashed) in [(&r.reflectance, false), (&r.transmittance, true)] {
            totals.push(Line {
                points: first
                    .cosines
                    .iter()
                    .zip(values)
                    .map(|(&mu, &v)| (angle(mu), v))
                    .collect(),
                channel: c,
                dashed,
            });
        }
    }
    let incidence = (0..first.cosines.len())
        .min_by(|&a, &b| {
            let off = |i: usize| (angle(first.cosines[i]) - 45.0).abs();
            off(a).total_cmp(&off(b))
        })
        .unwrap_or(0);
    let slices: Vec<Line> = responses
        .iter()
        .enumerate()
        .map(|(c, r)| {
            let mut points: Vec<(f64, f64)> = (0..first.cosines.len())
                .flat_map(|o| {
                    let theta = angle(first.cosines[o]);
                    [
                        (theta, r.brdf_at(o, incidence, 0.0)),
                        (-theta, r.brdf_at(o, incidence, PI)),
                    ]
                })
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Line {
                points,
                channel: c,
                dashed: false,
            }
        })
        .collect();
    let width = MARGIN_L + 2.0 * PANEL_W + GAP_X + 30.0;
    let height = MARGIN_T + PANEL_H + 90.0;
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{}" y="28" font-size="18" text-anchor="middle">{}</text>"#,
        width / 2.0,
        escape(title)
    );
    panel(
        &mut svg,
        MARGIN_L,
        "R (solid) and T (dashed) per unit irradiance",
        "θi [°]",
        (0.0, 90.0),
        &totals,
    );
    panel(
        &mut svg,
        MARGIN_L + PANEL_W + GAP_X,
        &format!(
            "BRDF [1/sr] at θi = {:.1}°, plane of incidence",
            angle(first.cosines[incidence])
        ),
        "θo [°] (specular side positive)",
        (-90.0, 90.0),
        &slices,
    );
    let _ = write!(
        svg,
        r#"<text x="{MARGIN_L}" y="{}">colours: red, green, blue channels</text></svg>"#,
        height - 18.0
    );
    svg
}

fn panel(svg: &mut String, x0: f64, label: &str, x_label: &str, x: (f64, f64), lines: &[Line]) {
    let y0 = MARGIN_T;
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
        .max(1e-12)
        * 1.05;
    let px = |v: f64| x0 + (v - x.0) / (x.1 - x.0) * PANEL_W;
    let py = |v: f64| y0 + PANEL_H * (1.0 - (v / top).clamp(0.0, 1.0));
    let _ = write!(
        svg,
        r##"<rect x="{x0}" y="{y0}" width="{PANEL_W}" height="{PANEL_H}" fill="none" stroke="#444"/><text x="{}" y="{}" text-anchor="middle" font-size="13">{}</text><text x="{}" y="{}" text-anchor="middle">{}</text>"##,
        x0 + PANEL_W / 2.0,
        y0 - 8.0,
        escape(label),
        x0 + PANEL_W / 2.0,
        y0 + PANEL_H + 34.0,
        escape(x_label)
    );
    for k in 0..=6 {
        let v = x.0 + (x.1 - x.0) * k as f64 / 6.0;
        let _ = write!(
            svg,
            r##"<line x1="{xx}" y1="{y0}" x2="{xx}" y2="{}" stroke="#ddd"/><text x="{xx}" y="{}" text-anchor="middle">{}</text>"##,
            y0 + PANEL_H,
            y0 + PANEL_H + 16.0,
            tick(v),
            xx = px(v)
        );
    }
    for k in 0..=4 {
        let v = top * k as f64 / 4.0;
        let _ = write!(
            svg,
            r##"<line x1="{x0}" y1="{yy}" x2="{}" y2="{yy}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">{}</text>"##,
            x0 + PANEL_W,
            x0 - 6.0,
            py(v) + 4.0,
            tick(v),
            yy = py(v)
        );
    }
    for line in lines {
        let points: Vec<String> = line
            .points
            .iter()
            .filter(|p| p.1.is_finite())
            .map(|&(a, v)| format!("{:.2},{:.2}", px(a), py(v)))
            .collect();
        let dash = if line.dashed {
            r#" stroke-dasharray="6 4""#
        } else {
            ""
        };
        let _ = write!(
            svg,
            r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.6"{dash}/>"#,
            points.join(" "),
            COLOURS[line.channel % 3]
        );
    }
}
