//! The replay's instants on one stretch (between two trajectory points or events): close
//! enough that no point moves more than the bound from one to the next.
//!
//! A stretch's joints are fastest somewhere inside it (a move leaves and reaches its
//! points slowly), so it is cut into equal windows, each stepped by its own peak speeds:
//! near a stop the instants thin out as the motion does.

/// At most this many windows per stretch.
pub(super) const WINDOWS: u64 = 16;

/// One window: its first instant, the step, and how many instants.
struct Window {
    start: f64,
    step: f64,
    n: u64,
}

/// The instants of one stretch `[ta, tb)`, window by window.
pub(super) struct Grid {
    windows: Vec<Window>,
}

/// An instant of a [`Grid`]: window, and index in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Instant {
    w: usize,
    k: u64,
}

impl Grid {
    /// `[ta, tb)` cut into `windows` equal windows (at least 1), each stepped so that
    /// `speed(a, b)` (a bound on how fast any point moves between `a` and `b`) times the
    /// step is at most `bound`.
    pub fn new(ta: f64, tb: f64, windows: u64, bound: f64, mut speed: impl FnMut(f64, f64) -> f64) -> Grid {
        let count = windows.max(1);
        let len = (tb - ta) / count as f64;
        let windows = (0..count)
            .map(|i| {
                let start = ta + len * i as f64;
                let end = if i + 1 == count { tb } else { ta + len * (i + 1) as f64 };
                let n = ((speed(start, end) * (end - start) / bound).ceil().max(1.0)).min(u32::MAX as f64) as u64;
                Window { start, step: (end - start) / n as f64, n }
            })
            .collect();
        Grid { windows }
    }

    pub fn first(&self) -> Option<Instant> {
        (!self.windows.is_empty()).then_some(Instant { w: 0, k: 0 })
    }

    pub fn time(&self, at: Instant) -> f64 {
        let w = &self.windows[at.w];
        w.start + w.step * at.k as f64
    }

    /// The instant after `at`; `None` past the stretch's last.
    pub fn next(&self, at: Instant) -> Option<Instant> {
        if at.k + 1 < self.windows[at.w].n {
            Some(Instant { w: at.w, k: at.k + 1 })
        } else {
            (at.w + 1 < self.windows.len()).then_some(Instant { w: at.w + 1, k: 0 })
        }
    }

    /// The last instant at or before `t`, or the one after `at` if that is later: the
    /// replay skips to it when nothing can come too close before `t`.
    pub fn skip_to(&self, at: Instant, t: f64) -> Option<Instant> {
        let next = self.next(at)?;
        // The last window starting at or before `t`, then the last instant in it.
        let w = self.windows.partition_point(|w| w.start <= t).saturating_sub(1);
        let win = &self.windows[w];
        let mut k = (((t - win.start) / win.step).floor().max(0.0) as u64).min(win.n - 1);
        if k > 0 && win.start + win.step * k as f64 > t {
            k -= 1;
        }
        Some(next.max(Instant { w, k }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(g: &Grid) -> Vec<f64> {
        let mut out = Vec::new();
        let mut at = g.first();
        while let Some(i) = at {
            out.push(g.time(i));
            at = g.next(i);
        }
        out
    }

    #[test]
    fn a_constant_speed_gives_the_uniform_steps() {
        // 1 m/s over 1 s, a bound of 2⁻⁹ m: 512 instants 2⁻⁹ s apart, in 4 windows of 128.
        let g = Grid::new(0.0, 1.0, 4, 1.0 / 512.0, |_, _| 1.0);
        let t = all(&g);
        assert_eq!(t.len(), 512);
        for (i, t) in t.iter().enumerate() {
            assert_eq!(*t, i as f64 / 512.0);
        }
    }

    #[test]
    fn slow_windows_get_fewer_instants() {
        // 0.5 m/s in the first half, 4 m/s in the second, 1/16 m: 4 + 32 instants.
        let g = Grid::new(0.0, 1.0, 2, 0.0625, |a, _| if a < 0.5 { 0.5 } else { 4.0 });
        let t = all(&g);
        assert_eq!(t.len(), 36);
        assert_eq!((t[1], t[4], t[5]), (0.125, 0.5, 0.515625));
    }

    #[test]
    fn skipping_lands_on_the_last_instant_not_after_the_time_and_always_moves_on() {
        let g = Grid::new(0.0, 1.0, 2, 0.0625, |a, _| if a < 0.5 { 0.5 } else { 4.0 });
        let t = all(&g);
        let mut at = g.first().expect("instants");
        // Within the first window, across into the second, one step, past the end.
        for target in [0.3, 0.26, 0.51, 0.5101, 0.7777, 2.0] {
            let before = g.time(at);
            match g.skip_to(at, target) {
                Some(next) => {
                    let tn = g.time(next);
                    let last = t.iter().copied().filter(|x| *x <= target).fold(f64::NEG_INFINITY, f64::max);
                    let after = t.iter().copied().find(|x| *x > before).expect("a later instant");
                    assert_eq!(tn, last.max(after), "from {before} to {target}");
                    at = next;
                }
                None => assert!(target > t[t.len() - 1] && g.next(at).is_none()),
            }
        }
        // A target behind still moves one instant on.
        let second = g.skip_to(g.first().expect("instants"), -1.0).expect("a second instant");
        assert_eq!(g.time(second), t[1]);
    }
}
