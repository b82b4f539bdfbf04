//! R(r) and r·R(r) per channel on logarithmic and linear axes, as in
//! Mikkelsen's figures 6–7, drawn as SVG (and rasterised to PNG).

use std::fmt::Write;

/// One channel's samples of one profile.
pub struct Curve {
    /// 0 red, 1 green, 2 blue.
    pub channel: usize,
    /// Legend text.
    pub label: String,
    /// (r in mm, R in 1/mm²).
    pub points: Vec<(f64, f64)>,
    /// Standard errors of R, drawn as bars.
    pub errors: Option<Vec<f64>>,
    /// Draw dots instead of a line.
    pub markers: bool,
}

pub(crate) const COLOURS: [&str; 3] = ["#c62828", "#2e7d32", "#1565c0"];
const PANEL_W: f64 = 460.0;
const PANEL_H: f64 = 300.0;
const MARGIN_L: f64 = 70.0;
const MARGIN_T: f64 = 60.0;
const GAP_X: f64 = 90.0;
const GAP_Y: f64 = 80.0;

/// An SVG document with four panels: R and r·R, each on log and linear y.
pub fn render_svg(title: &str, curves: &[Curve]) -> String {
    let width = MARGIN_L + 2.0 * PANEL_W + GAP_X + 30.0;
    let height = MARGIN_T + 2.0 * PANEL_H + GAP_Y + 70.0;
    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{}" y="28" font-size="18" text-anchor="middle">{}</text>"#,
        width / 2.0,
        escape(title)
    );
    let r_max = curves
        .iter()
        .flat_map(|c| c.points.iter().map(|p| p.0))
        .fold(0.0, f64::max)
        .max(1e-12);
    let r_max = nice_ceiling(r_max);
    let lines: Vec<&Curve> = curves.iter().filter(|c| !c.markers).collect();
    let scaled: Vec<&Curve> = if lines.is_empty() {
        curves.iter().collect()
    } else {
        lines
    };
    let panels = [
        ("R(r) [1/mm²], log", false, true),
        ("R(r) [1/mm²], linear", false, false),
        ("r·R(r) [1/mm], log", true, true),
        ("r·R(r) [1/mm], linear", true, false),
    ];
    for (i, (label, weighted, log)) in panels.into_iter().enumerate() {
        let x0 = MARGIN_L + (i % 2) as f64 * (PANEL_W + GAP_X);
        let y0 = MARGIN_T + (i / 2) as f64 * (PANEL_H + GAP_Y);
        // Linear axes zoom onto the radii where the profile is visible at all.
        let r_max = if log {
            r_max
        } else {
            nice_ceiling(visible_reach(&scaled, weighted).min(r_max))
        };
        panel(
            &mut svg,
            curves,
            &scaled,
            Frame {
                x0,
                y0,
                r_max,
                weighted,
                log,
            },
            label,
        );
    }
    legend(&mut svg, curves, MARGIN_L, height - 18.0);
    svg.push_str("</svg>");
    svg
}

struct Frame {
    x0: f64,
    y0: f64,
    r_max: f64,
    weighted: bool,
    log: bool,
}

impl Frame {
    fn value(&self, r: f64, v: f64) -> f64 {
        if self.weighted { r * v } else { v }
    }
    fn x(&self, r: f64) -> f64 {
        self.x0 + r / self.r_max * PANEL_W
    }
}

/// The largest radius at which some curve still reaches 1% of its peak.
fn visible_reach(curves: &[&Curve], weighted: bool) -> f64 {
    let value = |r: f64, v: f64| if weighted { r * v } else { v };
    let peak = curves
        .iter()
        .flat_map(|c| c.points.iter().map(|&(r, v)| value(r, v)))
        .fold(0.0, f64::max);
    curves
        .iter()
        .flat_map(|c| {
            c.points
                .iter()
                .filter(|&&(r, v)| value(r, v) >= 0.01 * peak)
                .map(|p| p.0)
        })
        .fold(1e-12, f64::max)
}

/// The smallest 1, 2, 2.5 or 5 times a power of ten at or above `x`.
fn nice_ceiling(x: f64) -> f64 {
    let base = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .find(|v| *v >= x * (1.0 - 1e-12))
        .unwrap_or(x)
}

fn panel(svg: &mut String, curves: &[Curve], scaled: &[&Curve], f: Frame, label: &str) {
    let top = scaled
        .iter()
        .flat_map(|c| c.points.iter().map(|&(r, v)| f.value(r, v)))
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
        .max(1e-300);
    let (lo, hi) = if f.log {
        let floor = top * 1e-7;
        let smallest = scaled
            .iter()
            .flat_map(|c| c.points.iter().map(|&(r, v)| f.value(r, v)))
            .filter(|v| *v > floor)
            .fold(top, f64::min);
        (smallest.log10().floor(), top.log10().ceil())
    } else {
        (0.0, top * 1.05)
    };
    let y = |v: f64| {
        let t = if f.log {
            (v.max(1e-300).log10().clamp(lo, hi) - lo) / (hi - lo).max(1e-12)
        } else {
            (v / hi).clamp(0.0, 1.0)
        };
        f.y0 + PANEL_H * (1.0 - t)
    };
    let _ = write!(
        svg,
        r##"<rect x="{}" y="{}" width="{PANEL_W}" height="{PANEL_H}" fill="none" stroke="#444"/><text x="{}" y="{}" text-anchor="middle" font-size="13">{}</text><text x="{}" y="{}" text-anchor="middle">r [mm]</text>"##,
        f.x0,
        f.y0,
        f.x0 + PANEL_W / 2.0,
        f.y0 - 8.0,
        escape(label),
        f.x0 + PANEL_W / 2.0,
        f.y0 + PANEL_H + 34.0
    );
    for k in 0..=5 {
        let r = f.r_max * k as f64 / 5.0;
        let _ = write!(
            svg,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" text-anchor="middle">{}</text>"##,
            f.y0,
            f.y0 + PANEL_H,
            f.y0 + PANEL_H + 16.0,
            tick(r),
            x = f.x(r)
        );
    }
    let ticks: Vec<f64> = if f.log {
        let step = ((hi - lo) / 8.0).ceil().max(1.0);
        (0..=((hi - lo) / step) as i32)
            .map(|i| 10f64.powf(lo + i as f64 * step))
            .collect()
    } else {
        (0..=4).map(|i| hi * i as f64 / 4.0).collect()
    };
    for v in ticks {
        let _ = write!(
            svg,
            r##"<line x1="{}" y1="{yy}" x2="{}" y2="{yy}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">{}</text>"##,
            f.x0,
            f.x0 + PANEL_W,
            f.x0 - 6.0,
            y(v) + 4.0,
            tick(v),
            yy = y(v)
        );
    }
    let inside = |r: f64| r <= f.r_max * (1.0 + 1e-9);
    for c in curves {
        let colour = COLOURS[c.channel % 3];
        let visible = |v: f64| v.is_finite() && (!f.log || v.log10() >= lo);
        if c.markers {
            for (i, &(r, v)) in c.points.iter().enumerate() {
                let value = f.value(r, v);
                if !visible(value) || !inside(r) || value > hi * 1.02 && !f.log {
                    continue;
                }
                if let Some(e) = c.errors.as_ref().and_then(|e| e.get(i)) {
                    let e = f.value(r, *e);
                    let _ = write!(
                        svg,
                        r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="{colour}"/>"#,
                        y((value - e).max(if f.log { 10f64.powf(lo) } else { 0.0 })),
                        y(value + e),
                        x = f.x(r)
                    );
                }
                let _ = write!(
                    svg,
                    r#"<circle cx="{}" cy="{}" r="2.5" fill="{colour}"/>"#,
                    f.x(r),
                    y(value)
                );
            }
        } else {
            let points: Vec<String> = c
                .points
                .iter()
                .map(|&(r, v)| (r, f.value(r, v)))
                .filter(|&(r, v)| visible(v) && inside(r))
                .map(|(r, v)| format!("{:.2},{:.2}", f.x(r), y(v)))
                .collect();
            let _ = write!(
                svg,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.6"/>"#,
                points.join(" ")
            );
        }
    }
}

fn legend(svg: &mut String, curves: &[Curve], x: f64, y: f64) {
    let mut labels: Vec<(&str, bool)> = Vec::new();
    for c in curves {
        if !labels.iter().any(|(l, _)| *l == c.label) {
            labels.push((&c.label, c.markers));
        }
    }
    let mut at = x;
    for (label, markers) in labels {
        let mark = if markers {
            format!(
                r##"<circle cx="{}" cy="{}" r="3" fill="#333"/>"##,
                at + 10.0,
                y - 4.0
            )
        } else {
            format!(
                r##"<line x1="{at}" y1="{yy}" x2="{}" y2="{yy}" stroke="#333" stroke-width="2"/>"##,
                at + 20.0,
                yy = y - 4.0
            )
        };
        let _ = write!(
            svg,
            r#"{mark}<text x="{}" y="{y}">{}</text>"#,
            at + 26.0,
            escape(label)
        );
        at += 40.0 + 8.0 * label.len() as f64;
    }
    let _ = write!(
        svg,
        r#"<text x="{at}" y="{y}">colours: red, green, blue channels</text>"#
    );
}

pub(crate) fn tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if (0.01..1000.0).contains(&v.abs()) {
        format!("{}", (v * 1000.0).round() / 1000.0)
    } else {
        format!("{v:.0e}")
    }
}

pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Rasterises the SVG to PNG bytes, with the system's fonts for the text.
pub fn render_png(svg: &str) -> Result<Vec<u8>, String> {
    let mut options = resvg::usvg::Options::default();
    options.fontdb_mut().load_system_fonts();
    let tree = resvg::usvg::Tree::from_str(svg, &options).map_err(|e| e.to_string())?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| "the plot has no area".to_string())?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| e.to_string())
}

/// The extension of `path`, in lower case.
fn extension(path: &std::path::Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// True when `path` names a plot this module writes: `.svg` or `.png`.
pub fn is_plot_file(path: &std::path::Path) -> bool {
    matches!(extension(path).as_deref(), Some("svg" | "png"))
}

/// `svg` as the bytes of a file named `path`: as it is for `.svg`,
/// rasterised for `.png`; any other name is refused, saying so.
pub fn file_bytes(path: &std::path::Path, svg: String) -> Result<Vec<u8>, String> {
    match extension(path).as_deref() {
        Some("svg") => Ok(svg.into_bytes()),
        Some("png") => render_png(&svg),
        _ => Err("the file must end in .svg or .png".into()),
    }
}
