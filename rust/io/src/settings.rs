//! Every bake setting, once: its name, what values it takes, its unit, its
//! default and its range, beside its doc. [`BakeOptions`] (a manifest's
//! table, the Python keywords, the C ABI's keys) is made from this list, and
//! the doors read it to build their own forms of it: the command line's
//! flags, the Python stubs, the Blender properties and the docs' tables. A
//! default or a range here is the library's own, read from where the
//! library defines it.

use crate::FolderOptions;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use sssbake::irradiance::bounce::MOST_BOUNCES;
use sssbake::limits::size_text;
use sssbake::materials::FALLBACK_PRESET;
use sssbake::request::{BakeRequest, MAX_RESOLUTION};
use sssbake::transport::light_check::MOST_TEXELS;
use sssbake::transport::texture_space::MAX_GAUSSIANS;
use sssbake::transport::walk::MOST_SAMPLES;
use sssbake::{Method, Output, UvPolicy};
use sssbake_profile::boundary::rough::MAX_ROUGHNESS;
use sssbake_profile::model::Model;
use std::path::PathBuf;
use std::sync::LazyLock;

/// What values a setting takes.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Kind {
    /// A whole number from `min` to `max`.
    Count {
        /// The least value.
        min: u64,
        /// The greatest value.
        max: u64,
    },
    /// A real number in the range; an open end is `None` (unbounded).
    Number {
        /// The least value, or `None`.
        min: Option<f64>,
        /// Whether `min` itself is refused.
        min_exclusive: bool,
        /// The greatest value, or `None`.
        max: Option<f64>,
    },
    /// On or off.
    Switch,
    /// One of `names`.
    Choice {
        /// The names it takes.
        names: Vec<&'static str>,
        /// What each name means, one line each (the library's own words).
        notes: Vec<&'static str>,
    },
    /// Any of `names`, as a list.
    Choices {
        /// The names it takes.
        names: Vec<&'static str>,
        /// What each name means, one line each.
        notes: Vec<&'static str>,
    },
    /// A list of free names (objects).
    Names,
    /// A file's path.
    File,
    /// A size in bytes, written as `16G` or `512M` (binary units).
    Size,
}

/// What part of a bake a setting belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Part {
    /// What to bake, from where, with which material.
    Scene,
    /// How the bake is done, whatever the integrator.
    Bake,
    /// One integrator's own setting.
    Integrator(Method),
    /// How the maps are written (`sssbake bake`, a batch, a host's folder).
    Writing,
}

/// One setting of [`BakeOptions`].
#[derive(Clone, Debug, Serialize)]
pub struct Setting {
    /// Its name in a manifest, in Python and in the C ABI (`--name` with
    /// dashes on the command line, but for `objects`: `--object`, repeated).
    pub name: &'static str,
    /// Its doc, one paragraph.
    pub doc: String,
    /// What values it takes.
    #[serde(flatten)]
    pub kind: Kind,
    /// Its unit, or what it counts; empty for names and switches.
    pub unit: &'static str,
    /// What part of a bake it belongs to.
    pub part: Part,
    /// The library's default, or `None` where there is none to state (then
    /// `default_text` says what happens).
    pub default: Option<Value>,
    /// What a bake does when the setting is left out, in words.
    pub default_text: String,
}

impl Setting {
    /// Its flag on the command line.
    pub fn flag(&self) -> String {
        match self.name {
            "objects" => "object".to_string(),
            name => name.replace('_', "-"),
        }
    }
}

/// The library's request defaults, read once.
fn request() -> &'static BakeRequest {
    static DEFAULTS: LazyLock<BakeRequest> = LazyLock::new(BakeRequest::default);
    &DEFAULTS
}

fn count(min: u64, max: u64) -> Kind {
    Kind::Count { min, max }
}

fn number(min: Option<f64>, min_exclusive: bool, max: Option<f64>) -> Kind {
    Kind::Number {
        min,
        min_exclusive,
        max,
    }
}

/// Every name of the enum `T` with its variant's doc.
fn described<T>() -> (Vec<&'static str>, Vec<&'static str>)
where
    T: strum::VariantArray + strum::EnumMessage + Copy + Into<&'static str>,
{
    T::VARIANTS
        .iter()
        .map(|&v| (v.into(), v.get_documentation().unwrap_or_default().trim()))
        .unzip()
}

fn choice<T>() -> Kind
where
    T: strum::VariantArray + strum::EnumMessage + Copy + Into<&'static str>,
{
    let (names, notes) = described::<T>();
    Kind::Choice { names, notes }
}

/// The presets a bake can name (not those that only describe angles), with
/// what each is.
fn presets() -> Kind {
    let (names, notes) = sssbake_profile::presets::list()
        .into_iter()
        .filter(|(name, _)| !sssbake_profile::presets::ANGULAR_ONLY.contains(name))
        .unzip();
    Kind::Choice { names, notes }
}

/// A default stated as a value, and the same in words (as a flag takes it).
fn stated(value: Value) -> (Option<Value>, String) {
    let text = value_text(&value);
    (Some(value), text)
}

/// A value as a flag or a manifest writes it: names bare, lists with
/// commas, whole numbers without a point, large ones as `3e10`.
pub fn value_text(value: &Value) -> String {
    match value {
        Value::String(s) => s.clone(),
        Value::Array(items) => items.iter().map(value_text).collect::<Vec<_>>().join(","),
        Value::Number(n) if n.is_f64() => {
            let v = n.as_f64().unwrap_or_default();
            if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
                format!("{v:e}")
            } else {
                format!("{v}")
            }
        }
        other => other.to_string(),
    }
}

/// No default value; `text` says what happens instead.
fn unstated(text: &str) -> (Option<Value>, String) {
    (None, text.to_string())
}

/// Joins a field's doc lines into one paragraph.
fn paragraph(lines: &[&str]) -> String {
    lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ")
}

/// Declares [`BakeOptions`] and [`SETTINGS`] from one list: each field's
/// doc, its type, and `kind, unit, part, default` for the schema.
macro_rules! settings {
    ($(
        $(#[doc = $doc:literal])*
        $name:ident : $ty:ty => ($kind:expr, $unit:literal, $part:expr, $default:expr)
    ),* $(,)?) => {
        /// A bake's options, as a manifest, Python or the C ABI gives them;
        /// `None` keeps the library's default. Every field is a [`Setting`]
        /// of [`SETTINGS`].
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct BakeOptions {
            $( $(#[doc = $doc])* pub $name: Option<$ty>, )*
        }

        impl BakeOptions {
            /// These options with every option `self` leaves out taken
            /// from `defaults`.
            pub fn or(&self, defaults: &BakeOptions) -> BakeOptions {
                BakeOptions {
                    $( $name: self.$name.clone().or_else(|| defaults.$name.clone()), )*
                }
            }
        }

        /// Every setting of [`BakeOptions`], in its order.
        pub static SETTINGS: LazyLock<Vec<Setting>> = LazyLock::new(|| {
            vec![$({
                let (default, default_text) = $default;
                Setting {
                    name: stringify!($name),
                    doc: paragraph(&[$($doc),*]),
                    kind: $kind,
                    unit: $unit,
                    part: $part,
                    default,
                    default_text,
                }
            }),*]
        });
    };
}

settings! {
    /// Objects to bake, by name.
    objects: Vec<String> => (Kind::Names, "", Part::Scene, unstated("every object")),
    /// A material preset for every object the sidecar does not name.
    preset: String => (
        presets(), "", Part::Scene,
        (None, format!("the object's own material in the file, else {FALLBACK_PRESET}"))
    ),
    /// A TOML material file for every object the sidecar does not name.
    material: PathBuf => (Kind::File, "", Part::Scene, unstated("none")),
    /// A TOML sidecar naming each object's preset or material file.
    materials: PathBuf => (Kind::File, "", Part::Scene, unstated("none")),
    /// The profile model.
    model: String => (choice::<Model>(), "", Part::Bake, unstated("chosen for the material")),
    /// Texels per side of each map.
    resolution: u32 => (
        count(1, MAX_RESOLUTION.into()), "texels", Part::Bake,
        stated(json!(request().resolution))
    ),
    /// The texture-coordinate set to bake into.
    uv_set: usize => (
        count(0, 255), "", Part::Scene, stated(json!(FolderOptions::default().uv_set))
    ),
    /// What to do with the objects' UVs: `auto` unwraps with xatlas where
    /// they are not usable, `unwrap` always, `keep` bakes into them as they
    /// are.
    uvs: String => (choice::<UvPolicy>(), "", Part::Bake, stated(json!(request().uvs))),
    /// Texels filled beyond each chart's edge, and between the charts of an
    /// unwrap.
    margin: u32 => (
        count(0, MAX_RESOLUTION.into()), "texels", Part::Bake,
        stated(json!(request().margin))
    ),
    /// The maps to make.
    outputs: Vec<String> => (
        {
            let (names, notes) = described::<Output>();
            Kind::Choices { names, notes }
        },
        "",
        Part::Bake,
        stated(json!(request().outputs))
    ),
    /// The integrator, or `auto` to let the library choose and say why.
    method: String => (choice::<Method>(), "", Part::Bake, stated(json!(request().method))),
    /// Octree: the solid angle below which a node is taken whole.
    octree_epsilon: f32 => (
        number(Some(0.0), false, None), "sr", Part::Integrator(Method::Octree),
        stated(json!(request().integrators.octree.epsilon))
    ),
    /// Texture space: Gaussians in the fit (and in a `gaussians` model).
    gaussians: usize => (
        count(1, MAX_GAUSSIANS as u64), "Gaussians", Part::Integrator(Method::Texture),
        stated(json!(request().integrators.texture.gaussians))
    ),
    /// Importance: probes per texel.
    samples: u32 => (
        count(1, u32::MAX.into()), "probes per texel", Part::Integrator(Method::Importance),
        stated(json!(request().integrators.importance.samples))
    ),
    /// Walk: walks per texel and channel.
    walk_samples: u32 => (
        count(2, MOST_SAMPLES.into()), "walks per texel", Part::Integrator(Method::Walk),
        stated(json!(request().integrators.walk.samples))
    ),
    /// Seed of the Monte Carlo of importance sampling and of the walk.
    seed: u64 => (
        count(0, u64::MAX), "", Part::Bake,
        stated(json!(request().integrators.importance.seed))
    ),
    /// Millimetres per scene unit, overriding the file's units.
    unit_scale: f64 => (
        number(Some(0.0), true, None), "mm per scene unit", Part::Scene,
        unstated("the file's own units")
    ),
    /// An image (.exr linear, .png sRGB) in the objects' UV layout used as
    /// the transmitted irradiance instead of the scene's lights.
    irradiance: PathBuf => (Kind::File, "", Part::Scene, unstated("the scene's lights")),
    /// An equirectangular image (.exr) for the scene's environment light.
    environment: PathBuf => (Kind::File, "", Part::Scene, unstated("the scene's own")),
    /// A base colour image (.exr linear, .png sRGB) in the objects' UVs,
    /// applied as C^α before scattering and C^(1−α) after.
    base_color: PathBuf => (Kind::File, "", Part::Scene, unstated("the material's colour")),
    /// α of the colour split (Mikkelsen §3.5): 0 colours after scattering
    /// only, 1 before only.
    colour_split: f32 => (
        number(Some(0.0), false, Some(1.0)), "", Part::Bake,
        stated(json!(request().colour_split))
    ),
    /// Samples per soft light and for the environment, per texel.
    light_samples: u32 => (
        count(1, u32::MAX.into()), "samples per texel", Part::Bake,
        stated(json!(request().light_samples))
    ),
    /// Bounces of the light each object sends onto itself across air (an
    /// eye socket, a fold, an ear), as a path tracer's diffuse bake carries
    /// it; 0 bakes the direct light alone.
    bounces: u32 => (
        count(0, MOST_BOUNCES.into()), "bounces", Part::Bake,
        stated(json!(request().bounces))
    ),
    /// RMS facet slope of every material's surface (Donner & Jensen 2005
    /// §2.4).
    roughness: f64 => (
        number(Some(0.0), false, Some(MAX_ROUGHNESS)), "RMS slope", Part::Bake,
        unstated("each material's own")
    ),
    /// Relative RMSE against the exact sum that `auto` holds each object
    /// to: it estimates its error and moves to a more exact method above it
    /// (0.01 is 1%).
    tolerance: f64 => (
        number(Some(0.0), true, None), "relative RMSE", Part::Bake,
        stated(json!(request().tolerance))
    ),
    /// Texels at which the bake is checked against light itself, a
    /// volumetric random walk through the mesh, reported beside the error
    /// against the exact sum (0 turns the check off).
    light_check: u32 => (
        count(0, MOST_TEXELS.into()), "texels", Part::Bake,
        stated(json!(request().light_check))
    ),
    /// Memory a bake may hold (16G, 512M: binary units); the plan refuses a
    /// bake estimated to need more.
    max_memory: String => (
        Kind::Size, "bytes", Part::Bake,
        stated(json!(size_text(request().limits.max_memory_bytes)))
    ),
    /// Shadow rays, kernel evaluations and probes a bake may take (3e10 is
    /// about an hour of the exact sum on two cores); the plan refuses more.
    max_evaluations: f64 => (
        number(Some(0.0), true, None), "evaluations", Part::Bake,
        stated(json!(request().limits.max_evaluations))
    ),
    /// Write EXRs as 16-bit half floats instead of 32-bit.
    half: bool => (
        Kind::Switch, "", Part::Writing,
        stated(json!(FolderOptions::default().precision == crate::image_writer::Precision::Half))
    ),
    /// Exposure of the PNG previews (the EXRs stay as baked).
    exposure: f32 => (
        number(None, false, None), "stops", Part::Writing,
        stated(json!(FolderOptions::default().exposure))
    ),
}

/// The setting called `name`.
pub fn setting(name: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.name == name)
}

impl BakeOptions {
    /// Refuses an option outside what its [`Setting`] takes, naming it:
    /// every door's options are checked here, before the scene is read
    /// (the library checks the request it makes again).
    pub fn validate(&self) -> Result<(), sssbake::Error> {
        let Value::Object(given) = serde_json::to_value(self).expect("options are plain data")
        else {
            unreachable!("options serialize as a table")
        };
        for setting in SETTINGS.iter() {
            if let Some(value) = given.get(setting.name).filter(|v| !v.is_null()) {
                setting
                    .check(value)
                    .map_err(|message| sssbake::Error::field(setting.name, message))?;
            }
        }
        Ok(())
    }
}

impl Setting {
    /// `text` (as a flag or a C host writes it: `1024`, `0.5`, `octree`,
    /// `subsurface,diffuse`, `16G`, `true`) as this setting's value,
    /// checked against what it takes.
    pub fn parse(&self, text: &str) -> Result<Value, String> {
        let value = match self.kind {
            Kind::Count { .. } => match (text.parse::<u64>(), text.parse::<i64>()) {
                (Ok(v), _) => Value::from(v),
                (_, Ok(v)) => Value::from(v),
                _ => return Err(format!("`{text}` is not a whole number")),
            },
            Kind::Number { .. } => text
                .parse::<f64>()
                .map(Value::from)
                .map_err(|_| format!("`{text}` is not a number"))?,
            Kind::Switch => match text {
                "true" | "1" => Value::Bool(true),
                "false" | "0" => Value::Bool(false),
                _ => return Err(format!("`{text}` is not true or false")),
            },
            Kind::Choices { .. } | Kind::Names => Value::Array(
                text.split(',')
                    .map(|item| Value::String(item.trim().to_string()))
                    .collect(),
            ),
            _ => Value::String(text.to_string()),
        };
        self.check(&value)?;
        Ok(value)
    }

    /// Whether `value` is one this setting takes; if not, why.
    pub fn check(&self, value: &Value) -> Result<(), String> {
        let unknown = |name: &str, names: &[&str]| {
            format!("unknown name `{name}` (one of {})", names.join(", "))
        };
        match &self.kind {
            Kind::Count { min, max } => {
                let outside = |v: &dyn std::fmt::Display| {
                    if *max >= u64::from(u32::MAX) {
                        format!("{v} must be at least {min}")
                    } else {
                        format!("{v} must be between {min} and {max}")
                    }
                };
                if let Some(negative) = value.as_i64().filter(|v| *v < 0) {
                    return Err(outside(&negative));
                }
                let v = value
                    .as_u64()
                    .ok_or_else(|| format!("{value} is not a whole number"))?;
                if v < *min || v > *max {
                    return Err(outside(&v));
                }
            }
            Kind::Number {
                min,
                min_exclusive,
                max,
            } => {
                let v = value
                    .as_f64()
                    .ok_or_else(|| format!("{value} is not a number"))?;
                let below = min.is_some_and(|m| v < m || (*min_exclusive && v == m));
                let above = max.is_some_and(|m| v > m);
                if !v.is_finite() || below || above {
                    let unit = if self.unit.is_empty() {
                        String::new()
                    } else {
                        format!(" ({})", self.unit)
                    };
                    return Err(match (min, max) {
                        (Some(lo), Some(hi)) => format!("{v} must be between {lo} and {hi}{unit}"),
                        (Some(lo), None) if *min_exclusive => {
                            format!("{v} must be a number above {lo}{unit}")
                        }
                        (Some(lo), None) => format!("{v} must be a number of at least {lo}{unit}"),
                        _ => format!("{v} must be a finite number{unit}"),
                    });
                }
            }
            Kind::Choice { names, .. } => {
                let name = value.as_str().unwrap_or_default();
                if !names.contains(&name) {
                    return Err(unknown(name, names));
                }
            }
            Kind::Choices { names, .. } => {
                for item in value.as_array().into_iter().flatten() {
                    let name = item.as_str().unwrap_or_default();
                    if !names.contains(&name) {
                        return Err(unknown(name, names));
                    }
                }
            }
            Kind::Size => {
                sssbake::limits::parse_bytes(value.as_str().unwrap_or_default())?;
            }
            Kind::Switch | Kind::Names | Kind::File => {}
        }
        Ok(())
    }
}
