//! Exact geometric predicates for delmesh, with a symbolic perturbation.
//!
//! Every topological decision delmesh makes (which side of a line/plane a point lies on, whether a
//! point lies inside a circumcircle/circumsphere) goes through this crate, in two stages: a
//! floating-point evaluation with a semi-static error bound answers almost every call, and an
//! exact evaluation in integer arithmetic answers the rest (the coordinates of one call are
//! integers at a common power-of-two scale; see `integer.rs`), so every sign returned here is
//! the sign of the exact determinant of the `f64` inputs. Shewchuk's adaptive arithmetic, from
//! the [`robust`] crate, is only the last resort for input outside [`COORDINATE_RANGE`].
//!
//! On top of that, [`incircle_sos`] and [`insphere_sos`] never answer [`Sign::Zero`]: four
//! co-circular (five co-spherical) points are resolved by a *symbolic perturbation* of the lifted
//! coordinate `w = |p|² + ε^(rank)`, ranked by the caller's keys (delmesh ranks points by their
//! coordinates in lexicographic order, see [`Lex`]). This is a genuine (infinitesimal)
//! perturbation of the input, so all answers are consistent with each other: the triangulation
//! built from them is one of the Delaunay triangulations of the unperturbed points (see
//! Edelsbrunner & Mücke, "Simulation of simplicity", 1990, and Devillers & Teillaud,
//! "Perturbations for Delaunay and weighted Delaunay 3D triangulations", 2011).
//!
//! Two constructions use the same integer arithmetic: [`circumcenter2`] and [`circumcenter3`]
//! compute a circumcentre exactly and round it, for the cells where delmesh's floating-point
//! circumcentre cannot guarantee its accuracy.
//!
//! # Conventions
//! - `orient2d(a, b, c)` is [`Sign::Positive`] when `a, b, c` turn counter-clockwise.
//! - `orient3d(a, b, c, d)` is [`Sign::Positive`] when the signed volume
//!   `(b − a) · ((c − a) × (d − a))` is positive (a right-handed tetrahedron).
//!   Note that this is the opposite of the raw sign of `robust::orient3d`.
//! - `incircle` / `insphere` are [`Sign::Positive`] when the last point lies strictly inside the
//!   circle/sphere through the others, which must be positively oriented.
//!
//! # Range of inputs
//! Exactness holds as long as no intermediate product underflows or overflows. Callers keep
//! coordinates in `[2^-142, 2^201]` in magnitude (or exactly zero); [`COORDINATE_RANGE`] gives
//! the bounds and `delaunay-core` rescales inputs by a power of two (an exact operation) and
//! rejects points whose coordinates span more than that range.
#![forbid(unsafe_code)]

mod bigint;
mod construct;
mod exact;
mod integer;
mod sos;

pub use construct::{circumcenter2, circumcenter3};
pub use exact::{incircle, insphere, orient2d, orient2d_value, orient3d, orient3d_value};
pub use sos::{
    incircle_lex, incircle_sos, incircle_tiebreak, insphere_lex, insphere_sos, insphere_tiebreak,
    Lex,
};

/// Smallest and largest non-zero coordinate magnitudes for which every predicate here is exact
/// (`2^-142` and `2^201`: the exact expansions of degree-5 `insphere` neither underflow nor
/// overflow).
pub const COORDINATE_RANGE: (f64, f64) = (1.7516230804060213e-43, 3.2138760885179806e60);

/// The sign of a predicate's determinant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sign {
    /// The determinant is negative.
    Negative,
    /// The determinant is exactly zero (a degenerate configuration).
    Zero,
    /// The determinant is positive.
    Positive,
}

impl Sign {
    /// The sign of an `f64` (zero for both `0.0` and `-0.0`).
    #[inline]
    pub fn of(value: f64) -> Sign {
        if value > 0.0 {
            Sign::Positive
        } else if value < 0.0 {
            Sign::Negative
        } else {
            Sign::Zero
        }
    }

    /// The opposite sign.
    #[inline]
    #[must_use]
    pub fn reversed(self) -> Sign {
        match self {
            Sign::Negative => Sign::Positive,
            Sign::Zero => Sign::Zero,
            Sign::Positive => Sign::Negative,
        }
    }

    /// `+1`, `0` or `-1`.
    #[inline]
    pub fn as_i32(self) -> i32 {
        match self {
            Sign::Negative => -1,
            Sign::Zero => 0,
            Sign::Positive => 1,
        }
    }

    /// True for [`Sign::Positive`].
    #[inline]
    pub fn is_positive(self) -> bool {
        self == Sign::Positive
    }

    /// True for [`Sign::Negative`].
    #[inline]
    pub fn is_negative(self) -> bool {
        self == Sign::Negative
    }
}
