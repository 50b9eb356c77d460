//! The replay's instants on one stretch (between two trajectory points or events): close
//! enough that no point moves more than the bound from one to the next.
//!
//! A stretch's joints are fastest somewhere inside it (a move leaves and reaches its
//! points slowly), so it is cut into equal windows, each stepped by its own peak speeds:
//! near a stop the instants thin out as the motion does.

/// At most this many windows per stretch.
pub(super) const WINDOWS: u64 = 16;

/// One window: its first instant and its end; the step and how many instants, once asked.
struct Window {
    start: f64,
    end: f64,
    steps: Option<(f64, u64)>,
}

/// The instants of one stretch `[ta, tb)`, window by window. A window's step is worked
/// out the first time an instant inside it is asked for: a window the replay skips
/// whole (it proved nothing can come too close there) costs nothing.
pub(super) struct Grid<F> {
    windows: Vec<Window>,
    bound: f64,
    speed: F,
}

/// An instant of a [`Grid`]: window, and index in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Instant {
    w: usize,
    k: u64,
}

impl<F: FnMut(f64, f64) -> f64> Grid<F> {
    /// `[ta, tb)` cut into `windows` equal windows (at least 1), each stepped so that
    /// `speed(a, b)` (a bound on how fast any point moves between `a` and `b`) times the
    /// step is at most `bound`.
    pub fn new(ta: f64, tb: f64, windows: u64, bound: f64, speed: F) -> Grid<F> {
        let count = windows.max(1);
        let len = (tb - ta) / count as f64;
        let windows = (0..count)
            .map(|i| {
                let start = ta + len * i as f64;
                let end = if i + 1 == count { tb } else { ta + len * (i + 1) as f64 };
                Window { start, end, steps: None }
            })
            .collect();
        Grid { windows, bound, speed }
    }

    /// Window `w`'s step and number of instants.
    fn steps(&mut self, w: usize) -> (f64, u64) {
        let win = &self.windows[w];
        if let Some(s) = win.steps {
            return s;
        }
        let (start, end) = (win.start, win.end);
        let n = (((self.speed)(start, end) * (end - start) / self.bound).ceil().max(1.0)).min(u32::MAX as f64) as u64;
        let s = ((end - start) / n as f64, n);
        self.windows[w].steps = Some(s);
        s
    }

    pub fn first(&self) -> Option<Instant> {
        (!self.windows.is_empty()).then_some(Instant { w: 0, k: 0 })
    }

    pub fn time(&mut self, at: Instant) -> f64 {
        let start = self.windows[at.w].start;
        if at.k == 0 {
            return start;
        }
        start + self.steps(at.w).0 * at.k as f64
    }

    /// The instant after `at`; `None` past the stretch's last.
    pub fn next(&mut self, at: Instant) -> Option<Instant> {
        if at.k + 1 < self.steps(at.w).1 {
            Some(Instant { w: at.w, k: at.k + 1 })
        } else {
            (at.w + 1 < self.windows.len()).then_some(Instant { w: at.w + 1, k: 0 })
        }
    }

    /// The last instant at or before `t`, or the one after `at` if that is later: the
    /// replay skips ahead to where the last check's proof runs out, and always moves on.
    pub fn skip_to(&mut self, at: Instant, t: f64) -> Option<Instant> {
        let next = self.next(at)?;
        // The last window starting at or before `t`, then the last instant in it.
        let w = self.windows.partition_point(|w| w.start <= t).saturating_sub(1);
        if w < next.w {
            return Some(next);
        }
        let start = self.windows[w].start;
        let (step, n) = self.steps(w);
        let mut k = (((t - start) / step).floor().max(0.0) as u64).min(n - 1);
        if k > 0 && start + step * k as f64 > t {
            k -= 1;
        }
        Some(next.max(Instant { w, k }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(g: &mut Grid<impl FnMut(f64, f64) -> f64>) -> Vec<f64> {
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
        let mut g = Grid::new(0.0, 1.0, 4, 1.0 / 512.0, |_, _| 1.0);
        let t = all(&mut g);
        assert_eq!(t.len(), 512);
        for (i, t) in t.iter().enumerate() {
            assert_eq!(*t, i as f64 / 512.0);
        }
    }

    #[test]
    fn slow_windows_get_fewer_instants() {
        // 0.5 m/s in the first half, 4 m/s in the second, 1/16 m: 4 + 32 instants.
        let mut g = Grid::new(0.0, 1.0, 2, 0.0625, |a, _| if a < 0.5 { 0.5 } else { 4.0 });
        let t = all(&mut g);
        assert_eq!(t.len(), 36);
        assert_eq!((t[1], t[4], t[5]), (0.125, 0.5, 0.515625));
    }

    #[test]
    fn skipping_lands_on_the_last_instant_not_after_the_time_and_always_moves_on() {
        let mut g = Grid::new(0.0, 1.0, 2, 0.0625, |a, _| if a < 0.5 { 0.5 } else { 4.0 });
        let t = all(&mut g);
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

    #[test]
    fn a_window_skipped_whole_is_never_stepped() {
        // Four windows; from the first instant straight into the last: the two between
        // never ask for their speed, and the instants are those of the eager grid.
        let asked = std::cell::RefCell::new(Vec::new());
        let mut g = Grid::new(0.0, 1.0, 4, 0.0625, |a, _| {
            asked.borrow_mut().push(a);
            1.0
        });
        let first = g.first().expect("instants");
        let landed = g.skip_to(first, 0.9).expect("an instant");
        assert_eq!(g.time(landed), 0.875);
        assert_eq!(*asked.borrow(), vec![0.0, 0.75]);
    }
}
