//! The sizes of a bake's samples, gathered in one pass: which rows of a
//! table of disk means ([`super::disk_kernel`]) they read.
//!
//! A table's sizes run geometrically from the least sample to the
//! greatest, so which rows are read is known only once both are. Rather
//! than a second pass over millions of texels, the pass notes each size's
//! bin: its float's exponent and three leading bits of its mantissa, an
//! eighth of an octave of area (2048 bins, a bit each). Each bin then
//! marks every row a size within it could read, so the rows marked are a
//! superset of those read: a row read is always made.

/// How many low bits of an area's float a bin ignores.
const BIN_SHIFT: u32 = 20;
/// Bins of non-negative floats: the sign bit is 0.
const BINS: usize = 1 << (31 - BIN_SHIFT);

/// The least and greatest sample area seen (mm²), and the bins of sizes
/// that hold one.
#[derive(Clone, Debug)]
pub struct SampleSizes {
    least: f32,
    greatest: f32,
    bins: [u64; BINS / 64],
}

impl Default for SampleSizes {
    fn default() -> Self {
        SampleSizes {
            least: f32::INFINITY,
            greatest: 0.0,
            bins: [0; BINS / 64],
        }
    }
}

impl SampleSizes {
    /// Notes a sample of `area` mm² (a NaN or negative area reads no row,
    /// and sets no bound, as with `f32::min`).
    pub fn add(&mut self, area: f32) {
        self.least = self.least.min(area);
        self.greatest = self.greatest.max(area);
        if area >= 0.0 {
            let bin = (area.to_bits() >> BIN_SHIFT) as usize;
            self.bins[bin / 64] |= 1 << (bin % 64);
        }
    }

    /// The sizes seen by either.
    pub fn join(mut self, other: Self) -> Self {
        self.least = self.least.min(other.least);
        self.greatest = self.greatest.max(other.greatest);
        for (a, b) in self.bins.iter_mut().zip(other.bins) {
            *a |= b;
        }
        self
    }

    /// The least and greatest area seen, mm².
    pub fn range(&self) -> (f32, f32) {
        (self.least, self.greatest)
    }

    /// Each bin holding a size, as the least and greatest area it holds
    /// within [`Self::range`].
    pub fn spans(&self) -> impl Iterator<Item = (f32, f32)> + '_ {
        (0..BINS)
            .filter(|&bin| self.bins[bin / 64] & (1 << (bin % 64)) != 0)
            .filter_map(|bin| {
                let first = f32::from_bits((bin as u32) << BIN_SHIFT);
                let last = f32::from_bits((((bin as u32) + 1) << BIN_SHIFT) - 1);
                let (a, b) = (first.max(self.least), last.min(self.greatest));
                (a <= b).then_some((a, b))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_size_added_lies_in_a_span_and_the_range_is_exact() {
        let areas = [0.0f32, 1e-6, 0.013, 0.0131, 0.5, 2.0, 2.3, 7.9e3];
        let mut sizes = SampleSizes::default();
        for &a in &areas {
            sizes.add(a);
        }
        sizes.add(f32::NAN);
        sizes.add(-1.0);
        assert_eq!(sizes.range(), (-1.0, 7.9e3));
        let spans: Vec<(f32, f32)> = sizes.spans().collect();
        for &a in &areas {
            assert!(spans.iter().any(|&(lo, hi)| lo <= a && a <= hi), "{a}");
        }
        // Each span is at most an eighth of an octave wide.
        for &(lo, hi) in &spans {
            assert!(hi <= lo * 1.125 || lo == 0.0, "{lo}..{hi}");
        }
        // 0.013 and 0.0131 share a bin; 2.0 and 2.3 do not.
        assert_eq!(spans.len(), areas.len() - 1);
    }

    #[test]
    fn joined_sizes_are_the_sizes_of_both() {
        let (mut a, mut b, mut both) = (
            SampleSizes::default(),
            SampleSizes::default(),
            SampleSizes::default(),
        );
        for (i, x) in [0.1f32, 3.0, 0.002, 40.0].into_iter().enumerate() {
            let half = if i % 2 == 0 { &mut a } else { &mut b };
            half.add(x);
            both.add(x);
        }
        let joined = a.join(b);
        assert_eq!(joined.range(), both.range());
        assert!(joined.spans().eq(both.spans()));
    }
}
