//! `sssbake profile --model stam --plot`: a layer's R(θi) and T(θi) per
//! channel, and its BRDF in the plane of incidence for light arriving at
//! about 45° (or, for a stack's Stam top layer, its totals in contact with
//! the layer beneath), drawn as SVG (rasterised to PNG by
//! `plot::render_png`).

use crate::plot::{COLOURS, escape, tick};
use sssbake_profile::models::stam::StamResponse;
use sssbake_profile::models::stam::epidermis::Epidermis;
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

/// A layer's R (solid) and T (dashed) per channel against the incidence
/// angle in degrees: `totals[c]` is (cosines, R, T) of channel `c`.
fn total_lines(totals: [(&[f64], &[f64], &[f64]); 3]) -> Vec<Line> {
    let mut lines = Vec::new();
    for (c, (cosines, reflectance, transmittance)) in totals.into_iter().enumerate() {
        for (values, dashed) in [(reflectance, false), (transmittance, true)] {
            lines.push(Line {
                points: cosines
                    .iter()
                    .zip(values)
                    .map(|(&mu, &v)| (degrees(mu), v))
                    .collect(),
                channel: c,
                dashed,
            });
        }
    }
    lines
}

/// The angle in degrees of the cosine `cos`.
pub fn degrees(cos: f64) -> f64 {
    cos.clamp(-1.0, 1.0).acos() * 180.0 / PI
}

/// The SVG: left, R (solid) and T (dashed) against the incidence angle;
/// right, the BRDF (1/sr) against the exit angle in the plane of incidence
/// (positive on the specular side) for the ordinate nearest 45°.
pub fn render_svg(title: &str, responses: &[StamResponse; 3]) -> String {
    let first = &responses[0];
    let totals = total_lines(std::array::from_fn(|c| {
        let r = &responses[c];
        (&r.cosines[..], &r.reflectance[..], &r.transmittance[..])
    }));
    let incidence = (0..first.cosines.len())
        .min_by(|&a, &b| {
            let off = |i: usize| (degrees(first.cosines[i]) - 45.0).abs();
            off(a).total_cmp(&off(b))
        })
        .unwrap_or(0);
    let slices: Vec<Line> = responses
        .iter()
        .enumerate()
        .map(|(c, r)| {
            let mut points: Vec<(f64, f64)> = (0..first.cosines.len())
                .flat_map(|o| {
                    let theta = degrees(first.cosines[o]);
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
    let slice_label = format!(
        "BRDF [1/sr] at θi = {:.1}°, plane of incidence",
        degrees(first.cosines[incidence])
    );
    figure(
        title,
        &[
            Panel {
                label: "R (solid) and T (dashed) per unit irradiance",
                x_label: "θi [°]",
                x: (0.0, 90.0),
                lines: totals,
            },
            Panel {
                label: &slice_label,
                x_label: "θo [°] (specular side positive)",
                x: (-90.0, 90.0),
                lines: slices,
            },
        ],
    )
}

/// The SVG of a stack's Stam top layer in contact with the layer beneath:
/// R back to air (solid) and T into the layer beneath (dashed) against the
/// incidence angle.
pub fn render_contact_svg(title: &str, epidermis: &Epidermis) -> String {
    let totals = total_lines(std::array::from_fn(|c| {
        let t = epidermis.channel(c);
        (&t.cosines[..], &t.reflectance[..], &t.transmittance[..])
    }));
    figure(
        title,
        &[Panel {
            label: "R to air (solid), T into the layer beneath (dashed)",
            x_label: "θi [°]",
            x: (0.0, 90.0),
            lines: totals,
        }],
    )
}

/// One panel of a figure: its title, x axis and lines.
struct Panel<'a> {
    label: &'a str,
    x_label: &'a str,
    x: (f64, f64),
    lines: Vec<Line>,
}

/// `panels` side by side under `title`, with the channels' colour key.
fn figure(title: &str, panels: &[Panel]) -> String {
    let count = panels.len() as f64;
    let width = MARGIN_L + count * PANEL_W + (count - 1.0) * GAP_X + 30.0;
    let height = MARGIN_T + PANEL_H + 90.0;
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{}" y="28" font-size="18" text-anchor="middle">{}</text>"#,
        width / 2.0,
        escape(title)
    );
    for (i, p) in panels.iter().enumerate() {
        let x0 = MARGIN_L + i as f64 * (PANEL_W + GAP_X);
        panel(&mut svg, x0, p.label, p.x_label, p.x, &p.lines);
    }
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
