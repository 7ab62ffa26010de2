//! Two runs in one SSE2 register: [`F2`] holds two `f64` lanes whose
//! operations are the scalar IEEE ones, for the steppers that cross the
//! eventless intervals of two runs at once (`exact::lanes`, `taylor::pair`).

use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Mul, Neg, Not, Sub};

/// Two `f64` lanes of one SSE2 register: the arithmetic of two runs at once,
/// each lane's operations the IEEE operations the scalar code does (no
/// fused multiply-add, nothing reassociated), so each lane's results are the
/// scalar ones to the bit.
#[derive(Clone, Copy)]
pub struct F2(__m128d);

/// A lane-wise comparison: all ones where it holds.
#[derive(Clone, Copy)]
pub struct M2(__m128d);

impl F2 {
    #[inline(always)]
    pub fn new(a: f64, b: f64) -> F2 {
        F2(unsafe { _mm_setr_pd(a, b) })
    }
    #[inline(always)]
    pub fn splat(x: f64) -> F2 {
        F2(unsafe { _mm_set1_pd(x) })
    }
    #[inline(always)]
    pub fn lanes(self) -> [f64; 2] {
        let mut out = [0.0; 2];
        unsafe { _mm_storeu_pd(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    pub fn abs(self) -> F2 {
        F2(unsafe { _mm_andnot_pd(_mm_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    pub fn lt(self, o: F2) -> M2 {
        M2(unsafe { _mm_cmplt_pd(self.0, o.0) })
    }
    #[inline(always)]
    pub fn le(self, o: F2) -> M2 {
        M2(unsafe { _mm_cmple_pd(self.0, o.0) })
    }
    #[inline(always)]
    pub fn gt(self, o: F2) -> M2 {
        M2(unsafe { _mm_cmpgt_pd(self.0, o.0) })
    }
    /// `self.max(o)` lane by lane, for operands that are not NaN and
    /// not both zero (where `f64::max` and `maxpd` may differ).
    #[inline(always)]
    pub fn max(self, o: F2) -> F2 {
        F2(unsafe { _mm_max_pd(self.0, o.0) })
    }
}

impl M2 {
    /// Bit i set where lane i holds.
    #[inline(always)]
    pub fn bits(self) -> i32 {
        unsafe { _mm_movemask_pd(self.0) }
    }
}

/// `impl $trait for $ty` by the lane-wise intrinsic `$op`.
macro_rules! lane_wise {
    ($($trait:ident, $method:ident, $ty:ident, $op:ident;)*) => {$(
        impl $trait for $ty {
            type Output = $ty;
            #[inline(always)]
            fn $method(self, o: $ty) -> $ty {
                $ty(unsafe { $op(self.0, o.0) })
            }
        }
    )*};
}
lane_wise! {
    Add, add, F2, _mm_add_pd;
    Sub, sub, F2, _mm_sub_pd;
    Mul, mul, F2, _mm_mul_pd;
    BitAnd, bitand, M2, _mm_and_pd;
    BitOr, bitor, M2, _mm_or_pd;
}
impl Not for M2 {
    type Output = M2;
    #[inline(always)]
    fn not(self) -> M2 {
        M2(unsafe { _mm_xor_pd(self.0, _mm_castsi128_pd(_mm_set1_epi32(-1))) })
    }
}
impl Neg for F2 {
    type Output = F2;
    /// The sign flipped, as the scalar `-x` does (NaN and zeros included).
    #[inline(always)]
    fn neg(self) -> F2 {
        F2(unsafe { _mm_xor_pd(self.0, _mm_set1_pd(-0.0)) })
    }
}
