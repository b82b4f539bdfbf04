//! The colour of a blackbody at a temperature, as UsdLux defines a light's
//! `colorTemperature` (`UsdLuxBlackbodyTemperatureAsRgb`): the emission of a
//! blackbody in linear Rec. 709 with luminance 1, for temperatures clamped
//! to UsdLux's valid range of 1000 K to 10000 K.
//!
//! Computed here from first principles: Planck's law integrated against the
//! CIE 1931 2° colour-matching functions, which are approximated by the
//! multi-lobe Gaussian fit of Wyman, Sloan and Shirley ("Simple Analytic
//! Approximations to the CIE XYZ Color Matching Functions", JCGT 2013),
//! then XYZ to linear Rec. 709 (D65) and divided by the luminance. It agrees
//! with usd-core's `UsdLux.BlackbodyTemperatureAsRgb` within 2% per channel
//! from 2500 K up (the fit's error; `tests/test_usd_lights.py` compares
//! them), and so with Blender's `temperature_color`, which follows the same
//! definition.

/// UsdLux's valid range of colour temperatures, kelvin.
pub const KELVIN_RANGE: (f64, f64) = (1000.0, 10000.0);

/// Linear Rec. 709 RGB of luminance 1 of a blackbody at `kelvin` (clamped
/// to [`KELVIN_RANGE`]; a non-finite temperature gives white).
pub fn blackbody_rgb(kelvin: f64) -> [f64; 3] {
    if !kelvin.is_finite() {
        return [1.0; 3];
    }
    let t = kelvin.clamp(KELVIN_RANGE.0, KELVIN_RANGE.1);
    // Second radiation constant hc/k, m·K.
    const C2: f64 = 1.438_776_877e-2;
    let mut xyz = [0.0f64; 3];
    for nm in 360..=830 {
        let lambda = f64::from(nm);
        let metres = lambda * 1e-9;
        // Planck's spectral radiance up to a constant factor, which the
        // normalisation removes.
        let planck = 1.0 / (metres.powi(5) * ((C2 / (metres * t)).exp() - 1.0));
        let cmf = colour_matching(lambda);
        for c in 0..3 {
            xyz[c] += planck * cmf[c];
        }
    }
    let [x, y, z] = xyz;
    let rgb = [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
    .map(|v| v.max(0.0));
    let luminance = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    rgb.map(|v| v / luminance)
}

/// CIE 1931 2° x̄, ȳ, z̄ at `nm` nanometres, by the multi-lobe fit of Wyman,
/// Sloan and Shirley 2013 (their equation 2 and table 1).
fn colour_matching(nm: f64) -> [f64; 3] {
    // A Gaussian with different widths either side of its peak.
    let lobe = |mu: f64, below: f64, above: f64| {
        let t = (nm - mu) * if nm < mu { below } else { above };
        (-0.5 * t * t).exp()
    };
    [
        1.056 * lobe(599.8, 0.0264, 0.0323) + 0.362 * lobe(442.0, 0.0624, 0.0374)
            - 0.065 * lobe(501.1, 0.0490, 0.0382),
        0.821 * lobe(568.8, 0.0213, 0.0247) + 0.286 * lobe(530.9, 0.0613, 0.0322),
        1.217 * lobe(437.0, 0.0845, 0.0278) + 0.681 * lobe(459.0, 0.0385, 0.0725),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_has_unit_luminance_and_warms_as_it_cools() {
        for kelvin in [1000.0, 2700.0, 6500.0, 10000.0] {
            let [r, g, b] = blackbody_rgb(kelvin);
            let luminance = 0.2126 * r + 0.7152 * g + 0.0722 * b;
            assert!((luminance - 1.0).abs() < 1e-9, "{kelvin} K: {luminance}");
        }
        let warm = blackbody_rgb(3000.0);
        let cool = blackbody_rgb(9000.0);
        assert!(warm[0] > warm[2] && cool[2] > cool[0]);
        // Outside UsdLux's range the ends hold.
        assert_eq!(blackbody_rgb(20000.0), blackbody_rgb(10000.0));
        assert_eq!(blackbody_rgb(500.0), blackbody_rgb(1000.0));
    }

    #[test]
    fn it_matches_usd_cores_values_within_the_fits_error() {
        // UsdLux.BlackbodyTemperatureAsRgb in usd-core 26 (printed once).
        let reference = [
            (3000.0, [1.771_028, 0.844_294, 0.272_032]),
            (5000.0, [1.213_509, 0.960_544, 0.762_144]),
            (6500.0, [1.043_333, 0.983_624, 1.034_613]),
            (10000.0, [0.871_841, 0.994_688, 1.429_996]),
        ];
        for (kelvin, want) in reference {
            let got = blackbody_rgb(kelvin);
            for c in 0..3 {
                assert!(
                    (got[c] / want[c] - 1.0).abs() < 0.02,
                    "{kelvin} K channel {c}: {} against {}",
                    got[c],
                    want[c]
                );
            }
        }
    }
}
