//! Where an integrator departs from the exact sum: |M − M_brute| per texel
//! over the UV layout, as a colour ramp a person can read at a glance.
//!
//! The error is the largest channel's |M − M_brute| over the 99th
//! percentile of M_brute (so one bright texel does not hide the rest):
//! dark blue is exact, red 3%, yellow 10%, white 30% and beyond; texels
//! outside the layout stay black.

use sssbake::TexelSurfels;
use sssbake::image::Image;
use sssbake::maps::in_layout;

/// The stops of the ramp: (relative error, linear RGB).
const RAMP: [(f32, [f32; 3]); 4] = [
    (0.0, [0.0, 0.0, 0.25]),
    (0.03, [1.0, 0.0, 0.0]),
    (0.10, [1.0, 1.0, 0.0]),
    (0.30, [1.0, 1.0, 1.0]),
];

/// The error map of exitance `got` against `reference`, per surfel of
/// `surfels`.
pub fn error_map(surfels: &TexelSurfels, got: &[[f32; 3]], reference: &[[f32; 3]]) -> Image {
    let scale = percentile_99(reference).max(f32::MIN_POSITIVE);
    let colours: Vec<[f32; 3]> = got
        .iter()
        .zip(reference)
        .map(|(g, r)| {
            let error = (0..3).map(|c| (g[c] - r[c]).abs()).fold(0.0, f32::max);
            ramp(error / scale)
        })
        .collect();
    in_layout(surfels, &colours, &[])
}

/// The 99th percentile of the brightest channel.
fn percentile_99(values: &[[f32; 3]]) -> f32 {
    let mut brightest: Vec<f32> = values
        .iter()
        .map(|v| v.iter().copied().fold(0.0, f32::max))
        .filter(|v| v.is_finite())
        .collect();
    if brightest.is_empty() {
        return 0.0;
    }
    let k = ((brightest.len() - 1) as f64 * 0.99).round() as usize;
    *brightest.select_nth_unstable_by(k, f32::total_cmp).1
}

/// The ramp's colour at relative error `x`, linear between stops.
fn ramp(x: f32) -> [f32; 3] {
    let x = if x.is_finite() { x.max(0.0) } else { 1.0 };
    for pair in RAMP.windows(2) {
        let ((x0, c0), (x1, c1)) = (pair[0], pair[1]);
        if x <= x1 {
            let t = (x - x0) / (x1 - x0);
            return [0, 1, 2].map(|k| c0[k] + t * (c1[k] - c0[k]));
        }
    }
    RAMP[RAMP.len() - 1].1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_runs_from_exact_to_white_through_its_stops() {
        assert_eq!(ramp(0.0), RAMP[0].1);
        assert_eq!(ramp(0.03), [1.0, 0.0, 0.0]);
        assert_eq!(ramp(0.10), [1.0, 1.0, 0.0]);
        assert_eq!(ramp(5.0), [1.0; 3]);
        assert_eq!(ramp(f32::NAN), [1.0; 3]);
        let half = ramp(0.015);
        assert!((half[0] - 0.5).abs() < 1e-6 && (half[2] - 0.125).abs() < 1e-6);
    }

    #[test]
    fn the_scale_is_the_99th_percentile_of_the_brightest_channel() {
        let values: Vec<[f32; 3]> = (0..=100).map(|i| [0.0, i as f32, 0.0]).collect();
        assert_eq!(percentile_99(&values), 99.0);
        assert_eq!(percentile_99(&[]), 0.0);
    }
}
