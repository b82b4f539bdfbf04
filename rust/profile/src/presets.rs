//! Named materials: the measured media of Jensen et al. 2001, those of
//! Donner et al. 2009 (wax, diluted milk, orange juice), the three-layer
//! skin of Donner & Jensen 2005, the two slabs of Donner & Jensen 2006
//! (Mikkelsen 2009 table 3), Stam 2001's dermis and his skin (an
//! epidermis by discrete ordinates over it), and d'Eon & Luebke's
//! six-Gaussian skin.

use crate::Rgb;
use crate::material::{Layer, Material, Optics, TopLayer};
use crate::models::gaussians::SumOfGaussians;

/// Jensen et al. 2001, table of measured parameters: name, σs' (1/mm) and
/// σa (1/mm) per channel. All were measured with η = 1.3 and are given as
/// reduced scattering, so the layers have g = 0 and σs = σs'.
const JENSEN_2001: [(&str, Rgb, Rgb); 12] = [
    ("apple", [2.29, 2.39, 1.97], [0.0030, 0.0034, 0.046]),
    ("chicken1", [0.15, 0.21, 0.38], [0.015, 0.077, 0.19]),
    ("chicken2", [0.19, 0.25, 0.32], [0.018, 0.088, 0.20]),
    ("cream", [7.38, 5.47, 3.15], [0.0002, 0.0028, 0.0163]),
    ("ketchup", [0.18, 0.07, 0.03], [0.061, 0.97, 1.45]),
    ("marble", [2.19, 2.62, 3.00], [0.0021, 0.0041, 0.0071]),
    ("potato", [0.68, 0.70, 0.55], [0.0024, 0.0090, 0.12]),
    ("skimmilk", [0.70, 1.22, 1.90], [0.0014, 0.0025, 0.0142]),
    ("skin1", [0.74, 0.88, 1.01], [0.032, 0.17, 0.48]),
    ("skin2", [1.09, 1.59, 1.79], [0.013, 0.070, 0.145]),
    ("spectralon", [11.6, 20.4, 14.9], [0.0, 0.0, 0.0]),
    ("wholemilk", [2.55, 3.21, 3.77], [0.0011, 0.0024, 0.014]),
];

/// Index of refraction used by Jensen et al. 2001 for every measured medium.
pub const JENSEN_IOR: f64 = 1.3;

/// Donner et al. 2009's media: name, σs and σa (1/mm) per channel, g and
/// η. Wax and 50% diluted skim milk are the measured media of figure 3
/// (one red wavelength, so equal in every channel); orange juice is
/// figure 1's; the green lozenge (figure 7) is [`lozenge`].
const DONNER_2009: [(&str, Rgb, Rgb, f64, f64); 3] = [
    ("wax", [1.0; 3], [0.5; 3], 0.0, 1.4),
    ("dilutedmilk", [1.165; 3], [0.0007; 3], 0.7, 1.35),
    (
        "orangejuice",
        [0.071, 0.1, 0.042],
        [0.093, 0.16, 1.15],
        0.9,
        1.3,
    ),
];

/// The green lozenge of Donner et al. 2009 figure 7: its albedo
/// (0.16, 0.27, 0.15) and g = 0.5 are the paper's. The paper gives no
/// scale and no index, so the preset takes σt = 0.5/mm (a mean free path
/// of 2 mm, which leaves a lozenge about 20 mm across as translucent as
/// the figure shows it) and η = 1.5, sugar glass's. The empirical model's
/// shape depends only on albedo, g and η; σt scales it.
fn lozenge() -> Layer {
    const ALBEDO: Rgb = [0.16, 0.27, 0.15];
    const SIGMA_T: f64 = 0.5;
    Layer {
        sigma_a: ALBEDO.map(|a| (1.0 - a) * SIGMA_T),
        sigma_s: ALBEDO.map(|a| a * SIGMA_T),
        g: 0.5,
        ior: 1.5,
        thickness_mm: None,
    }
}

/// Donner & Jensen 2005 table 3 (Mikkelsen table 2): epidermis, upper
/// dermis and a semi-infinite bloody dermis; σa, σs in 1/mm, thickness in mm.
fn three_layer_skin() -> Vec<Layer> {
    vec![
        Layer {
            sigma_a: [2.1, 2.1, 5.0],
            sigma_s: [48.0, 60.0, 65.0],
            g: 0.0,
            ior: 1.4,
            thickness_mm: Some(0.03),
        },
        Layer {
            sigma_a: [0.16, 0.19, 0.30],
            sigma_s: [32.0, 40.0, 46.0],
            g: 0.25,
            ior: 1.34,
            thickness_mm: Some(0.05),
        },
        Layer {
            sigma_a: [0.085, 1.0, 25.0],
            sigma_s: [4.5, 4.7, 4.8],
            g: 0.8,
            ior: 1.4,
            thickness_mm: None,
        },
    ]
}

/// Donner & Jensen 2006's figure 4a (Mikkelsen 2009 table 3): a 6 mm slab
/// over a semi-infinite one, both at η = 1.4; σa and σs' in 1/mm, one value
/// for every channel (the paper's figure is monochrome). Given as reduced
/// scattering, so g = 0 and σs = σs'.
fn two_slab_example() -> Vec<Layer> {
    vec![
        Layer {
            sigma_a: [0.005; 3],
            sigma_s: [1.3; 3],
            g: 0.0,
            ior: 1.4,
            thickness_mm: Some(6.0),
        },
        Layer {
            sigma_a: [0.01; 3],
            sigma_s: [1.0; 3],
            g: 0.0,
            ior: 1.4,
            thickness_mm: None,
        },
    ]
}

/// Stam 2001 table 2: the dermis's single-scattering albedo per channel.
const STAM_DERMIS_ALBEDO: Rgb = [0.993, 0.979, 0.943];
/// Table 2's anisotropy per channel; a layer has one g, their mean.
const STAM_DERMIS_G: Rgb = [0.860, 0.854, 0.823];
/// A roughness within table 2's range (0.1 – 0.9) of Stam's σ, the slope
/// deviation per axis (σ = m/√2 for the RMS slope m a material gives):
/// m = 0.4 is σ ≈ 0.28.
const STAM_ROUGHNESS: f64 = 0.4;

/// σt (1/mm) that gives Stam's dermis a length scale in `stam-skin`: the
/// scattering of Donner & Jensen 2005's bloody dermis (σs 4.5–4.8/mm).
/// With table 2's albedo and g it makes σs' ≈ 0.72/mm and σa ≈ 0.033,
/// 0.099, 0.27/mm, near Jensen et al. 2001's measured skin1.
const STAM_SKIN_DERMIS_SIGMA_T: f64 = 4.7;

/// Stam 2001's dermis: opaque (T = 0, so semi-infinite), index 1.4 (his
/// ratio for skin), extinction `sigma_t` (1/mm). The paper works in
/// optical depth and gives no length scale: `stam-dermis` takes a nominal
/// 1/mm (the angular results of `stam` do not depend on it, a radial
/// profile would), `stam-skin` [`STAM_SKIN_DERMIS_SIGMA_T`].
fn stam_dermis(sigma_t: f64) -> Layer {
    Layer {
        sigma_a: STAM_DERMIS_ALBEDO.map(|a| (1.0 - a) * sigma_t),
        sigma_s: STAM_DERMIS_ALBEDO.map(|a| a * sigma_t),
        g: STAM_DERMIS_G.iter().sum::<f64>() / 3.0,
        ior: 1.4,
        thickness_mm: None,
    }
}

/// Presets without a length scale (Stam 2001 gives none), for the angular
/// `stam` model only: a bake refuses them.
pub const ANGULAR_ONLY: [&str; 1] = ["stam-dermis"];

/// Every preset name with a one-line description.
pub fn list() -> Vec<(&'static str, &'static str)> {
    let mut names: Vec<(&str, &str)> = JENSEN_2001
        .iter()
        .map(|(n, _, _)| (*n, "measured medium, Jensen et al. 2001 (dipole, η = 1.3)"))
        .collect();
    names.extend(DONNER_2009.iter().map(|(n, ..)| {
        (
            *n,
            "medium of Donner et al. 2009 (semi-infinite, σs, σa, g, η)",
        )
    }));
    names.push((
        "lozenge",
        "green lozenge of Donner et al. 2009 fig. 7 (its albedo and g; nominal σt 0.5/mm, η 1.5)",
    ));
    names.push((
        "skin3layer",
        "epidermis, upper and bloody dermis, Donner & Jensen 2005",
    ));
    names.push((
        "two-slab",
        "6 mm slab over a semi-infinite one, Donner & Jensen 2006 fig. 4a (Mikkelsen table 3)",
    ));
    names.push((
        "stam-dermis",
        "dermis of Stam 2001 table 2 (albedo, g, η = 1.4, m = 0.4; nominal σt = 1/mm) for --model stam",
    ));
    names.push((
        "stam-skin",
        "Stam 2001's skin: a rough (m = 0.4) epidermis by discrete ordinates over table 2's dermis (σt 4.7/mm)",
    ));
    names.push((
        "deon-skin",
        "six-Gaussian skin of d'Eon & Luebke 2007 (a profile, no coefficients)",
    ));
    names
}

/// The preset called `name`, or an error that lists the known names.
pub fn named(name: &str) -> Result<Material, String> {
    preset(name).ok_or_else(|| {
        let names: Vec<&str> = list().into_iter().map(|(n, _)| n).collect();
        format!("unknown preset `{name}` (known: {})", names.join(", "))
    })
}

/// The preset called `name`, if there is one.
pub fn preset(name: &str) -> Option<Material> {
    let mut roughness = crate::material::DEFAULT_ROUGHNESS;
    let mut top_layer = TopLayer::Diffusion;
    let optics = match name {
        "skin3layer" => Optics::Layers(three_layer_skin()),
        "lozenge" => Optics::Layers(vec![lozenge()]),
        "two-slab" => Optics::Layers(two_slab_example()),
        "stam-dermis" => {
            roughness = STAM_ROUGHNESS;
            Optics::Layers(vec![stam_dermis(1.0)])
        }
        "stam-skin" => {
            roughness = STAM_ROUGHNESS;
            top_layer = TopLayer::Stam;
            Optics::Layers(vec![
                three_layer_skin()[0].clone(),
                stam_dermis(STAM_SKIN_DERMIS_SIGMA_T),
            ])
        }
        "deon-skin" => Optics::Gaussians(SumOfGaussians::deon_skin()),
        _ if DONNER_2009.iter().any(|(n, ..)| *n == name) => {
            let (_, sigma_s, sigma_a, g, ior) = DONNER_2009.iter().find(|(n, ..)| *n == name)?;
            Optics::Layers(vec![Layer {
                sigma_a: *sigma_a,
                sigma_s: *sigma_s,
                g: *g,
                ior: *ior,
                thickness_mm: None,
            }])
        }
        _ => {
            let (_, sigma_s_reduced, sigma_a) = JENSEN_2001.iter().find(|(n, _, _)| *n == name)?;
            Optics::Layers(vec![Layer::semi_infinite(
                *sigma_a,
                *sigma_s_reduced,
                JENSEN_IOR,
            )])
        }
    };
    Some(Material {
        name: name.to_string(),
        optics,
        coat_ior: None,
        top_layer,
        roughness,
    })
}
