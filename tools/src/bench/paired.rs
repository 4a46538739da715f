//! Side-by-side measurement: two things timed in alternation, each round
//! giving one figure of each, so that a shared machine's slow spells fall
//! on both sides. Their ratio is taken within each round, where both
//! sides met the same machine, and the median of those ratios reported
//! with their range.

use anyhow::Result;

/// Figures of two things taken side by side: each side's median, and the
/// median, lowest and highest of the rounds' ratios `a / b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Paired {
    /// Median of the first thing's figures.
    pub a: f64,
    /// Median of the second thing's figures.
    pub b: f64,
    /// Median of the rounds' `a / b`.
    pub ratio: f64,
    /// Lowest and highest of the rounds' `a / b`.
    pub low: f64,
    pub high: f64,
    /// Rounds.
    pub rounds: usize,
}

impl Paired {
    /// From each round's pair of figures; `None` for no rounds.
    pub fn of(rounds: &[(f64, f64)]) -> Option<Paired> {
        if rounds.is_empty() {
            return None;
        }
        let ratios: Vec<f64> = rounds.iter().map(|&(a, b)| a / b).collect();
        Some(Paired {
            a: median(rounds.iter().map(|r| r.0)),
            b: median(rounds.iter().map(|r| r.1)),
            ratio: median(ratios.iter().copied()),
            low: ratios.iter().copied().fold(f64::INFINITY, f64::min),
            high: ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            rounds: rounds.len(),
        })
    }

    /// `2.17x`, with the rounds' range when there is more than one:
    /// `2.17x (2.10-2.31)`.
    pub fn ratio_text(&self) -> String {
        if self.rounds > 1 {
            format!("{:.2}x ({:.2}-{:.2})", self.ratio, self.low, self.high)
        } else {
            format!("{:.2}x", self.ratio)
        }
    }
}

/// The median (the mean of the middle two for an even count); NaN for
/// none.
pub fn median(values: impl Iterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// `rounds` rounds of `first` and `second`, each round's pair of results:
/// the order alternates (first then second, then second then first, ...)
/// so that neither always runs on the heels of the other.
pub fn alternate<A, B>(
    rounds: u32,
    mut first: impl FnMut() -> Result<A>,
    mut second: impl FnMut() -> Result<B>,
) -> Result<Vec<(A, B)>> {
    (0..rounds.max(1))
        .map(|r| {
            if r % 2 == 0 {
                let a = first()?;
                Ok((a, second()?))
            } else {
                let b = second()?;
                Ok((first()?, b))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratios_are_taken_round_by_round() {
        // The machine halves its speed in the second round: both sides
        // slow down, their ratio does not.
        let p = Paired::of(&[(2.0, 1.0), (4.0, 2.0), (3.0, 1.0)]).unwrap();
        assert_eq!((p.a, p.b, p.ratio, p.low, p.high, p.rounds), (3.0, 1.0, 2.0, 2.0, 3.0, 3));
        assert_eq!(p.ratio_text(), "2.00x (2.00-3.00)");
        let one = Paired::of(&[(1.0, 4.0)]).unwrap();
        assert_eq!((one.ratio, one.ratio_text()), (0.25, "0.25x".to_string()));
        assert_eq!(Paired::of(&[]), None);
    }

    #[test]
    fn medians_of_odd_and_even_counts() {
        assert_eq!(median([3.0, 1.0, 2.0].into_iter()), 2.0);
        assert_eq!(median([4.0, 1.0, 3.0, 2.0].into_iter()), 2.5);
        assert!(median(std::iter::empty()).is_nan());
    }

    #[test]
    fn the_order_alternates_round_by_round() {
        let log = std::cell::RefCell::new(String::new());
        let pairs = alternate(
            3,
            || {
                log.borrow_mut().push('a');
                Ok(1.0)
            },
            || {
                log.borrow_mut().push('b');
                Ok(2.0)
            },
        )
        .unwrap();
        assert_eq!(log.into_inner(), "abbaab");
        assert_eq!(pairs, vec![(1.0, 2.0); 3]);
        // A failing side stops the rounds with its error.
        let failed = alternate(2, || Ok(1.0), || -> Result<f64> { anyhow::bail!("no embree") });
        assert!(failed.unwrap_err().to_string().contains("no embree"));
    }
}
