//! Materials: a stack of layers with optical coefficients, or a measured sum
//! of Gaussians; read from TOML files and validated with errors that name the
//! file and the field.

use crate::Rgb;
use crate::boundary::rough::MAX_ROUGHNESS;
use crate::diffusion::medium::Medium;
use crate::models::gaussians::SumOfGaussians;
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;
use std::path::Path;

/// The roughness of a material that gives none: a smooth surface.
pub const DEFAULT_ROUGHNESS: f64 = 0.0;

/// One homogeneous layer of a material.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Absorption coefficient σa per channel, 1/mm.
    pub sigma_a: Rgb,
    /// Scattering coefficient σs per channel, 1/mm.
    pub sigma_s: Rgb,
    /// Henyey–Greenstein mean cosine g, in (−1, 1).
    pub g: f64,
    /// Refractive index of the layer (the outside is air, index 1).
    pub ior: f64,
    /// Thickness in mm; `None` for a semi-infinite layer.
    pub thickness_mm: Option<f64>,
}

impl Layer {
    /// A semi-infinite layer given reduced scattering σs' (g = 0), as the
    /// measured media of Jensen et al. 2001 are given.
    pub fn semi_infinite(sigma_a: Rgb, sigma_s_reduced: Rgb, ior: f64) -> Self {
        Self {
            sigma_a,
            sigma_s: sigma_s_reduced,
            g: 0.0,
            ior,
            thickness_mm: None,
        }
    }

    /// The channel-`c` coefficients with σs' = σs(1 − g).
    pub fn medium(&self, c: usize) -> Medium {
        Medium {
            sigma_a: self.sigma_a[c],
            sigma_s_reduced: self.sigma_s[c] * (1.0 - self.g),
        }
    }
}

/// How a material's top layer is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TopLayer {
    /// By diffusion, as every layer of the stack.
    #[default]
    Diffusion,
    /// By Stam 2001's discrete ordinates ([`crate::models::stam`]): a thin surface
    /// layer (an epidermis) whose faces are the material's surface, with
    /// its own roughness. Light enters through its angular transmittance
    /// T(θi) and the layers below see its totals, with no lateral spread
    /// ([`crate::models::stam::topped`]). TOML: `model = "stam"` in the first
    /// `[[layers]]` table.
    Stam,
    /// By diffusion, under Blender's Principled specular layer (the coat,
    /// [`Material::coat_ior`]) as Cycles weighs it: once, where the surface
    /// is viewed (a bake views along the normal), and not where light
    /// enters, since Cycles lights the point a subsurface walk leaves
    /// through a plain diffuse closure (`subsurface_shader_data_setup` in
    /// `kernel/integrator/subsurface.h`). Set by
    /// [`crate::appearance::cycles::PrincipledSubsurface::to_material`].
    PrincipledSpecular,
}

/// What a material is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum Optics {
    /// Layers from the top down; only the last may be semi-infinite.
    Layers(Vec<Layer>),
    /// A measured profile with no optical coefficients behind it.
    Gaussians(SumOfGaussians),
}

/// A named material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name for reports.
    pub name: String,
    /// The optics.
    pub optics: Optics,
    /// Index of a smooth dielectric coat over the top layer that light
    /// crosses on entry (Blender's specular layer over an index-matched
    /// random walk); `None`: the top layer's own index.
    pub coat_ior: Option<f64>,
    /// RMS slope m of the Beckmann facets of the material's surface, the
    /// rough boundary of Donner & Jensen 2005 §2.4 (dimensionless, in
    /// [0, [`MAX_ROUGHNESS`]]; 0 is smooth). It sets the light crossing in
    /// and out (ρdt, eq. 25–26, through the coat when there is one) and
    /// the diffusion boundary of the faces against air (A from ρd, eq. 24).
    pub roughness: f64,
    /// How the top layer is solved (of [`Optics::Layers`]; diffusion
    /// unless a material file says `model = "stam"`).
    pub top_layer: TopLayer,
}

/// A material that could not be read or is not physical; says where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MaterialError {
    /// The file (or preset) the material came from.
    pub source: String,
    /// The offending field, such as `layers[1].sigma_a`, or empty.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for MaterialError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}: {}", self.source, self.message)
        } else {
            write!(f, "{}: {}: {}", self.source, self.field, self.message)
        }
    }
}

impl std::error::Error for MaterialError {}

impl Material {
    /// Reads and validates a TOML material file.
    pub fn from_file(path: &Path) -> Result<Self, MaterialError> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| MaterialError {
            source: source.clone(),
            field: String::new(),
            message: format!("cannot read the file: {e}"),
        })?;
        let default_name = path
            .file_stem()
            .map_or("material".into(), |s| s.to_string_lossy().into_owned());
        Self::from_toml(&text, &source, &default_name)
    }

    /// Parses and validates TOML text; `source` names it in errors, with the
    /// field's path (`layers[1].ior`). A key outside the layout below is an
    /// error, so a misspelt one is caught rather than left at its default.
    ///
    /// ```toml
    /// name = "two-layer skin"        # optional
    /// coat_ior = 1.4                 # optional: a coat light enters through
    /// roughness = 0.3                # optional: RMS facet slope in [0, 1], default 0 (smooth)
    /// [[layers]]
    /// sigma_a = [0.032, 0.17, 0.48]  # 1/mm, a number or [r, g, b]
    /// sigma_s = 0.74                 # 1/mm
    /// g = 0.0                        # optional, default 0
    /// ior = 1.3                      # optional, default 1.3
    /// thickness_mm = 0.25            # absent: semi-infinite
    /// model = "stam"                 # optional, top layer only: "diffusion" (default) or "stam"
    /// ```
    pub fn from_toml(text: &str, source: &str, default_name: &str) -> Result<Self, MaterialError> {
        let error = |field: &str, message: String| MaterialError {
            source: source.to_string(),
            field: field.to_string(),
            message,
        };
        let document = toml::Deserializer::parse(text)
            .map_err(|e| error("", format!("not valid TOML: {}", e.message().trim())))?;
        let file: MaterialFile = serde_path_to_error::deserialize(document).map_err(|e| {
            // The path prints as `layers[0].ior`, the form the validation
            // below uses; an error at the root (which prints as `.`) has none.
            let field = match e.path().iter().next() {
                Some(_) => e.path().to_string(),
                None => String::new(),
            };
            error(&field, e.inner().message().trim().to_string())
        })?;
        let Some(LayerList(layers)) = file.layers else {
            return Err(error(
                "layers",
                "missing: a material needs at least one [[layers]] table".into(),
            ));
        };
        let mut parsed = Vec::with_capacity(layers.len());
        let mut top_layer = TopLayer::Diffusion;
        for (i, layer) in layers.into_iter().enumerate() {
            match (i, layer.model.as_deref()) {
                (_, None | Some("diffusion")) => {}
                (0, Some("stam")) => top_layer = TopLayer::Stam,
                (_, Some("stam")) => {
                    return Err(error(
                        &format!("layers[{i}].model"),
                        "only the top layer (layers[0]) may be solved by stam".into(),
                    ));
                }
                (_, Some(other)) => {
                    return Err(error(
                        &format!("layers[{i}].model"),
                        format!("unknown layer model `{other}` (known: diffusion, stam)"),
                    ));
                }
            }
            let missing = |name: &str| {
                error(
                    &format!("layers[{i}].{name}"),
                    "missing (1/mm, a number or [r, g, b])".into(),
                )
            };
            let sigma_a = layer.sigma_a.ok_or_else(|| missing("sigma_a"))?;
            let sigma_s = layer.sigma_s.ok_or_else(|| missing("sigma_s"))?;
            parsed.push(Layer {
                sigma_a: sigma_a.0,
                sigma_s: sigma_s.0,
                g: layer.g.map_or(0.0, |n| n.0),
                ior: layer.ior.map_or(1.3, |n| n.0),
                thickness_mm: layer.thickness_mm.map(|n| n.0),
            });
        }
        let material = Material {
            name: file.name.unwrap_or_else(|| default_name.to_string()),
            optics: Optics::Layers(parsed),
            coat_ior: file.coat_ior.map(|n| n.0),
            roughness: file.roughness.map_or(DEFAULT_ROUGHNESS, |n| n.0),
            top_layer,
        };
        material.validate(source)?;
        Ok(material)
    }

    /// Checks that every coefficient is physical and the stack is well formed.
    pub fn validate(&self, source: &str) -> Result<(), MaterialError> {
        let error = |field: String, message: String| MaterialError {
            source: source.to_string(),
            field,
            message,
        };
        if let Some(coat) = self.coat_ior.filter(|n| !(n.is_finite() && *n > 0.0)) {
            return Err(error(
                "coat_ior".into(),
                format!("must be a positive finite index, got {coat}"),
            ));
        }
        if !(0.0..=MAX_ROUGHNESS).contains(&self.roughness) {
            return Err(error(
                "roughness".into(),
                format!(
                    "must be an RMS facet slope between 0 (smooth) and {MAX_ROUGHNESS}, got {}",
                    self.roughness
                ),
            ));
        }
        if self.top_layer == TopLayer::Stam {
            if matches!(self.optics, Optics::Gaussians(_)) {
                return Err(error(
                    "layers[0].model".into(),
                    "stam needs a layer's optical coefficients; a measured sum of Gaussians has none"
                        .into(),
                ));
            }
            if self.coat_ior.is_some() {
                return Err(error(
                    "coat_ior".into(),
                    "a stam top layer's faces are the surface; a coat over it is not modelled"
                        .into(),
                ));
            }
        }
        let Optics::Layers(layers) = &self.optics else {
            return Ok(());
        };
        if layers.is_empty() {
            return Err(error("layers".into(), "the stack is empty".into()));
        }
        for (i, layer) in layers.iter().enumerate() {
            let at = |name: &str| format!("layers[{i}].{name}");
            for (name, values) in [("sigma_a", layer.sigma_a), ("sigma_s", layer.sigma_s)] {
                if let Some(v) = values.iter().find(|v| !v.is_finite() || **v < 0.0) {
                    return Err(error(
                        at(name),
                        format!("must be finite and non-negative (1/mm), got {v}"),
                    ));
                }
            }
            if let Some(c) = (0..3).find(|&c| layer.sigma_a[c] + layer.sigma_s[c] <= 0.0) {
                return Err(error(
                    at("sigma_s"),
                    format!(
                        "channel {c} neither scatters nor absorbs; diffusion needs sigma_a + sigma_s > 0"
                    ),
                ));
            }
            if !(layer.g.is_finite() && layer.g > -1.0 && layer.g < 1.0) {
                return Err(error(
                    at("g"),
                    format!("must lie strictly between -1 and 1, got {}", layer.g),
                ));
            }
            if !(layer.ior.is_finite() && layer.ior > 0.0) {
                return Err(error(
                    at("ior"),
                    format!("must be a positive finite index, got {}", layer.ior),
                ));
            }
            match layer.thickness_mm {
                Some(t) if !(t.is_finite() && t > 0.0) => {
                    return Err(error(
                        at("thickness_mm"),
                        format!("must be positive and finite (mm), got {t}"),
                    ));
                }
                None if i + 1 < layers.len() => {
                    return Err(error(
                        at("thickness_mm"),
                        format!(
                            "missing: only the last layer may be semi-infinite, and this is layer {i} of {}",
                            layers.len()
                        ),
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The index of refraction light enters through: the top layer's (1.3
    /// for a measured Gaussian profile, which carries none).
    pub fn entry_index(&self) -> f64 {
        if let Some(coat) = self.coat_ior {
            return coat;
        }
        match &self.optics {
            Optics::Layers(layers) => layers.first().map_or(1.3, |l| l.ior),
            Optics::Gaussians(_) => 1.3,
        }
    }

    /// The shortest transport mean free path 1/σt' of the top layer over
    /// the channels, mm (for a measured Gaussian profile, its narrowest
    /// spread): the finest spacing the material's light transport resolves.
    pub fn finest_mean_free_path_mm(&self) -> f64 {
        match &self.optics {
            Optics::Layers(layers) => (0..3)
                .map(|c| layers[0].medium(c).mean_free_path())
                .fold(f64::INFINITY, f64::min),
            Optics::Gaussians(g) => g
                .terms
                .iter()
                .flatten()
                .map(|&(_, v)| v.sqrt())
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The layers, or `None` for a measured Gaussian profile.
    pub fn layers(&self) -> Option<&[Layer]> {
        match &self.optics {
            Optics::Layers(l) => Some(l),
            Optics::Gaussians(_) => None,
        }
    }
}

/// A material file as written (the layout [`Material::from_toml`]
/// documents). Keys outside it are refused, so a misspelt one is an error
/// that names it rather than a silent default.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    /// Name for reports; absent, the file's stem.
    name: Option<String>,
    /// Index of a coat over the top layer; absent, none.
    coat_ior: Option<Number>,
    /// RMS facet slope of the surface; absent, smooth.
    roughness: Option<Number>,
    /// The `[[layers]]` tables, top down; absent is an error said after
    /// parsing, with what a material needs.
    layers: Option<LayerList>,
}

/// One `[[layers]]` table. The coefficients are optional here only so that
/// a missing one is reported with its full path (serde would name the
/// table, not the key); the physical checks follow in
/// [`Material::validate`].
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a table of sigma_a, sigma_s, g, ior, thickness_mm and model"
)]
struct LayerFile {
    /// σa, 1/mm.
    sigma_a: Option<Coefficient>,
    /// σs, 1/mm.
    sigma_s: Option<Coefficient>,
    /// Henyey–Greenstein g [default: 0].
    g: Option<Number>,
    /// Refractive index [default: 1.3].
    ior: Option<Number>,
    /// Thickness in mm [default: semi-infinite].
    thickness_mm: Option<Number>,
    /// How the layer is solved: "diffusion" [default] or "stam" (top
    /// layer only).
    model: Option<String>,
}

/// The `layers` array, with an expectation that tells the writer of
/// `layers = 3` to use `[[layers]]` (serde's own says only "a sequence").
struct LayerList(Vec<LayerFile>);

impl<'de> Deserialize<'de> for LayerList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Tables;
        impl<'de> Visitor<'de> for Tables {
            type Value = LayerList;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of tables ([[layers]])")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<LayerList, A::Error> {
                let mut layers = Vec::with_capacity(seq.size_hint().unwrap_or(0));
                while let Some(layer) = seq.next_element()? {
                    layers.push(layer);
                }
                Ok(LayerList(layers))
            }
        }
        deserializer.deserialize_seq(Tables)
    }
}

/// A coefficient per channel, written as one number for all three or as
/// `[r, g, b]`. Deserialized by hand rather than as an untagged enum so a
/// wrong value says what was expected instead of "did not match any
/// variant".
struct Coefficient(Rgb);

impl<'de> Deserialize<'de> for Coefficient {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Channels;
        impl<'de> Visitor<'de> for Channels {
            type Value = Coefficient;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or [r, g, b] (1/mm)")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Coefficient, E> {
                Ok(Coefficient([x; 3]))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Coefficient, E> {
                Ok(Coefficient([x as f64; 3]))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Coefficient, E> {
                Ok(Coefficient([x as f64; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Coefficient, A::Error> {
                let mut channels = Vec::with_capacity(3);
                while let Some(Number(x)) = seq.next_element()? {
                    channels.push(x);
                }
                match channels[..] {
                    [r, g, b] => Ok(Coefficient([r, g, b])),
                    _ => Err(de::Error::custom(format!(
                        "needs 3 entries [r, g, b], got {}",
                        channels.len()
                    ))),
                }
            }
        }
        deserializer.deserialize_any(Channels)
    }
}

/// A number, integer or float (TOML tells them apart; a coefficient does
/// not), with "a number" as what a wrong value should have been.
struct Number(f64);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Any;
        impl Visitor<'_> for Any {
            type Value = Number;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Number, E> {
                Ok(Number(x))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Number, E> {
                Ok(Number(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Number, E> {
                Ok(Number(x as f64))
            }
        }
        deserializer.deserialize_any(Any)
    }
}
