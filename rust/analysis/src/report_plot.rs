//! The report's figure: relative RMSE against seconds on log–log axes, one
//! curve per integrator, the reference's time as a vertical line.

use std::fmt::Write;

/// One integrator's runs: (seconds, relative RMSE, setting label).
pub struct Series {
    /// The integrator's name.
    pub name: String,
    /// Its runs, in any order.
    pub points: Vec<(f64, f64, String)>,
}

const COLOURS: [&str; 4] = ["#c62828", "#2e7d32", "#1565c0", "#6a1b9a"];
const W: f64 = 720.0;
const H: f64 = 460.0;
const LEFT: f64 = 80.0;
const TOP: f64 = 50.0;

/// An SVG document of `series` with the reference's time `reference_s`.
pub fn render(title: &str, series: &[Series], reference_s: f64) -> String {
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| (p.0, p.1)))
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .collect();
    let decade = |v: f64, up: bool| {
        let e = v.log10();
        10f64.powf(if up { e.ceil() } else { e.floor() })
    };
    let fold = |f: fn(f64, f64) -> f64, start: f64, pick: fn(&(f64, f64)) -> f64| {
        all.iter().map(pick).fold(start, f)
    };
    let x_lo = decade(fold(f64::min, reference_s.max(1e-6), |p| p.0), false);
    let x_hi = decade(fold(f64::max, reference_s.max(1e-6), |p| p.0), true).max(x_lo * 10.0);
    let y_lo = decade(fold(f64::min, 1.0, |p| p.1), false);
    let y_hi = decade(fold(f64::max, 1e-6, |p| p.1), true).max(y_lo * 10.0);
    let x = |s: f64| LEFT + (s.log10() - x_lo.log10()) / (x_hi.log10() - x_lo.log10()) * W;
    let y = |e: f64| TOP + H - (e.log10() - y_lo.log10()) / (y_hi.log10() - y_lo.log10()) * H;
    let (width, height) = (LEFT + W + 170.0, TOP + H + 60.0);
    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{}" y="28" font-size="16" text-anchor="middle">{}</text>"#,
        LEFT + W / 2.0,
        escape(title)
    );
    let _ = write!(
        svg,
        r##"<rect x="{LEFT}" y="{TOP}" width="{W}" height="{H}" fill="none" stroke="#444"/>"##
    );
    let mut tick = x_lo;
    while tick <= x_hi * 1.0001 {
        let px = x(tick);
        let _ = write!(
            svg,
            r##"<line x1="{px}" y1="{TOP}" x2="{px}" y2="{}" stroke="#ddd"/><text x="{px}" y="{}" text-anchor="middle">{}</text>"##,
            TOP + H,
            TOP + H + 18.0,
            label(tick)
        );
        tick *= 10.0;
    }
    let mut tick = y_lo;
    while tick <= y_hi * 1.0001 {
        let py = y(tick);
        let _ = write!(
            svg,
            r##"<line x1="{LEFT}" y1="{py}" x2="{}" y2="{py}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">{}</text>"##,
            LEFT + W,
            LEFT - 6.0,
            py + 4.0,
            label(tick)
        );
        tick *= 10.0;
    }
    let _ = write!(
        svg,
        r#"<text x="{}" y="{}" text-anchor="middle">integration time [s]</text><text transform="translate(22 {}) rotate(-90)" text-anchor="middle">relative RMSE against brute</text>"#,
        LEFT + W / 2.0,
        TOP + H + 42.0,
        TOP + H / 2.0
    );
    let rx = x(reference_s.max(x_lo));
    let _ = write!(
        svg,
        r##"<line x1="{rx}" y1="{TOP}" x2="{rx}" y2="{}" stroke="#000" stroke-dasharray="5 4"/><text x="{}" y="{}" >brute {reference_s:.2} s</text>"##,
        TOP + H,
        rx + 4.0,
        TOP + 14.0
    );
    for (k, s) in series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let mut points: Vec<&(f64, f64, String)> =
            s.points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let path: Vec<String> = points
            .iter()
            .map(|p| format!("{:.1},{:.1}", x(p.0), y(p.1)))
            .collect();
        let _ = write!(
            svg,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.5"/>"#,
            path.join(" ")
        );
        for p in &points {
            let _ = write!(
                svg,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{colour}"/><text x="{:.1}" y="{:.1}" font-size="10" fill="{colour}">{}</text>"#,
                x(p.0),
                y(p.1),
                x(p.0) + 5.0,
                y(p.1) - 5.0,
                escape(&p.2)
            );
        }
        let ly = TOP + 20.0 + 22.0 * k as f64;
        let _ = write!(
            svg,
            r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{colour}" stroke-width="2"/><text x="{}" y="{}">{}</text>"#,
            LEFT + W + 15.0,
            LEFT + W + 45.0,
            LEFT + W + 52.0,
            ly + 4.0,
            escape(&s.name)
        );
    }
    svg.push_str("</svg>");
    svg
}

fn label(v: f64) -> String {
    let e = v.log10().round() as i32;
    if (-2..=3).contains(&e) {
        format!("{}", 10f64.powi(e))
    } else {
        format!("1e{e}")
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
