//! Label sets as the searches see them: an exact bitset over object ids, the first
//! 128 objects inline and any further ones in a heap spill that exists only in scenes
//! that have them, so small scenes pay one `None` check per operation and large ones
//! keep exact comparisons (no id shares a bit with another).

use crate::resolve::ObjectId;
use crate::world::ObjectSet;

/// Bit i is object i.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Mask {
    low: u128,
    /// Objects 128 and up, 64 per word; `None` when all are clear (trimmed, so equal
    /// sets are equal values).
    high: Option<Box<[u64]>>,
}

const INLINE: usize = 128;

impl Mask {
    pub(crate) fn from_set(s: &ObjectSet) -> Mask {
        let mut m = Mask::default();
        for o in s.iter() {
            m.insert(o);
        }
        m
    }

    pub(crate) fn insert(&mut self, o: ObjectId) {
        let i = o.index();
        if i < INLINE {
            self.low |= 1 << i;
            return;
        }
        let (w, b) = ((i - INLINE) / 64, (i - INLINE) % 64);
        let mut words = self.high.take().map(Vec::from).unwrap_or_default();
        if words.len() <= w {
            words.resize(w + 1, 0);
        }
        words[w] |= 1 << b;
        self.high = Some(words.into_boxed_slice());
    }

    /// This set without `o`.
    pub(crate) fn without(&self, o: ObjectId) -> Mask {
        let i = o.index();
        if i < INLINE {
            return Mask { low: self.low & !(1 << i), high: self.high.clone() };
        }
        let (w, b) = ((i - INLINE) / 64, (i - INLINE) % 64);
        let mut out = self.clone();
        if let Some(h) = out.high.as_mut().filter(|h| h.len() > w) {
            h[w] &= !(1 << b);
        }
        out.trim();
        out
    }

    pub(crate) fn count(&self) -> u32 {
        self.low.count_ones() + self.high.as_ref().map_or(0, |h| h.iter().map(|w| w.count_ones()).sum())
    }

    pub(crate) fn union(&self, o: &Mask) -> Mask {
        let high = match (&self.high, &o.high) {
            (None, None) => None,
            (Some(h), None) | (None, Some(h)) => Some(h.clone()),
            (Some(a), Some(b)) => {
                let (long, short) = if a.len() >= b.len() { (a, b) } else { (b, a) };
                let mut w = long.clone();
                for (x, y) in w.iter_mut().zip(short.iter()) {
                    *x |= y;
                }
                Some(w)
            }
        };
        Mask { low: self.low | o.low, high }
    }

    /// Whether every member of `self` is in `o`.
    pub(crate) fn is_subset(&self, o: &Mask) -> bool {
        if self.low & !o.low != 0 {
            return false;
        }
        match (&self.high, &o.high) {
            (None, _) => true,
            (Some(_), None) => false,
            (Some(a), Some(b)) => a.iter().enumerate().all(|(i, x)| x & !b.get(i).copied().unwrap_or(0) == 0),
        }
    }

    fn trim(&mut self) {
        if let Some(h) = &self.high {
            let n = h.iter().rposition(|&w| w != 0).map_or(0, |i| i + 1);
            self.high = (n > 0).then(|| h[..n].to_vec().into_boxed_slice());
        }
    }
}

impl FromIterator<ObjectId> for Mask {
    fn from_iter<I: IntoIterator<Item = ObjectId>>(iter: I) -> Self {
        let mut m = Mask::default();
        for o in iter {
            m.insert(o);
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(ids: &[u32]) -> Mask {
        ids.iter().map(|&i| ObjectId(i)).collect()
    }

    #[test]
    fn exact_past_the_inline_words() {
        // 127, 128 and 300 are three objects, not one shared bit.
        let a = m(&[1, 127, 128, 300]);
        assert_eq!(a.count(), 4);
        assert!(m(&[128]).is_subset(&a) && !m(&[129]).is_subset(&a) && !m(&[301]).is_subset(&a));
        assert!(!a.is_subset(&m(&[1, 127, 128])));
        assert_eq!(m(&[1, 300]).union(&m(&[127, 128])), a);
        assert_eq!(a.without(ObjectId(300)).without(ObjectId(128)), m(&[1, 127]));
        assert_eq!(a.without(ObjectId(300)).without(ObjectId(128)).high, None, "trimmed back to inline");
        assert_eq!(Mask::from_set(&[5, 200].into_iter().map(ObjectId).collect()), m(&[5, 200]));
    }
}
