//! The pairs' expiries (see `Memory`): per pair the time its bound runs out, with the
//! least of each block of pairs beside them.
//!
//! The replay asks three things at each instant: every pair that runs out before a
//! time, the least expiry left, and a pair's expiry anew once measured. A new part of a
//! stretch changes every pair's expiry, which on the examples happens at a third of the
//! instants or more: a binary heap rebuilt by a push per pair, and popped entry by entry,
//! was a seventh of the 200-can table's compile. Flat expiries are set in place, and a
//! block's least lets the scans skip the blocks with nothing below the time asked.

/// Pairs per block.
const BLOCK: usize = 32;

/// A pair not queued (its movers stand still) or taken off: never below anything.
const OFF: f64 = f64::NAN;

#[derive(Default)]
pub(super) struct Expiries {
    /// Per pair: its expiry, or [`OFF`].
    at: Vec<f64>,
    /// Per block: the least expiry in it (NaN ignored), `+∞` when none.
    least: Vec<f64>,
}

impl Expiries {
    /// `n` pairs, pair `k`'s expiry `expiry(k)` (NaN for none).
    pub(super) fn fill(&mut self, n: usize, expiry: impl FnMut(usize) -> f64) {
        self.at.clear();
        self.at.extend((0..n).map(expiry));
        self.least.clear();
        self.least.resize(n.div_ceil(BLOCK), f64::INFINITY);
        for b in 0..self.least.len() {
            self.recompute(b);
        }
    }

    /// Pair `k`'s expiry is `e` (NaN for none).
    pub(super) fn set(&mut self, k: usize, e: f64) {
        let old = std::mem::replace(&mut self.at[k], e);
        let b = k / BLOCK;
        if e < self.least[b] {
            self.least[b] = e;
        } else if old == self.least[b] && e.total_cmp(&old) != std::cmp::Ordering::Equal {
            // The block's least was this pair's and it grew (or left): find the new one.
            self.recompute(b);
        }
    }

    /// The least expiry queued (NaN never is), `+∞` when none.
    pub(super) fn least(&self) -> f64 {
        self.least.iter().fold(f64::INFINITY, |a, &b| a.min(b))
    }

    /// Takes off, into `out` (pair, expiry), every pair whose expiry is below `limit`.
    pub(super) fn take_below(&mut self, limit: f64, mut out: impl FnMut(usize, f64)) {
        for b in 0..self.least.len() {
            if self.least[b] < limit {
                let start = b * BLOCK;
                let end = (start + BLOCK).min(self.at.len());
                let mut least = f64::INFINITY;
                for k in start..end {
                    let e = self.at[k];
                    if e < limit {
                        self.at[k] = OFF;
                        out(k, e);
                    } else {
                        least = least.min(e);
                    }
                }
                self.least[b] = least;
            }
        }
    }

    fn recompute(&mut self, b: usize) {
        let start = b * BLOCK;
        let end = (start + BLOCK).min(self.at.len());
        self.least[b] = self.at[start..end].iter().fold(f64::INFINITY, |a, &e| a.min(e));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// What the scans must give: every expiry looked at, one by one.
    #[derive(Default)]
    struct Plain(Vec<f64>);

    impl Plain {
        fn least(&self) -> f64 {
            self.0.iter().fold(f64::INFINITY, |a, &b| a.min(b))
        }
        fn take_below(&mut self, limit: f64) -> Vec<(usize, u64)> {
            let mut out = vec![];
            for (k, e) in self.0.iter_mut().enumerate() {
                if *e < limit {
                    out.push((k, e.to_bits()));
                    *e = OFF;
                }
            }
            out
        }
    }

    /// Expiries drawn from a few values (ties), infinities and NaN among them.
    fn expiry() -> impl Strategy<Value = f64> {
        prop_oneof![(0u8..8).prop_map(f64::from), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(OFF), -1e3..1e3f64,]
    }

    #[derive(Debug, Clone)]
    enum Op {
        Set(usize, f64),
        Take(f64),
        Fill(usize),
    }

    fn op(n: usize) -> impl Strategy<Value = Op> {
        prop_oneof![
            4 => (0..n, expiry()).prop_map(|(k, e)| Op::Set(k, e)),
            2 => prop_oneof![expiry(), Just(f64::MIN)].prop_map(Op::Take),
            1 => (0usize..5).prop_map(Op::Fill),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]
        /// Any sequence of fills, sets and takes gives the pairs, expiries and least a
        /// plain scan of every pair gives, across block edges (sizes not a block's
        /// multiple among them).
        #[test]
        fn blocks_answer_as_a_plain_scan(
            (n, ops) in (1usize..150).prop_flat_map(|n| (Just(n), prop::collection::vec(op(n), 0..300)))
        ) {
            let (mut fast, mut plain) = (Expiries::default(), Plain(vec![OFF; n]));
            fast.fill(n, |_| OFF);
            for op in ops {
                match op {
                    Op::Set(k, e) => { fast.set(k, e); plain.0[k] = e; }
                    Op::Fill(seed) => {
                        let e = |k: usize| [OFF, f64::NEG_INFINITY, 1.0, 2.0, f64::INFINITY][(k * 7 + seed) % 5];
                        fast.fill(n, e);
                        plain.0 = (0..n).map(e).collect();
                    }
                    Op::Take(limit) => {
                        let mut got = vec![];
                        fast.take_below(limit, |k, e| got.push((k, e.to_bits())));
                        prop_assert_eq!(got, plain.take_below(limit));
                    }
                }
                prop_assert_eq!(fast.least(), plain.least());
            }
        }
    }
}
