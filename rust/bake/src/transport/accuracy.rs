//! How far one integrator's exitance is from a reference's.

/// Relative RMSE and maximum error of `got` against `reference`, over
/// every texel and channel: RMS(got − ref)/RMS(ref), and max |got − ref| /
/// max ref. Both zero when the reference is black.
pub fn relative_errors(got: &[[f32; 3]], reference: &[[f32; 3]]) -> (f64, f64) {
    let (mut diff2, mut ref2, mut worst, mut peak) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (g, r) in got.iter().zip(reference) {
        for c in 0..3 {
            let d = (g[c] - r[c]) as f64;
            diff2 += d * d;
            ref2 += (r[c] as f64).powi(2);
            worst = worst.max(d.abs());
            peak = peak.max(r[c] as f64);
        }
    }
    if ref2 <= 0.0 {
        return (0.0, 0.0);
    }
    ((diff2 / ref2).sqrt(), worst / peak.max(1e-30))
}
