//! The empirical model's fitted slices kept on disk, beside the Monte Carlo
//! tallies (`crate::monte_carlo_cache`): a file per material channel's
//! optics (α, g, η), named by a hash of everything that decides the fit
//! (the optics, photons, seed, grid and this code's version) and holding
//! that key in full, so a stale or colliding file is fitted anew. A slice
//! does not depend on σt, so media that differ only in scale share it.

use crate::monte_carlo_cache::{cached, file_for};
use sssbake_profile::Material;
use sssbake_profile::empirical::{EmpiricalProfile, EmpiricalSettings, Slice, SliceOptics};
use std::path::{Path, PathBuf};

/// Changes whenever the simulation or the fit change meaning without the
/// crate's version changing.
const FORMAT: u32 = 2;

/// The name the slices' files start with.
const KIND: &str = "empirical";

/// Everything that decides one channel's slice, as text.
fn key_text(optics: &SliceOptics, settings: &EmpiricalSettings, channel: usize) -> String {
    format!(
        "sssbake {} empirical format {FORMAT}\noptics {optics:?}\nsettings {settings:?}\nchannel {channel}",
        env!("CARGO_PKG_VERSION"),
    )
}

/// The path channel `channel`'s slice of `material` is kept at in `dir`
/// (`None` for a material without layers).
pub fn cache_file(
    material: &Material,
    settings: &EmpiricalSettings,
    channel: usize,
    dir: &Path,
) -> Option<PathBuf> {
    let top = material.layers()?.first()?;
    let key = key_text(&SliceOptics::of(top, channel), settings, channel);
    Some(file_for(dir, KIND, &key))
}

/// The empirical profile of `material`, its slices read from `dir` when
/// fitted before, else simulated, fitted and stored there; with `dir`
/// `None`, fitted every time. `Err` says why the model does not apply.
pub fn empirical_profile(
    material: &Material,
    settings: &EmpiricalSettings,
    dir: Option<&Path>,
) -> Result<EmpiricalProfile, String> {
    let Some(top) = material.layers().and_then(|l| l.first()) else {
        // The library names the reason.
        return EmpiricalProfile::simulate(material, settings);
    };
    let slices = [0, 1, 2].map(|c| {
        let optics = SliceOptics::of(top, c);
        let key = key_text(&optics, settings, c);
        cached(dir, KIND, key, slice_is_physical, || {
            Slice::simulate(optics, settings, c as u64)
        })
    });
    EmpiricalProfile::from_slices(material, slices)
}

/// True when every fitted lobe's parameters are finite and non-negative.
fn slice_is_physical(slice: &Slice) -> bool {
    slice.fits.iter().all(|f| {
        let k = &f.lobe;
        [
            k.k_s, k.k_e, k.k_c, k.a_plus, k.a_minus, k.b_plus, k.b_minus,
        ]
        .iter()
        .all(|v| v.is_finite() && *v >= 0.0)
    })
}
