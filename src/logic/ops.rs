//! The fuzzy connectives: t-norms and their dual t-conorms, negation, and implications, plus the
//! [`LogicConfig`] by which a rule file picks among them.
//!
//! | t-norm `T(a, b)`            | dual t-conorm `S(a, b) = 1 − T(1 − a, 1 − b)` | residuum `R(a, b) = sup{z : T(a, z) ≤ b}` |
//! |-----------------------------|-----------------------------------------------|--------------------------------------------|
//! | min: `min(a, b)`            | max: `max(a, b)`                              | Gödel: `1` if `a ≤ b`, else `b`            |
//! | product: `a·b`              | probabilistic sum: `a + b − a·b`              | Goguen: `1` if `a ≤ b`, else `b / a`       |
//! | Łukasiewicz: `max(0, a+b−1)`| bounded sum: `min(1, a + b)`                  | Łukasiewicz: `min(1, 1 − a + b)`           |
//!
//! Negation is `1 − a`; the Kleene–Dienes implication is `max(1 − a, b)`.

use serde::{Deserialize, Serialize};

/// A triangular norm: the file's `*` connective.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TNorm {
    /// `min(a, b)` (Gödel).
    #[default]
    Min,
    /// `a · b` (Goguen).
    Product,
    /// `max(0, a + b − 1)`.
    Lukasiewicz,
}

impl TNorm {
    /// All t-norms, for tests and `--help` texts.
    pub const ALL: [TNorm; 3] = [TNorm::Min, TNorm::Product, TNorm::Lukasiewicz];

    /// `T(a, b)`.
    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            TNorm::Min => a.min(b),
            TNorm::Product => a * b,
            TNorm::Lukasiewicz => (a + b - 1.0).max(0.0),
        }
    }

    /// The dual t-conorm `S(a, b) = 1 − T(1 − a, 1 − b)`: max, probabilistic sum, bounded sum.
    #[inline]
    pub fn conorm(self, a: f64, b: f64) -> f64 {
        match self {
            TNorm::Min => a.max(b),
            TNorm::Product => a + b - a * b,
            TNorm::Lukasiewicz => (a + b).min(1.0),
        }
    }

    /// The residuum `R(a, b) = sup{ z ∈ [0,1] : T(a, z) ≤ b }` (Gödel, Goguen, Łukasiewicz).
    #[inline]
    pub fn residuum(self, a: f64, b: f64) -> f64 {
        if a <= b {
            return 1.0;
        }
        match self {
            TNorm::Min => b,
            TNorm::Product => b / a,
            TNorm::Lukasiewicz => (1.0 - a + b).min(1.0),
        }
    }

    /// The name used in rule files and in `explain` output.
    pub fn name(self) -> &'static str {
        match self {
            TNorm::Min => "min",
            TNorm::Product => "product",
            TNorm::Lukasiewicz => "lukasiewicz",
        }
    }
}

/// How `->` is read (DESIGN §3).
///
/// For a sequent `|- (body -> head, w)` the head receives
/// - [`Implication::Residuum`] (default): `T(body, w)` — the modus ponens of the residuated
///   implication of the file's t-norm (`T(a, R(a, b)) ≤ b`), and a nested `φ -> ψ` is `R(φ, ψ)`;
/// - [`Implication::MinMp`]: `min(body, w)` — possibilistic min-based modus ponens
///   (`N(a) ≥ α, N(a → b) ≥ w ⊢ N(b) ≥ min(α, w)`), and a nested `φ -> ψ` is the material
///   (Kleene–Dienes) implication `max(1 − φ, ψ)`.
///
/// With antecedent 0.8 and weight 0.6 under the product t-norm: residuum 0.48, min-MP 0.6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Implication {
    /// Residuated implication of the file's t-norm.
    #[default]
    Residuum,
    /// Min-based modus ponens with the material implication.
    MinMp,
}

impl Implication {
    /// The name used in rule files.
    pub fn name(self) -> &'static str {
        match self {
            Implication::Residuum => "residuum",
            Implication::MinMp => "min_mp",
        }
    }
}

/// How the place distribution is normalised when its height is below 1 (DESIGN §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalisation {
    /// Min-based: `π'(k) = 1` where `π(k) = h`, else `π(k)`.
    #[default]
    Min,
    /// Product-based: `π'(k) = π(k) / h`.
    Product,
}

impl Normalisation {
    /// The name used in rule files.
    pub fn name(self) -> &'static str {
        match self {
            Normalisation::Min => "min",
            Normalisation::Product => "product",
        }
    }
}

/// How the distributions of several named evidence groups (`group name { … }` in a rule file)
/// are combined, world by world (DESIGN §3; Dubois & Prade's fusion of possibility
/// distributions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Fusion {
    /// `π(k) = min_g π_g(k)`: the same as pooling every rule into one base (idempotent, for
    /// sources that may share information).
    #[default]
    Min,
    /// `π(k) = Π_g π_g(k)`: reinforcement, for independent sources (each source's doubt about a
    /// place multiplies the other's).
    Product,
}

impl Fusion {
    /// The name used in rule files.
    pub fn name(self) -> &'static str {
        match self {
            Fusion::Min => "min",
            Fusion::Product => "product",
        }
    }

    /// The combination of two possibility degrees of one world.
    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Fusion::Min => a.min(b),
            Fusion::Product => a * b,
        }
    }
}

/// The operators and decision parameters a rule file's `logic { … }` block chooses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LogicConfig {
    /// The `*` connective, and the t-norm whose residuum reads `->`.
    pub tnorm: TNorm,
    /// How `->` is read.
    pub implication: Implication,
    /// How the place distribution is normalised.
    pub normalisation: Normalisation,
    /// Necessity a place needs to be chosen (default 0.5).
    pub threshold: f64,
    /// How far a chosen place's necessity must exceed the inconsistency (default 0: strictly).
    pub margin: f64,
    /// How the distributions of named evidence groups combine (default min).
    pub fusion: Fusion,
}

impl Default for LogicConfig {
    fn default() -> Self {
        LogicConfig {
            tnorm: TNorm::Min,
            implication: Implication::Residuum,
            normalisation: Normalisation::Min,
            threshold: 0.5,
            margin: 0.0,
            fusion: Fusion::Min,
        }
    }
}

impl LogicConfig {
    /// The head degree of a sequent whose body has degree `body` and whose weight is `w`.
    #[inline]
    pub fn detach(&self, body: f64, w: f64) -> f64 {
        match self.implication {
            Implication::Residuum => self.tnorm.apply(body, w),
            Implication::MinMp => body.min(w),
        }
    }

    /// The degree of a nested implication `a -> b`.
    #[inline]
    pub fn implies(&self, a: f64, b: f64) -> f64 {
        match self.implication {
            Implication::Residuum => self.tnorm.residuum(a, b),
            Implication::MinMp => (1.0 - a).max(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn design_example_of_the_two_readings() {
        // DESIGN §3: antecedent 0.8, weight 0.6 — min-MP gives 0.6, product residuum 0.48.
        let mut c = LogicConfig {
            tnorm: TNorm::Product,
            ..LogicConfig::default()
        };
        assert!((c.detach(0.8, 0.6) - 0.48).abs() < 1e-12);
        c.implication = Implication::MinMp;
        assert!((c.detach(0.8, 0.6) - 0.6).abs() < 1e-12);
    }
}
