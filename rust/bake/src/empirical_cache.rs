//! The empirical model's fitted slices kept on disk, beside the Monte Carlo
//! tallies (`crate::monte_carlo_cache`): a file per material channel's
//! optics (α, g, η), named by a hash of everything that decides the fit
//! (the optics, photons, seed, grid and this code's version) and holding
//! that key in full, so a stale or colliding file is fitted anew. A slice
//! does not depend on σt, so media that differ only in scale share it.
//! The oblique-incidence tallies of each channel
//! ([`sssbake_profile::models::empirical::oblique`]) are kept the same way, keyed
//! by the same optics and annuli.

use crate::monte_carlo_cache::{cached, file_for};
use sssbake_profile::Material;
use sssbake_profile::models::empirical::kernel::ObliqueKernel;
use sssbake_profile::models::empirical::oblique::{DEFAULT_OBLIQUE_PHOTONS, ObliqueSlice};
use sssbake_profile::models::empirical::{EmpiricalProfile, EmpiricalSettings, Slice, SliceOptics};
use std::path::{Path, PathBuf};

/// Changes whenever the simulation or the fit change meaning without the
/// crate's version changing.
const FORMAT: u32 = 3;

/// The name the slices' files start with.
const KIND: &str = "empirical";
/// The name the oblique tallies' files start with.
const OBLIQUE_KIND: &str = "empirical-oblique";

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

/// The oblique-incidence kernel of `material` over its normal-incidence
/// `profile`, each channel's tallies ([`DEFAULT_OBLIQUE_PHOTONS`] photons
/// per incidence node, the seed of `settings`) read from `dir` when
/// simulated before, else simulated and stored there.
pub fn empirical_oblique_kernel(
    material: &Material,
    profile: &EmpiricalProfile,
    settings: &EmpiricalSettings,
    dir: Option<&Path>,
) -> Result<ObliqueKernel, String> {
    let top = material
        .layers()
        .and_then(|l| l.first())
        .ok_or("a measured sum of Gaussians has no optical coefficients")?;
    let oblique = [0, 1, 2].map(|c| {
        let optics = SliceOptics::of(top, c);
        let edges = profile.slices()[c].edges_mfp.clone();
        let key = format!(
            "sssbake {} empirical oblique format {FORMAT}\noptics {optics:?}\nedges {edges:?}\nphotons {DEFAULT_OBLIQUE_PHOTONS} seed {}\nchannel {c}",
            env!("CARGO_PKG_VERSION"),
            settings.seed,
        );
        cached(dir, OBLIQUE_KIND, key, oblique_is_physical, || {
            ObliqueSlice::simulate(optics, edges, DEFAULT_OBLIQUE_PHOTONS, settings.seed, c as u64)
        })
    });
    ObliqueKernel::new(material, profile, &oblique)
}

/// True when every tallied harmonic is finite and every mean non-negative.
fn oblique_is_physical(slice: &ObliqueSlice) -> bool {
    slice.nodes.iter().all(|n| {
        n.harmonics
            .iter()
            .all(|m| m.iter().all(|v| v.is_finite()) && m[0] >= 0.0)
    })
}
