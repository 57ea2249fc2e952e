//! Sets of places — rooms, regions, kinds, and their Boolean combinations — as events over the
//! worlds "the robot is at place k" (DESIGN §3), with their possibility and necessity.
//!
//! Places exclude each other and exhaust the map, so a set of places *is* a proposition: "the
//! robot is in the east wing" holds in exactly the worlds of the wing's places. Then, for a
//! normalised distribution `π'` over places,
//!
//! ```text
//! Π(S) = max_{k ∈ S} π'_k        (0 for the empty set)
//! N(S) = 1 − max_{k ∉ S} π'_k    (1 for the set of all places)
//! ¬S = complement,  S & T = S ∩ T,  S (+) T = S ∪ T
//! ```
//!
//! and a weighted head over a set, `(P1 ∨ P2, α)`, lowers every world outside the set to
//! `1 − α` (see [`crate::logic::PlaceDistribution::constrain`]). Depends on nothing else in the
//! crate.

use serde::{Deserialize, Serialize};

/// A set of places of one map, as a membership flag per place (index order of the map).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PlaceSet {
    members: Vec<bool>,
}

impl PlaceSet {
    /// The empty set over `n` places.
    pub fn empty(n: usize) -> Self {
        PlaceSet {
            members: vec![false; n],
        }
    }

    /// The set of all `n` places.
    pub fn all(n: usize) -> Self {
        PlaceSet {
            members: vec![true; n],
        }
    }

    /// The places with these indices, over `n` places (indices `≥ n` are ignored).
    pub fn from_indices(n: usize, indices: impl IntoIterator<Item = usize>) -> Self {
        let mut s = Self::empty(n);
        for k in indices {
            if let Some(m) = s.members.get_mut(k) {
                *m = true;
            }
        }
        s
    }

    /// Number of places of the map this set is over.
    pub fn universe(&self) -> usize {
        self.members.len()
    }

    /// True when place `k` is in the set (false for indices out of range).
    #[inline]
    pub fn contains(&self, k: usize) -> bool {
        self.members.get(k).copied().unwrap_or(false)
    }

    /// The indices of the member places, ascending.
    pub fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.members
            .iter()
            .enumerate()
            .filter(|(_, &m)| m)
            .map(|(k, _)| k)
    }

    /// `¬S`: every place not in the set.
    pub fn complement(&self) -> Self {
        PlaceSet {
            members: self.members.iter().map(|m| !m).collect(),
        }
    }

    /// `S (+) T`: union (over the larger universe when they differ).
    pub fn union(&self, other: &Self) -> Self {
        self.zip(other, |a, b| a || b)
    }

    /// `S & T`: intersection.
    pub fn intersection(&self, other: &Self) -> Self {
        self.zip(other, |a, b| a && b)
    }

    fn zip(&self, other: &Self, f: fn(bool, bool) -> bool) -> Self {
        let n = self.members.len().max(other.members.len());
        PlaceSet {
            members: (0..n)
                .map(|k| f(self.contains(k), other.contains(k)))
                .collect(),
        }
    }

    /// `Π(S) = max_{k ∈ S} π_k` over a distribution `pi` indexed like the map (0 when empty).
    pub fn possibility(&self, pi: &[f64]) -> f64 {
        pi.iter()
            .enumerate()
            .filter(|&(k, _)| self.contains(k))
            .map(|(_, &p)| p)
            .fold(0.0, f64::max)
    }

    /// `N(S) = 1 − max_{k ∉ S} π_k` (1 when every place is in the set).
    pub fn necessity(&self, pi: &[f64]) -> f64 {
        let outside = pi
            .iter()
            .enumerate()
            .filter(|&(k, _)| !self.contains(k))
            .map(|(_, &p)| p)
            .fold(0.0, f64::max);
        1.0 - outside
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn algebra_and_degrees_hand_worked() {
        // π' = (1, 0.6, 0.3): Π({P1, P2}) = 1, N({P1, P2}) = 1 − 0.3 = 0.7; N({P1}) = 0.4.
        let pi = [1.0, 0.6, 0.3];
        let s = PlaceSet::from_indices(3, [0, 1]);
        assert_eq!(s.possibility(&pi), 1.0);
        assert!((s.necessity(&pi) - 0.7).abs() < 1e-12);
        let p1 = PlaceSet::from_indices(3, [0]);
        assert!((p1.necessity(&pi) - 0.4).abs() < 1e-12);
        // ¬{P1, P2} = {P3}: Π = 0.3, N = 1 − 1 = 0.
        assert_eq!(s.complement(), PlaceSet::from_indices(3, [2]));
        assert_eq!(s.complement().possibility(&pi), 0.3);
        assert_eq!(s.complement().necessity(&pi), 0.0);
        let t = PlaceSet::from_indices(3, [1, 2]);
        assert_eq!(s.intersection(&t), PlaceSet::from_indices(3, [1]));
        assert_eq!(s.union(&t), PlaceSet::all(3));
        assert_eq!(PlaceSet::all(3).necessity(&pi), 1.0);
        assert_eq!(PlaceSet::empty(3).possibility(&pi), 0.0);
    }
}
