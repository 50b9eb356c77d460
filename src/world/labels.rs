//! Collision labels: which removable objects a configuration touches, or what
//! fixed thing blocks it.

use std::fmt;

use serde::Serialize;

use crate::resolve::{FixedId, ObjectId, RobotId};

/// A set of removable objects, as a bitset over [`ObjectId`].
#[derive(Clone, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ObjectSet {
    // Trailing zero words are trimmed so equal sets compare and hash equal.
    words: Vec<u64>,
}

impl ObjectSet {
    pub fn new() -> ObjectSet {
        ObjectSet::default()
    }

    pub fn single(o: ObjectId) -> ObjectSet {
        let mut s = ObjectSet::new();
        s.insert(o);
        s
    }

    pub fn insert(&mut self, o: ObjectId) {
        let (w, b) = (o.index() / 64, o.index() % 64);
        if self.words.len() <= w {
            self.words.resize(w + 1, 0);
        }
        self.words[w] |= 1 << b;
    }

    pub fn remove(&mut self, o: ObjectId) {
        let (w, b) = (o.index() / 64, o.index() % 64);
        if let Some(word) = self.words.get_mut(w) {
            *word &= !(1 << b);
        }
        self.trim();
    }

    pub fn contains(&self, o: ObjectId) -> bool {
        let (w, b) = (o.index() / 64, o.index() % 64);
        self.words.get(w).is_some_and(|word| word & (1 << b) != 0)
    }

    pub fn len(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
    }

    pub fn union_with(&mut self, other: &ObjectSet) {
        if self.words.len() < other.words.len() {
            self.words.resize(other.words.len(), 0);
        }
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            *a |= b;
        }
    }

    pub fn union(&self, other: &ObjectSet) -> ObjectSet {
        let mut s = self.clone();
        s.union_with(other);
        s
    }

    /// Removes every member of `other` from `self`.
    pub fn subtract(&mut self, other: &ObjectSet) {
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            *a &= !b;
        }
        self.trim();
    }

    pub fn is_subset(&self, other: &ObjectSet) -> bool {
        self.words.iter().enumerate().all(|(i, w)| w & !other.words.get(i).copied().unwrap_or(0) == 0)
    }

    pub fn intersects(&self, other: &ObjectSet) -> bool {
        self.words.iter().zip(&other.words).any(|(a, b)| a & b != 0)
    }

    /// Members in increasing id order.
    pub fn iter(&self) -> impl Iterator<Item = ObjectId> + '_ {
        self.words
            .iter()
            .enumerate()
            .flat_map(|(i, &w)| (0..64u32).filter(move |b| w & (1 << b) != 0).map(move |b| ObjectId(i as u32 * 64 + b)))
    }

    fn trim(&mut self) {
        while self.words.last() == Some(&0) {
            self.words.pop();
        }
    }
}

impl FromIterator<ObjectId> for ObjectSet {
    fn from_iter<I: IntoIterator<Item = ObjectId>>(iter: I) -> Self {
        let mut s = ObjectSet::new();
        for o in iter {
            s.insert(o);
        }
        s
    }
}

impl fmt::Debug for ObjectSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_set().entries(self.iter().map(|o| o.0)).finish()
    }
}

/// What makes a configuration or segment unusable, whatever is removed.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Blocker {
    /// A robot link (or its hand) hits a fixed body.
    Fixed { body: FixedId, link: String },
    /// The carried object hits a fixed body.
    HeldFixed { object: ObjectId, body: FixedId },
    /// A link hits another robot standing at its home configuration.
    Robot { other: RobotId, link: String, other_link: String },
    /// The carried object hits another robot.
    HeldRobot { object: ObjectId, other: RobotId, other_link: String },
    /// Two links of the same robot collide.
    SelfCollision { link_a: String, link_b: String },
    /// The carried object hits the arm that carries it (other than the hand holding it).
    HeldSelf { object: ObjectId, link: String },
    /// A joint value outside its limits.
    JointLimit { joint: String, value: f64 },
}

/// The answer of a labelled check.
#[derive(Clone, Debug, PartialEq)]
pub enum Check {
    /// Something fixed is hit: no removal can make this valid.
    Blocked(Blocker),
    /// Only these removable objects are touched (empty: collision-free).
    Touches(ObjectSet),
}

impl Check {
    pub fn free() -> Check {
        Check::Touches(ObjectSet::new())
    }

    pub fn is_blocked(&self) -> bool {
        matches!(self, Check::Blocked(_))
    }

    /// Combines two checks of pieces of one motion: the first block wins, else labels unite.
    pub fn and(self, other: Check) -> Check {
        match (self, other) {
            (Check::Blocked(b), _) | (_, Check::Blocked(b)) => Check::Blocked(b),
            (Check::Touches(mut a), Check::Touches(b)) => {
                a.union_with(&b);
                Check::Touches(a)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_algebra_across_word_boundaries() {
        let a: ObjectSet = [0, 63, 64, 130].into_iter().map(ObjectId).collect();
        let b: ObjectSet = [63, 130].into_iter().map(ObjectId).collect();
        assert_eq!(a.len(), 4);
        assert!(b.is_subset(&a));
        assert!(!a.is_subset(&b));
        let mut c = a.clone();
        c.subtract(&b);
        assert_eq!(c.iter().map(|o| o.0).collect::<Vec<_>>(), vec![0, 64]);
        let mut d = b.clone();
        d.remove(ObjectId(130));
        assert_eq!(d, ObjectSet::single(ObjectId(63)));
        assert!(a.intersects(&d));
        assert!(!c.intersects(&d));
    }
}
