//! The Monte Carlo profile's tallies kept on disk, so a material is
//! simulated once: a file per simulation in the user's cache folder, named
//! by a hash of everything that decides the tallies (the layers, photons,
//! seed, bins, interaction limit and this code's version), and holding that
//! key in full, so a collision or a stale file is simulated anew rather than
//! trusted. A cache that cannot be read or written costs time, never a bake.

use sssbake_profile::Material;
use sssbake_profile::models::monte_carlo::profile::{
    MonteCarloProfile, ProfileSettings, tallies_are_physical,
};
use sssbake_profile::models::monte_carlo::{MonteCarlo, Settings, simulate};
use std::path::{Path, PathBuf};

/// The environment variable naming the cache folder (else the user's
/// cache folder: `$XDG_CACHE_HOME/sssbake`, `~/.cache/sssbake`, or
/// `%LOCALAPPDATA%\sssbake`).
pub const CACHE_DIR_ENV: &str = "SSSBAKE_CACHE_DIR";

/// Changes whenever the simulation or its tallies change meaning without
/// the crate's version changing.
const FORMAT: u32 = 2;

/// The name the tallies' files start with.
const KIND: &str = "montecarlo";

/// The cache folder, if there is one.
pub fn cache_dir() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = var(CACHE_DIR_ENV) {
        return Some(dir.into());
    }
    if let Some(dir) = var("XDG_CACHE_HOME") {
        return Some(PathBuf::from(dir).join("sssbake"));
    }
    if let Some(dir) = var("LOCALAPPDATA") {
        return Some(PathBuf::from(dir).join("sssbake"));
    }
    var("HOME").map(|home| PathBuf::from(home).join(".cache").join("sssbake"))
}

/// Everything that decides a simulation's tallies, as text.
fn key_text(material: &Material, simulation: &Settings) -> Option<String> {
    Some(format!(
        "sssbake {} montecarlo format {FORMAT}\nlayers {:?}\nphotons {} seed {} max_interactions {}\nedges {:?}",
        env!("CARGO_PKG_VERSION"),
        material.layers()?,
        simulation.photons,
        simulation.seed,
        simulation.max_interactions,
        simulation.edges_mm,
    ))
}

/// FNV-1a, 64 bits: stable across builds and platforms, unlike std's hasher.
pub(crate) fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A cache file: the key in full and what it keys.
#[derive(serde::Serialize, serde::Deserialize)]
struct Entry<T> {
    key: String,
    value: T,
}

/// The file `key` is kept in under `kind` (`montecarlo`, `empirical`) in
/// `dir`.
pub(crate) fn file_for(dir: &Path, kind: &str, key: &str) -> PathBuf {
    dir.join(format!("{kind}-{:016x}.json", fnv1a(key)))
}

/// What `compute` makes, read from `dir` when kept there under `kind` and
/// `key` before and still `sound`, else computed and kept there; with
/// `dir` `None`, computed every time. A cache that cannot be written only
/// costs the next bake time.
pub(crate) fn cached<T: serde::Serialize + serde::de::DeserializeOwned>(
    dir: Option<&Path>,
    kind: &str,
    key: String,
    sound: impl Fn(&T) -> bool,
    compute: impl FnOnce() -> T,
) -> T {
    let path = dir.map(|d| file_for(d, kind, &key));
    if let Some(value) = path.as_deref().and_then(|p| read(p, &key, &sound)) {
        return value;
    }
    let value = compute();
    if let Some(path) = &path {
        let _ = write(path, &Entry { key, value: &value });
    }
    value
}

/// The Monte Carlo profile of `material` (`None` for a material without
/// layers), its tallies read from `dir` when simulated before, else
/// simulated and stored there; with `dir` `None`, simulated every time.
pub fn monte_carlo_profile(
    material: &Material,
    settings: &ProfileSettings,
    dir: Option<&Path>,
) -> Option<MonteCarloProfile> {
    monte_carlo_tallies(material, settings, dir).map(MonteCarloProfile::from_tallies)
}

/// The Monte Carlo simulation's tallies of `material`, kept as
/// [`monte_carlo_profile`] keeps them, without the profile's smoothing
/// fit: a reader of the tallies alone (a slab rung) would otherwise fit
/// six sums of Gaussians it never reads.
pub fn monte_carlo_tallies(
    material: &Material,
    settings: &ProfileSettings,
    dir: Option<&Path>,
) -> Option<MonteCarlo> {
    let simulation = settings.simulation(material);
    let key = key_text(material, &simulation)?;
    let layers = material.layers()?;
    Some(cached(dir, KIND, key, tallies_are_physical, || {
        simulate(layers, &simulation)
    }))
}

/// The path the tallies of `material` under `settings` are kept at in `dir`.
pub fn cache_file(material: &Material, settings: &ProfileSettings, dir: &Path) -> Option<PathBuf> {
    let key = key_text(material, &settings.simulation(material))?;
    Some(file_for(dir, KIND, &key))
}

fn read<T: serde::de::DeserializeOwned>(
    path: &Path,
    key: &str,
    sound: impl Fn(&T) -> bool,
) -> Option<T> {
    let text = std::fs::read_to_string(path).ok()?;
    let entry: Entry<T> = serde_json::from_str(&text).ok()?;
    (entry.key == key && sound(&entry.value)).then_some(entry.value)
}

/// Writes beside the target and renames, so no reader sees half a file.
fn write(path: &Path, entry: &impl serde::Serialize) -> std::io::Result<()> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)?;
    }
    let text = serde_json::to_string(entry).map_err(std::io::Error::other)?;
    let partial = path.with_extension(format!("json.{}.partial", std::process::id()));
    std::fs::write(&partial, text)?;
    std::fs::rename(&partial, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&partial);
    })
}
