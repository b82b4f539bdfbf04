//! The reference: the exact discrete sum M(x) = Σ_j P(|x − x_j|) E_j A_j
//! over every source within d_max, in parallel over targets.

use super::Method;
use super::disk_kernel::DiskKernel;
use super::integrator::{Integrated, Integrator};
use super::kernel::Kernel;
use super::source_table::{SourceTable, texel_disks};
use super::sources::{Grid, OwnSource, Sources, Targets};
use crate::control::{Cancelled, Control, parallel_fill};
use crate::error::Error;
use crate::pipeline::Prepared;
use crate::scattering::Scattering;
use glam::Vec3;

/// Sources copied into grid order, so a row of cells is a contiguous run.
pub(super) struct Sorted {
    pub grid: Grid,
    pub table: SourceTable,
}

impl Sorted {
    pub fn new(sources: &Sources, cell: f32, disks: &DiskKernel) -> Self {
        let grid = Grid::new(&sources.position, cell);
        let table = SourceTable::new(sources, &grid.order, disks);
        Sorted { grid, table }
    }

    /// Σ over sources within the kernel's reach of `p` of P·flux, `own`
    /// being the source the target is, if any.
    #[inline]
    pub fn gather(&self, disks: &DiskKernel, p: Vec3, n: Vec3, own: Option<usize>) -> [f64; 3] {
        let own = self.table.rank_of(own);
        let reach = disks.kernel().d_max;
        let mut sum = [0.0f64; 3];
        self.grid.for_each_run(p, reach, |run| {
            for j in run {
                let d2 = (self.table.position[j] - p).length_squared();
                if d2 > reach * reach {
                    continue;
                }
                let m = self.table.contribution(disks, j, p, n, d2, own);
                for c in 0..3 {
                    sum[c] += m[c] as f64;
                }
            }
        });
        sum
    }
}

/// Radiant exitance (W/m²) at each target by the exact sum over `sources`.
pub fn integrate(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let disks = texel_disks(kernel, sources);
    let sorted = Sorted::new(sources, 0.5 * kernel.d_max, &disks);
    let mut out = vec![[0.0f32; 3]; targets.position.len()];
    parallel_fill(&mut out, 256, control, |i| {
        sorted
            .gather(
                &disks,
                targets.position[i],
                targets.normal[i],
                targets.own.of(i),
            )
            .map(|v| v as f32)
    })?;
    Ok(out)
}

/// The exact discrete sum over every texel within d_max: the reference
/// every other method is measured against. It has no settings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BruteIntegrator;

impl Integrator for BruteIntegrator {
    fn method(&self) -> Method {
        Method::Brute
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let sources = prepared.texel_sources();
        // The targets are the texels the sources were made from, in order.
        let targets = Targets {
            own: OwnSource::Same,
            ..prepared.targets()
        };
        let exitance = integrate(&scattering.kernel, &sources, targets, control)?;
        Ok(Integrated {
            exitance,
            sources: sources.len(),
        })
    }
}
