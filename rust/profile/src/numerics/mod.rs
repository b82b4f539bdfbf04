//! Numerical tools the models share: Hankel transforms, quadrature, root
//! finding and a seeded random stream.

pub mod hankel;
pub mod quadrature;
pub mod rng;
pub mod roots;
