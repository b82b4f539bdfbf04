//! A stack under a Stam top layer: the epidermis solved by discrete
//! ordinates ([`crate::models::stam::epidermis`]), the layers below by diffusion
//! ([`crate::models::layered`]), joined per spatial frequency by the stack algebra
//! of Donner & Jensen 2005 (Mikkelsen 2.7.3) with the epidermis as a slab
//! of no lateral spread.
//!
//! What is approximated, and why: the epidermis's lateral spread is taken
//! as zero (a few hundredths of a millimetre against the dermis's
//! millimetres); the light it passes down enters the layers below as the
//! diffuse light any lower layer of a stack receives, whatever its angles;
//! and the light coming up meets it as Lambertian light (what the
//! diffusion layers send). Its bottom face is in optical contact with the
//! layer below ([`crate::models::stam::contact`]). The light from above
//! is counted after it crossed the epidermis (the bake's entry term is the
//! epidermis's T(θi) per light), so R(r) is the exitance into air per
//! unit of light that reached the layers below.

use crate::diffusion::slab::SideResponse;
use crate::diffusion::split::{Split, SplitSlab, combine};
use crate::material::{Material, TopLayer};
use crate::models::layered::{Stack, tabulate};
use crate::models::stam::epidermis::Epidermis;
use crate::models::tabulated::Tabulated;
use crate::profile::Profile;
use crate::{Rgb, rgb_map};

/// The profiles of a material whose top layer is declared stam.
#[derive(Clone, Debug)]
pub struct StamTopped {
    epidermis: Epidermis,
    below: Stack,
    table: Tabulated,
}

impl StamTopped {
    /// Solves `material`'s top layer by Stam and tabulates the stack under
    /// it. Refuses a material whose top layer is not declared stam, and
    /// one with nothing under it (no light would scatter back to bake).
    pub fn new(material: &Material) -> Result<Self, String> {
        if material.top_layer != TopLayer::Stam {
            return Err(
                "the top layer is not declared stam (`model = \"stam\"` in layers[0])".into(),
            );
        }
        let Some(layers) = material.layers() else {
            return Err("a measured sum of Gaussians has no layers".into());
        };
        if layers.len() < 2 {
            return Err(
                "a stam top layer needs a layer under it to scatter into (add a [[layers]] table)"
                    .into(),
            );
        }
        let epidermis = Epidermis::solve(material)?;
        let below = Stack::with_roughness(layers, material.roughness).without_top();
        let table = tabulate("stam", below.length_scales(), |c, k| {
            joined(&epidermis, &below, c, k).map(|s| s.diffuse).down
        });
        Ok(Self {
            epidermis,
            below,
            table,
        })
    }

    /// The epidermis as solved.
    pub fn epidermis(&self) -> &Epidermis {
        &self.epidermis
    }

    /// The joined response in channel `c` at angular frequency `k` (rad/mm).
    pub fn split_response(&self, c: usize, k: f64) -> SplitSlab {
        joined(&self.epidermis, &self.below, c, k)
    }

    fn at_rest(&self, c: usize) -> SideResponse {
        self.split_response(c, 0.0).map(|s: Split| s.ballistic).down
    }
}

fn joined(epidermis: &Epidermis, below: &Stack, c: usize, k: f64) -> SplitSlab {
    combine(epidermis.split_slab(c), below.split_response(c, k))
}

impl Profile for StamTopped {
    fn model(&self) -> &'static str {
        "stam"
    }
    fn reflectance(&self, r: f64) -> Rgb {
        self.table.reflectance(r)
    }
    fn transmittance(&self, r: f64) -> Rgb {
        self.table.transmittance(r)
    }
    fn total_reflectance(&self) -> Rgb {
        self.table.total_reflectance()
    }
    fn total_transmittance(&self) -> Rgb {
        self.table.total_transmittance()
    }
    fn ballistic_reflectance(&self) -> Rgb {
        rgb_map(|c| self.at_rest(c).reflectance)
    }
    fn ballistic_transmittance(&self) -> Rgb {
        rgb_map(|c| self.at_rest(c).transmittance)
    }
    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| {
            self.split_response(c, k).down.reflectance.diffuse
        }))
    }
    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        self.table.enclosed_reflectance(r)
    }
    fn length_scale(&self) -> Rgb {
        self.table.length_scale()
    }
}
