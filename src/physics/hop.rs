//! A small hop in closed form: from the pivot (`y = 0`) at speed `w` out,
//! under `ÿ = p²y + a + bσ` with `a < 0` (the forcing pulls the block
//! back), the return to the pivot, by a double series in its two small
//! parameters or by Newton on its Taylor terms. The exact stepper's
//! equation is this one; the Taylor stepper's is near it on a hop low
//! enough. Derivation: docs/MODEL.md, §3.3.

/// The largest expansion parameter of a hop solved by its Taylor series:
/// `z = pσ` and the relative change of the forcing over the hop. At 1e-2,
/// the series through y⁽⁸⁾ leaves a remainder below 1e-18 of the motion
/// (its last term kept is 5e-17 of it).
pub(in crate::physics) const HOP_Z: f64 = 1e-2;

/// Up to this size of a hop's expansion parameters (`max(z², |bσ/|a||)`),
/// its return time and speed are their series to fifth order in them;
/// above it, two Newton steps from the second-order guess.
pub(in crate::physics) const HOP_SERIES: f64 = 2e-3;

/// A hop's return to the pivot ([`hop_return`]), with the expansion
/// parameters it was found from.
pub(in crate::physics) struct HopReturn {
    /// The return's time σ (s).
    pub sigma: f64,
    /// The speed there over the speed out, `V` (`ẏ = −w·V`).
    pub v_ratio: f64,
    /// `β = bσ₀/|a|`, the forcing's relative change over the hop.
    pub beta: f64,
    /// `q = z² = (pσ₀)²`.
    pub q: f64,
}

/// The return to the pivot of a hop of `ÿ = p²y + a + bσ` from `y = 0`,
/// `ẏ = w > 0`, when both expansion parameters are at most [`HOP_Z`],
/// the return lies inside `(0, len)` and the apex provably stays below
/// `top`. `None` otherwise.
#[inline(always)]
pub(in crate::physics) fn hop_return(
    p: f64,
    w: f64,
    a: f64,
    b: f64,
    len: f64,
    top: f64,
) -> Option<HopReturn> {
    if a.is_nan() || a >= 0.0 {
        return None;
    }
    let r = 1.0 / a;
    let sigma0 = -2.0 * w * r;
    let beta = -(b * r) * sigma0;
    let z0 = p * sigma0;
    // On the hop ÿ ≤ a(1 − HOP_Z) + p²·y_max, so the apex is below
    // w²/(2|a|)·(1 + 4·HOP_Z) (the p²y part is z²/8 of a): it must stay
    // below top.
    if !(z0 <= HOP_Z && beta.abs() <= HOP_Z && w * w * (1.0 + 4.0 * HOP_Z) < top * (-2.0 * a)) {
        return None;
    }
    let q = z0 * z0;
    let (t, v_ratio) = if q.max(beta.abs()) <= HOP_SERIES {
        hop_series(q, beta)
    } else {
        hop_newton(q, beta)
    };
    let sigma = sigma0 * t;
    if !(sigma > 0.0 && sigma < len) {
        return None;
    }
    Some(HopReturn {
        sigma,
        v_ratio,
        beta,
        q,
    })
}

/// A hop's return time `T = σ/σ₀` and speed ratio `V` to fifth order in
/// `q` and `β` (docs/MODEL.md, §3.3): `Σ βʲ·Pⱼ(q)`, the `Pⱼ` independent of
/// each other and `β`'s powers paired, so that few operations depend on
/// one another. As `q = z² ≤ HOP_Z² = 1e-4` on a hop, the terms of `q⁴`
/// and `q³β²` and beyond (below 1e-19) are left out.
#[inline(always)]
fn hop_series(q: f64, beta: f64) -> (f64, f64) {
    let t0 = 1.0 + q * (1.0 / 12.0 + q * (1.0 / 80.0 + q * (1.0 / 448.0)));
    let t1 = 1.0 / 3.0 + q * (1.0 / 10.0 + q * (3.0 / 112.0 + q * (1.0 / 144.0)));
    let t2 = 2.0 / 9.0 + q * (7.0 / 60.0 + q * (47.0 / 1050.0));
    let t3 = 5.0 / 27.0 + q * (56.0 / 405.0 + q * (173.0 / 2520.0));
    let t4 = 14.0 / 81.0 + q * (1.0 / 6.0);
    let t5 = 14.0 / 81.0;
    let v1 = -1.0 / 3.0 - q * (1.0 / 20.0 + q * (1.0 / 112.0 + q * (1.0 / 576.0)));
    let v2 = -2.0 / 9.0 - q * (7.0 / 90.0 + q * (47.0 / 2100.0));
    let v3 = -5.0 / 27.0 - q * (14.0 / 135.0 + q * (173.0 / 4200.0));
    let v4 = -14.0 / 81.0 - q * (2.0 / 15.0);
    let v5 = -14.0 / 81.0;
    let b2 = beta * beta;
    let t = t0 + beta * ((t1 + beta * t2) + b2 * ((t3 + beta * t4) + b2 * t5));
    let v = 1.0 + beta * ((v1 + beta * v2) + b2 * ((v3 + beta * v4) + b2 * v5));
    (t, v)
}

/// A hop's `T` and `V` by two Newton steps on its Taylor terms through
/// y⁽⁸⁾ (docs/MODEL.md, §3.3), for `max(q, |β|)` up to [`HOP_Z`].
#[inline(always)]
fn hop_newton(q: f64, beta: f64) -> (f64, f64) {
    let c = q * (1.0 / 6.0) + beta * (1.0 / 3.0);
    let q12 = q * (1.0 / 12.0);
    let d1 = c - q12;
    let mut t =
        1.0 + (d1 + d1 * (2.0 * c - 0.25 * q) + c * q * (1.0 / 20.0) - q * q * (1.0 / 360.0));
    for _ in 0..2 {
        let t2 = t * t;
        let u = q * t2;
        let f = (1.0 - t)
            + t2 * (c * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0)))
                - q12 * t * (1.0 + u * (1.0 / 30.0 + u * (1.0 / 1680.0))));
        let df = -1.0 + 2.0 * c * t * (1.0 + u * (1.0 / 10.0 + u * (1.0 / 280.0)))
            - q12 * t2 * (3.0 + u * (1.0 / 6.0 + u * (1.0 / 240.0)));
        t -= f / df;
    }
    let t2 = t * t;
    let u = q * t2;
    let ydot_w = (1.0 - 2.0 * t)
        + (3.0 * c * t2 * (1.0 + u * (1.0 / 12.0 + u * (1.0 / 360.0)))
            - 4.0 * q12 * t2 * t * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0))));
    (t, -ydot_w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hop's two solutions, the double series and Newton on the Taylor
    /// terms (derived separately), agree to rounding wherever the series
    /// is used (`q ≤ HOP_Z²`, `|β| ≤ HOP_SERIES`): a fifth-order
    /// coefficient wrong by 10 % would show at its edges (0.17·β⁵ = 5e-15
    /// there).
    #[test]
    fn hop_series_agrees_with_newton_where_it_is_used() {
        let steps = [-1.0, -0.7, -0.3, -1e-2, 0.0, 1e-3, 0.2, 0.5, 0.9, 1.0];
        for fq in steps.iter().map(|f: &f64| f.abs()) {
            for fb in steps {
                let (q, beta) = (fq * HOP_Z * HOP_Z, fb * HOP_SERIES);
                let (t, v) = hop_series(q, beta);
                let (t_n, v_n) = hop_newton(q, beta);
                assert!((t - t_n).abs() <= 4e-16, "q {q} β {beta}: T {t} vs {t_n}");
                assert!((v - v_n).abs() <= 4e-16, "q {q} β {beta}: V {v} vs {v_n}");
            }
        }
    }
}
