//! One slab's reflectance and transmittance by the multipole, summed in real
//! space with as many image pairs as the requested accuracy needs.

use crate::diffusion::slab::SlabChannel;
use crate::material::Layer;
use crate::models::layered::{Stack, tabulate};
use crate::models::tabulated::Tabulated;
use crate::profile::Profile;
use crate::{Rgb, rgb_map};

/// Relative accuracy of the totals used to choose the pole count.
pub const DEFAULT_ACCURACY: f64 = 1e-6;

/// A single slab (or semi-infinite layer) under air, with air below.
#[derive(Clone, Debug)]
pub struct Multipole {
    slabs: [SlabChannel; 3],
    /// Image pairs per channel; `None` where the series converges too
    /// slowly and its closed frequency form is tabulated instead.
    pairs: [Option<usize>; 3],
    /// Largest error the left-out images can make in R(r) or T(r), per channel.
    truncation: [f64; 3],
    table: Option<Tabulated>,
}

impl Multipole {
    /// The multipole of `layer` with pole counts chosen so that the summed
    /// totals are within `accuracy` (relative) of the exact ones.
    pub fn new(layer: &Layer, accuracy: f64) -> Self {
        Self::with_roughness(layer, 0.0, accuracy)
    }

    /// [`Self::new`] with faces against air of RMS facet slope `roughness`
    /// (Donner & Jensen 2005 eq. 24 sets their extrapolation distances).
    pub fn with_roughness(layer: &Layer, roughness: f64, accuracy: f64) -> Self {
        let stack = Stack::with_roughness(std::slice::from_ref(layer), roughness);
        let slabs = [0, 1, 2].map(|c| stack.channel(c)[0].clone());
        let pairs = [0, 1, 2].map(|c| slabs[c].pole_pairs_for(accuracy));
        let table = pairs.iter().any(Option::is_none).then(|| {
            tabulate("multipole", stack.length_scales(), |c, k| {
                slabs[c].image_diffuse(k)
            })
        });
        let truncation = [0, 1, 2].map(|c| pairs[c].map_or(0.0, |n| slabs[c].truncation_bound(n)));
        Self {
            slabs,
            pairs,
            truncation,
            table,
        }
    }

    /// Image pairs summed per channel (`None`: tabulated from the series'
    /// closed frequency form).
    pub fn pole_pairs(&self) -> [Option<usize>; 3] {
        self.pairs
    }

    fn per_channel(
        &self,
        poles: impl Fn(&SlabChannel, usize) -> f64,
        table: impl Fn(&Tabulated) -> Rgb,
    ) -> Rgb {
        // The table exists exactly when some channel has no pole count.
        let tabulated = self.table.as_ref().map_or([0.0; 3], table);
        rgb_map(|c| match self.pairs[c] {
            // A value negative by less than what the left-out images can
            // contribute is zero within the series' accuracy.
            Some(n) => match poles(&self.slabs[c], n) {
                v if v < 0.0 && -v <= self.truncation[c] => 0.0,
                v => v,
            },
            None => tabulated[c],
        })
    }
}

impl Profile for Multipole {
    fn model(&self) -> &'static str {
        "multipole"
    }

    fn reflectance(&self, r: f64) -> Rgb {
        self.per_channel(|s, n| s.reflectance(r, n), |t| t.reflectance(r))
    }

    fn transmittance(&self, r: f64) -> Rgb {
        self.per_channel(|s, n| s.transmittance(r, n), |t| t.transmittance(r))
    }

    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| self.slabs[c].image_totals().reflectance)
    }

    fn total_transmittance(&self) -> Rgb {
        rgb_map(|c| self.slabs[c].image_totals().transmittance)
    }

    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| self.slabs[c].image_diffuse(k).reflectance))
    }

    fn ballistic_reflectance(&self) -> Rgb {
        rgb_map(|c| self.slabs[c].ballistic().down.reflectance)
    }

    fn ballistic_transmittance(&self) -> Rgb {
        rgb_map(|c| self.slabs[c].ballistic().down.transmittance)
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        self.per_channel(
            |s, n| s.enclosed_reflectance(r, n),
            |t| t.enclosed_reflectance(r),
        )
    }

    fn length_scale(&self) -> Rgb {
        rgb_map(|c| {
            let (shortest, longest) = self.slabs[c].length_scales();
            (shortest * longest).sqrt()
        })
    }
}
