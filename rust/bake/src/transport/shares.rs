//! Per-channel shares of light, as the walked totals keep them.

/// True when every channel of `v` is finite and within [0, 1].
pub(super) fn is_share(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x))
}

/// Per channel, the largest of `first` and each of `rest`.
pub(super) fn most_per_channel(first: [f64; 3], rest: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    rest.fold(first, |most, v| [0, 1, 2].map(|c| most[c].max(v[c])))
}

/// Per channel, `part` over `whole`, at least 0, and 0 where the ratio is
/// not finite (a channel of which `whole` holds nothing).
pub(super) fn share_of(part: [f64; 3], whole: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|c| {
        let share = part[c] / whole[c];
        if share.is_finite() {
            share.max(0.0)
        } else {
            0.0
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_share_of_nothing_is_none_and_never_below_none() {
        let shares = share_of([0.1, -0.2, f64::NAN], [0.5, 0.5, 0.5]);
        assert_eq!(shares[..2], [0.2, 0.0]);
        assert_eq!(shares[2], 0.0);
        assert_eq!(
            share_of([0.1, 0.0, 1.0], [0.0, 0.0, f64::INFINITY]),
            [0.0; 3]
        );
    }

    #[test]
    fn shares_are_finite_and_within_one() {
        assert!(is_share(&[0.0, 0.5, 1.0]));
        for bad in [
            [1.0 + 1e-12, 0.0, 0.0],
            [-1e-12, 0.0, 0.0],
            [f64::NAN, 0.0, 0.0],
        ] {
            assert!(!is_share(&bad), "{bad:?}");
        }
        let most = most_per_channel(
            [0.1, 0.5, 0.0],
            [[0.3, 0.2, 0.0], [0.2, 0.1, 0.4]].into_iter(),
        );
        assert_eq!(most, [0.3, 0.5, 0.4]);
    }
}
