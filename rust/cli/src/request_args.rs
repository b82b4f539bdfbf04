//! The options `bake`, `plan` and `report` share, made from the library's
//! settings ([`sssbake_io::settings::SETTINGS`]): each setting is a flag
//! with its doc, its default and its range, and what is given becomes the
//! library's [`BakeOptions`]. Nothing here restates a setting.

use clap::builder::{PossibleValuesParser, TypedValueParser, ValueParser};
use clap::{Arg, ArgAction, ArgMatches, Command};
use serde_json::Value;
use sssbake::{BakeRequest, Error, Scene};
use sssbake_io::BakeOptions;
use sssbake_io::settings::{Kind, Part, SETTINGS, Setting};
use std::path::PathBuf;

/// A parser accepting the names `names` and parsing them as `T`.
pub fn named<T>(names: &'static [&'static str]) -> impl TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    PossibleValuesParser::new(names).try_map(|name| name.parse::<T>())
}

/// Options shared by the commands that bake.
#[derive(clap::Args, Clone, Debug)]
pub struct RequestArgs {
    /// The scene: .gltf, .glb, .usd, .usda, .usdc or .usdz.
    pub input: PathBuf,
    /// The bake's settings.
    #[command(flatten)]
    pub settings: Settings<false>,
    /// Worker threads [default: every core].
    #[arg(long)]
    pub threads: Option<usize>,
}

impl RequestArgs {
    /// Reads the scene, the materials and the images, and makes the request.
    pub fn load(&self) -> Result<(Scene, BakeRequest), Error> {
        if let Some(threads) = self.threads {
            // Only the first call sets the pool; later ones keep it.
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.max(1))
                .build_global();
        }
        self.settings.options.load(&self.input)
    }
}

/// The settings as flags: those of how the maps are written when `WRITING`,
/// the others when not.
#[derive(Clone, Debug, Default)]
pub struct Settings<const WRITING: bool> {
    /// What the flags gave; the rest is `None`, the library's default.
    pub options: BakeOptions,
}

impl<const WRITING: bool> Settings<WRITING> {
    fn chosen() -> impl Iterator<Item = &'static Setting> {
        SETTINGS
            .iter()
            .filter(|s| (s.part == Part::Writing) == WRITING)
    }
}

impl<const WRITING: bool> clap::Args for Settings<WRITING> {
    fn augment_args(command: Command) -> Command {
        command.args(Self::chosen().map(flag))
    }

    fn augment_args_for_update(command: Command) -> Command {
        Self::augment_args(command)
    }
}

impl<const WRITING: bool> clap::FromArgMatches for Settings<WRITING> {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut given = serde_json::Map::new();
        for setting in Self::chosen() {
            let value = match setting.kind {
                Kind::Switch => matches.get_flag(setting.name).then_some(Value::Bool(true)),
                Kind::Names | Kind::Choices { .. } => matches
                    .get_many::<Value>(setting.name)
                    .map(|values| Value::Array(values.cloned().collect())),
                _ => matches.get_one::<Value>(setting.name).cloned(),
            };
            if let Some(value) = value {
                given.insert(setting.name.to_string(), value);
            }
        }
        let options = serde_json::from_value(Value::Object(given))
            .map_err(|e| clap::Error::raw(clap::error::ErrorKind::InvalidValue, e))?;
        Ok(Settings { options })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

/// `setting` as a flag: its doc and default as the help, its values checked
/// by the setting itself.
fn flag(setting: &'static Setting) -> Arg {
    let numeric = matches!(setting.kind, Kind::Count { .. } | Kind::Number { .. });
    let default = match (&setting.kind, &setting.default) {
        (Kind::Switch, _) => String::new(),
        (_, Some(_)) if numeric && !setting.unit.is_empty() => {
            format!(" [default: {} {}]", setting.default_text, setting.unit)
        }
        _ => format!(" [default: {}]", setting.default_text),
    };
    let doc = setting.doc.strip_suffix('.').unwrap_or(&setting.doc);
    let arg = Arg::new(setting.name)
        .long(setting.flag())
        .help(format!("{doc}{default}"));
    match &setting.kind {
        Kind::Switch => arg.action(ArgAction::SetTrue),
        Kind::Choice { names, .. } => arg
            .value_name(setting.name.to_uppercase())
            .value_parser(choices(names)),
        Kind::Choices { names, .. } => arg
            .value_name(setting.name.to_uppercase())
            .value_parser(choices(names))
            .value_delimiter(',')
            .action(ArgAction::Append),
        Kind::Names => arg
            .value_name("NAME")
            .action(ArgAction::Append)
            .value_parser(ValueParser::new(|text: &str| {
                Ok::<_, String>(Value::String(text.into()))
            })),
        kind => arg
            .value_name(match kind {
                Kind::File => "FILE".to_string(),
                Kind::Size => "SIZE".to_string(),
                _ => setting.name.to_uppercase(),
            })
            .allow_negative_numbers(true)
            .value_parser(ValueParser::new(move |text: &str| setting.parse(text))),
    }
}

/// A parser of `names` giving each as a JSON string.
fn choices(names: &[&'static str]) -> impl TypedValueParser<Value = Value> {
    PossibleValuesParser::new(names.to_vec()).map(Value::String)
}
