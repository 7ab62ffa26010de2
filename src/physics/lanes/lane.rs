//! What the numerics written once need of their number type ([`Lane`],
//! [`Lanes`], [`Mask`]), and the lone run's: `f64`, one lane.

use std::ops::{Add, BitAnd, BitOr, Mul, Neg, Not, Sub};

/// A vector of runs' values: the IEEE operations lane by lane (each
/// lane's results the scalar ones, to the bit) and comparisons into a
/// [`Mask`]. What the numerics written once need of their number type.
pub trait Lane:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    type Mask: Mask;
    fn splat(x: f64) -> Self;
    fn abs(self) -> Self;
    /// `self.max(o)` lane by lane, for operands that are not NaN and not
    /// both zero.
    fn max(self, o: Self) -> Self;
    /// Where `self < o`, lane by lane (false on NaN).
    fn lt(self, o: Self) -> Self::Mask;
    /// Where `self > o`, lane by lane (false on NaN).
    fn gt(self, o: Self) -> Self::Mask;
}

/// A lane-wise truth: combined without short circuits, asked at the end.
pub trait Mask: Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> {
    /// Whether it holds in every lane.
    fn all(self) -> bool;
}

/// `N` lanes in and out, and the Taylor series' tail test.
pub trait Lanes<const N: usize>: Lane {
    fn from_lanes(x: [f64; N]) -> Self;
    fn to_lanes(self) -> [f64; N];
    /// Bit i set where lane i of `self` is at most `o`'s, and `also`'s
    /// at most `also_o`'s, and `and`'s at most `and_o`'s.
    fn le3(self, o: Self, also: Self, also_o: Self, and: Self, and_o: Self) -> u32;
}

impl Mask for bool {
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
}

impl Lane for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn abs(self) -> f64 {
        f64::abs(self)
    }
    #[inline(always)]
    fn max(self, o: f64) -> f64 {
        f64::max(self, o)
    }
    #[inline(always)]
    fn lt(self, o: f64) -> bool {
        self < o
    }
    #[inline(always)]
    fn gt(self, o: f64) -> bool {
        self > o
    }
}

/// The lone run: one lane, the scalar operations themselves.
impl Lanes<1> for f64 {
    #[inline(always)]
    fn from_lanes([x]: [f64; 1]) -> f64 {
        x
    }
    #[inline(always)]
    fn to_lanes(self) -> [f64; 1] {
        [self]
    }
    #[inline(always)]
    fn le3(self, o: f64, also: f64, also_o: f64, and: f64, and_o: f64) -> u32 {
        u32::from(self <= o && also <= also_o && and <= and_o)
    }
}
