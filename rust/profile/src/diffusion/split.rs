//! Responses kept in two parts: the light that crossed thin layers without
//! scattering (a delta at r = 0, the same at every frequency) and the
//! diffuse rest. Keeping them apart through the layer algebra means the
//! diffuse part is never found by subtracting a large delta from a large
//! total, which would leave only round-off for the transform to amplify.

use crate::diffusion::slab::{SideResponse, SlabResponse};
use std::ops::{Add, Mul};

/// One response: unscattered plus diffuse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// The unscattered part.
    pub ballistic: f64,
    /// The diffuse part.
    pub diffuse: f64,
}

impl Split {
    /// Both parts together.
    pub fn total(self) -> f64 {
        self.ballistic + self.diffuse
    }

    /// The geometric series 1 + x + x² + … = 1/(1 − x): its unscattered part
    /// is 1/(1 − x_b) and its diffuse part x_d/((1 − x)(1 − x_b)).
    pub fn loops(self) -> Split {
        let ballistic = 1.0 / (1.0 - self.ballistic);
        let all = 1.0 / (1.0 - self.total());
        Split {
            ballistic,
            diffuse: self.diffuse * all * ballistic,
        }
    }
}

impl Add for Split {
    type Output = Split;
    fn add(self, o: Split) -> Split {
        Split {
            ballistic: self.ballistic + o.ballistic,
            diffuse: self.diffuse + o.diffuse,
        }
    }
}

impl Mul for Split {
    type Output = Split;
    /// Convolution: only delta times delta stays a delta.
    fn mul(self, o: Split) -> Split {
        Split {
            ballistic: self.ballistic * o.ballistic,
            diffuse: self.diffuse * o.total() + self.ballistic * o.diffuse,
        }
    }
}

/// A reflectance and a transmittance, each split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitSide {
    /// Back out of the entry face.
    pub reflectance: Split,
    /// Out of the opposite face.
    pub transmittance: Split,
}

/// Responses to light from above (`down`) and from below (`up`), split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitSlab {
    /// R⁺, T⁺.
    pub down: SplitSide,
    /// R⁻, T⁻.
    pub up: SplitSide,
}

impl SplitSlab {
    /// A slab's response from its unscattered and diffuse parts.
    pub fn new(ballistic: SlabResponse, diffuse: SlabResponse) -> Self {
        let side = |b: SideResponse, d: SideResponse| SplitSide {
            reflectance: Split {
                ballistic: b.reflectance,
                diffuse: d.reflectance,
            },
            transmittance: Split {
                ballistic: b.transmittance,
                diffuse: d.transmittance,
            },
        };
        Self {
            down: side(ballistic.down, diffuse.down),
            up: side(ballistic.up, diffuse.up),
        }
    }

    /// No layer at all: everything passes, unscattered.
    pub fn transparent() -> Self {
        let pass = Split {
            ballistic: 1.0,
            diffuse: 0.0,
        };
        let nothing = Split {
            ballistic: 0.0,
            diffuse: 0.0,
        };
        let side = SplitSide {
            reflectance: nothing,
            transmittance: pass,
        };
        Self {
            down: side,
            up: side,
        }
    }

    /// Selects one part (or the sum) of every response.
    pub fn map(self, part: impl Fn(Split) -> f64) -> SlabResponse {
        let side = |s: SplitSide| SideResponse {
            reflectance: part(s.reflectance),
            transmittance: part(s.transmittance),
        };
        SlabResponse {
            down: side(self.down),
            up: side(self.up),
        }
    }
}

/// Light bouncing between stack `a` (above) and slab `b` (below), summed as
/// the geometric series 1/(1 − R_a⁻R_b⁺), side-aware (Mikkelsen 2.7.3).
pub fn combine(a: SplitSlab, b: SplitSlab) -> SplitSlab {
    let loops = (a.up.reflectance * b.down.reflectance).loops();
    SplitSlab {
        down: SplitSide {
            reflectance: a.down.reflectance
                + a.up.transmittance * b.down.reflectance * a.down.transmittance * loops,
            transmittance: b.down.transmittance * a.down.transmittance * loops,
        },
        up: SplitSide {
            reflectance: b.up.reflectance
                + b.down.transmittance * a.up.reflectance * b.up.transmittance * loops,
            transmittance: a.up.transmittance * b.up.transmittance * loops,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_add_up_to_the_plain_algebra() {
        let x = Split {
            ballistic: 0.3,
            diffuse: 0.2,
        };
        let y = Split {
            ballistic: 0.1,
            diffuse: 0.45,
        };
        assert!(((x * y).total() - x.total() * y.total()).abs() < 1e-15);
        assert_eq!((x * y).ballistic, 0.03);
        assert!((x.loops().total() - 1.0 / (1.0 - x.total())).abs() < 1e-15);
        assert!((x.loops().ballistic - 1.0 / 0.7).abs() < 1e-15);
    }
}
