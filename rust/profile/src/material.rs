//! Materials: a stack of layers with optical coefficients, or a measured sum
//! of Gaussians; read from TOML files and validated with errors that name the
//! file and the field.

use crate::Rgb;
use crate::gaussians::SumOfGaussians;
use crate::medium::Medium;
use std::fmt;
use std::path::Path;

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

    /// Parses and validates TOML text; `source` names it in errors.
    ///
    /// ```toml
    /// name = "two-layer skin"        # optional
    /// [[layers]]
    /// sigma_a = [0.032, 0.17, 0.48]  # 1/mm, a number or [r, g, b]
    /// sigma_s = 0.74                 # 1/mm
    /// g = 0.0                        # optional, default 0
    /// ior = 1.3                      # optional, default 1.3
    /// thickness_mm = 0.25            # absent: semi-infinite
    /// ```
    pub fn from_toml(text: &str, source: &str, default_name: &str) -> Result<Self, MaterialError> {
        let error = |field: &str, message: String| MaterialError {
            source: source.to_string(),
            field: field.to_string(),
            message,
        };
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            error("", format!("not valid TOML: {}", e.message().trim()))
        })?;
        for key in table.keys() {
            if key != "name" && key != "layers" {
                return Err(error(
                    key,
                    "unknown field (expected `name` or `layers`)".into(),
                ));
            }
        }
        let name = match table.get("name") {
            None => default_name.to_string(),
            Some(toml::Value::String(s)) => s.clone(),
            Some(_) => return Err(error("name", "must be a string".into())),
        };
        let layers = match table.get("layers") {
            None => {
                return Err(error(
                    "layers",
                    "missing: a material needs at least one [[layers]] table".into(),
                ));
            }
            Some(toml::Value::Array(items)) => items,
            Some(_) => {
                return Err(error(
                    "layers",
                    "must be an array of tables ([[layers]])".into(),
                ));
            }
        };
        let mut parsed = Vec::with_capacity(layers.len());
        for (i, item) in layers.iter().enumerate() {
            let prefix = format!("layers[{i}]");
            let toml::Value::Table(fields) = item else {
                return Err(error(&prefix, "must be a table".into()));
            };
            parsed.push(parse_layer(fields, &prefix).map_err(|(f, m)| error(&f, m))?);
        }
        let material = Material {
            name,
            optics: Optics::Layers(parsed),
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

fn parse_layer(fields: &toml::Table, prefix: &str) -> Result<Layer, (String, String)> {
    let at = |name: &str| format!("{prefix}.{name}");
    const KNOWN: [&str; 5] = ["sigma_a", "sigma_s", "g", "ior", "thickness_mm"];
    if let Some(key) = fields.keys().find(|k| !KNOWN.contains(&k.as_str())) {
        return Err((
            at(key),
            format!("unknown field (expected one of {})", KNOWN.join(", ")),
        ));
    }
    let rgb = |name: &str| -> Result<Rgb, (String, String)> {
        match fields.get(name) {
            None => Err((at(name), "missing (1/mm, a number or [r, g, b])".into())),
            Some(value) => {
                if let Some(x) = number(value) {
                    return Ok([x; 3]);
                }
                match value {
                    toml::Value::Array(items) if items.len() == 3 => {
                        let xs: Option<Vec<f64>> = items.iter().map(number).collect();
                        xs.map(|v| [v[0], v[1], v[2]])
                            .ok_or_else(|| (at(name), "every entry must be a number".into()))
                    }
                    toml::Value::Array(items) => Err((
                        at(name),
                        format!("needs 3 entries [r, g, b], got {}", items.len()),
                    )),
                    _ => Err((at(name), "must be a number or [r, g, b]".into())),
                }
            }
        }
    };
    let scalar = |name: &str, default: Option<f64>| -> Result<Option<f64>, (String, String)> {
        match fields.get(name) {
            None => Ok(default),
            Some(v) => number(v)
                .map(Some)
                .ok_or_else(|| (at(name), "must be a number".into())),
        }
    };
    Ok(Layer {
        sigma_a: rgb("sigma_a")?,
        sigma_s: rgb("sigma_s")?,
        g: scalar("g", Some(0.0))?.unwrap_or(0.0),
        ior: scalar("ior", Some(1.3))?.unwrap_or(1.3),
        thickness_mm: scalar("thickness_mm", None)?,
    })
}

fn number(value: &toml::Value) -> Option<f64> {
    match value {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}
