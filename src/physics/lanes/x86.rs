//! Lanes of x86-64 vector registers: [`F2`] holds two `f64` lanes of an
//! SSE2 register and [`F4`] four of an AVX one, their operations the scalar
//! IEEE ones ([`Lanes`]).

use std::arch::x86_64::*;

use super::lane::{Lane, Lanes, Mask};
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

impl Mask for M2 {
    #[inline(always)]
    fn all(self) -> bool {
        self.bits() == 0b11
    }
}

impl Lane for F2 {
    type Mask = M2;
    #[inline(always)]
    fn splat(x: f64) -> F2 {
        F2::splat(x)
    }
    #[inline(always)]
    fn abs(self) -> F2 {
        F2::abs(self)
    }
    #[inline(always)]
    fn max(self, o: F2) -> F2 {
        F2::max(self, o)
    }
    #[inline(always)]
    fn lt(self, o: F2) -> M2 {
        F2::lt(self, o)
    }
    #[inline(always)]
    fn gt(self, o: F2) -> M2 {
        F2::gt(self, o)
    }
}

impl Lanes<2> for F2 {
    #[inline(always)]
    fn from_lanes([a, b]: [f64; 2]) -> F2 {
        F2::new(a, b)
    }
    #[inline(always)]
    fn to_lanes(self) -> [f64; 2] {
        self.lanes()
    }
    #[inline(always)]
    fn le3(self, o: F2, also: F2, also_o: F2, and: F2, and_o: F2) -> u32 {
        (self.le(o) & also.le(also_o) & and.le(and_o)).bits() as u32
    }
}

/// Four `f64` lanes of one AVX register, as [`F2`] is two of an SSE2 one.
/// Its operations are AVX instructions: it is used only in code compiled
/// for x86-64-v3 or v4 (`dispatch`), run where the CPU has them.
#[derive(Clone, Copy)]
pub struct F4(__m256d);

// SAFETY (every `unsafe` below): `F4` is only built and used in functions
// compiled with AVX enabled, which run only where the CPU has it
// (`dispatch::drive_lanes`, called after `Isa::detected()` has lanes).
impl Lane for F4 {
    type Mask = M4;
    #[inline(always)]
    fn splat(x: f64) -> F4 {
        F4(unsafe { _mm256_set1_pd(x) })
    }
    #[inline(always)]
    fn abs(self) -> F4 {
        F4(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn max(self, o: F4) -> F4 {
        F4(unsafe { _mm256_max_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn lt(self, o: F4) -> M4 {
        M4(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn gt(self, o: F4) -> M4 {
        M4(unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0) })
    }
}

impl Lanes<4> for F4 {
    #[inline(always)]
    fn from_lanes([a, b, c, d]: [f64; 4]) -> F4 {
        F4(unsafe { _mm256_setr_pd(a, b, c, d) })
    }
    #[inline(always)]
    fn to_lanes(self) -> [f64; 4] {
        let mut out = [0.0; 4];
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    fn le3(self, o: F4, also: F4, also_o: F4, and: F4, and_o: F4) -> u32 {
        unsafe {
            let m = _mm256_and_pd(
                _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0),
                    _mm256_cmp_pd::<_CMP_LE_OQ>(also.0, also_o.0),
                ),
                _mm256_cmp_pd::<_CMP_LE_OQ>(and.0, and_o.0),
            );
            _mm256_movemask_pd(m) as u32
        }
    }
}

/// A lane-wise comparison of [`F4`]s: all ones where it holds.
#[derive(Clone, Copy)]
pub struct M4(__m256d);

impl Mask for M4 {
    #[inline(always)]
    fn all(self) -> bool {
        unsafe { _mm256_movemask_pd(self.0) == 0b1111 }
    }
}

impl Not for M4 {
    type Output = M4;
    #[inline(always)]
    fn not(self) -> M4 {
        M4(unsafe { _mm256_xor_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi32(-1))) })
    }
}

lane_wise! {
    Add, add, F4, _mm256_add_pd;
    Sub, sub, F4, _mm256_sub_pd;
    Mul, mul, F4, _mm256_mul_pd;
    BitAnd, bitand, M4, _mm256_and_pd;
    BitOr, bitor, M4, _mm256_or_pd;
}
impl Neg for F4 {
    type Output = F4;
    /// The sign flipped, as the scalar `-x` does (NaN and zeros included).
    #[inline(always)]
    fn neg(self) -> F4 {
        F4(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}
