//! tanh of a buffer in place, branch-free and vectorised: the activation of every hidden
//! layer on the kernels engine (libm's scalar `tanh` was a third of an iteration).

/// tanh of every value, within a few ulp of libm's (tested), several times faster: the
/// loop is branch-free so the compiler vectorises it, and on CPUs with AVX2 and FMA a copy
/// compiled for them is chosen at run time.
///
/// tanh|x| = e/(e + 2) with e = expm1(2|x|). expm1 by range reduction, 2|x| = n ln 2 + r,
/// |r| ≤ ln2/2: expm1 = 2ⁿ·expm1(r) + (2ⁿ − 1), and expm1(r) = r·Σ r^k/(k+1)! (14 terms),
/// which keeps full relative precision near 0 without a second polynomial.
pub fn tanh_f64_in_place(values: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has the features this copy is compiled for (checked here).
            unsafe { tanh_avx512(values) };
        } else {
            // SAFETY: as above.
            unsafe { tanh_avx2_fma(values) };
        }
        return;
    }
    tanh_loop::<false>(values);
}

/// The loop of [`tanh_loop`] written with AVX-512 intrinsics, four vectors at a time. The
/// compiler vectorised the plain loop one vector per step, and that step is one long
/// chain of dependent operations (13 FMAs of Horner, then a division): the scheduler
/// filled up with waiting µops and a value took ≈ 7 cycles. Four independent chains
/// interleaved keep the FMA units busy. Every value goes through exactly the operations
/// of `tanh_loop::<true>` in the same order, so the results are the same to the bit
/// (tested), the tail included (it runs `tanh_loop` itself).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn tanh_avx512(values: &mut [f64]) {
    use std::arch::x86_64::*;
    const WAYS: usize = 4;
    let splat = _mm512_set1_pd;
    let mut chunks = values.chunks_exact_mut(8 * WAYS);
    for chunk in &mut chunks {
        let at = |w: usize| chunk.as_ptr().wrapping_add(8 * w);
        // SAFETY: the chunk holds WAYS × 8 values.
        let x: [__m512d; WAYS] = std::array::from_fn(|w| unsafe { _mm512_loadu_pd(at(w)) });
        let each = |f: &dyn Fn(usize) -> __m512d| -> [__m512d; WAYS] { std::array::from_fn(f) };
        let z =
            each(&|w| _mm512_min_pd(_mm512_mul_pd(splat(2.0), _mm512_abs_pd(x[w])), splat(40.0)));
        let t =
            each(&|w| _mm512_add_pd(_mm512_mul_pd(z[w], splat(TANH_INV_LN2)), splat(TANH_SHIFT)));
        let n = each(&|w| _mm512_sub_pd(t[w], splat(TANH_SHIFT)));
        let r = each(&|w| {
            _mm512_sub_pd(
                _mm512_sub_pd(z[w], _mm512_mul_pd(n[w], splat(TANH_LN2_HI))),
                _mm512_mul_pd(n[w], splat(TANH_LN2_LO)),
            )
        });
        let mut q = [splat(INV_FACTORIALS[14]); WAYS];
        for k in (1..14).rev() {
            q = each(&|w| _mm512_fmadd_pd(q[w], r[w], splat(INV_FACTORIALS[k])));
        }
        let expm1_r = each(&|w| _mm512_mul_pd(q[w], r[w]));
        let two_to_n = each(&|w| {
            let bits = _mm512_sub_epi64(
                _mm512_castpd_si512(t[w]),
                _mm512_set1_epi64(TANH_SHIFT.to_bits() as i64),
            );
            _mm512_castsi512_pd(_mm512_slli_epi64::<52>(_mm512_add_epi64(
                bits,
                _mm512_set1_epi64(1023),
            )))
        });
        let e = each(&|w| {
            _mm512_fmadd_pd(
                two_to_n[w],
                expm1_r[w],
                _mm512_sub_pd(two_to_n[w], splat(1.0)),
            )
        });
        let sign = _mm512_set1_epi64(i64::MIN);
        for w in 0..WAYS {
            let magnitude =
                _mm512_castpd_si512(_mm512_div_pd(e[w], _mm512_add_pd(e[w], splat(2.0))));
            let signed = _mm512_or_si512(
                _mm512_andnot_si512(sign, magnitude),
                _mm512_and_si512(sign, _mm512_castpd_si512(x[w])),
            );
            let nan = _mm512_cmp_pd_mask::<_CMP_UNORD_Q>(x[w], x[w]);
            let y = _mm512_mask_blend_pd(nan, _mm512_castsi512_pd(signed), x[w]);
            // SAFETY: as the loads.
            unsafe { _mm512_storeu_pd(chunk.as_mut_ptr().add(8 * w), y) };
        }
    }
    tanh_loop::<true>(chunks.into_remainder());
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn tanh_avx2_fma(values: &mut [f64]) {
    tanh_loop::<true>(values);
}

/// `FMA`: fuse the polynomial steps (only where the CPU has FMA: elsewhere `mul_add`
/// would be a slow library call).
#[inline(always)]
fn tanh_loop<const FMA: bool>(values: &mut [f64]) {
    let step = |acc: f64, x: f64, c: f64| if FMA { acc.mul_add(x, c) } else { acc * x + c };
    const LN2_HI: f64 = TANH_LN2_HI;
    const LN2_LO: f64 = TANH_LN2_LO;
    const INV_LN2: f64 = TANH_INV_LN2;
    const SHIFT: f64 = TANH_SHIFT;
    for v in values.iter_mut() {
        let x = *v;
        // Saturate where tanh rounds to ±1 anyway (2^57 ≫ 2/ulp).
        let z = (2.0 * x.abs()).min(40.0);
        let t = z * INV_LN2 + SHIFT;
        let n = t - SHIFT;
        let r = (z - n * LN2_HI) - n * LN2_LO;
        let mut q = INV_FACTORIALS[14];
        for k in (1..14).rev() {
            q = step(q, r, INV_FACTORIALS[k]);
        }
        let expm1_r = q * r;
        let two_to_n =
            f64::from_bits(t.to_bits().wrapping_sub(SHIFT.to_bits()).wrapping_add(1023) << 52);
        let e = step(two_to_n, expm1_r, two_to_n - 1.0);
        let y = (e / (e + 2.0)).copysign(x);
        *v = if x.is_nan() { x } else { y };
    }
}

// ln 2 split so that n·LN2_HI is exact (fdlibm's constants).
const TANH_LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const TANH_LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
const TANH_INV_LN2: f64 = std::f64::consts::LOG2_E;
// Adding 1.5·2^52 rounds to an integer and leaves it in the low mantissa bits: no
// libm `round`, no float-to-int conversion (neither vectorises on baseline x86-64).
const TANH_SHIFT: f64 = 6_755_399_441_055_744.0;

/// 1/k! for k = 0..=20 (k! is exact in f64 up to 22!).
const INV_FACTORIALS: [f64; 21] = {
    let mut f = [1.0; 21];
    let mut k = 1;
    while k < 21 {
        f[k] = f[k - 1] * k as f64;
        k += 1;
    }
    let mut inv = [1.0; 21];
    let mut k = 0;
    while k < 21 {
        inv[k] = 1.0 / f[k];
        k += 1;
    }
    inv
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Whichever copy `tanh_f64_in_place` picks on this CPU (AVX-512 intrinsics, AVX2, or
    /// the plain loop) gives the plain loop's result to the bit: the copies exist for
    /// speed only, so a change in them must not move a training run.
    #[test]
    fn every_copy_of_tanh_gives_the_plain_loops_bits() {
        let mut xs: Vec<f64> = (0..20_011)
            .map(|i| (i as f64 * 0.7548776662).sin() * 10f64.powi(i % 7 - 3))
            .collect();
        xs.extend([
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            5e-324,
            -1e-300,
            19.06,
            -25.0,
            1e300,
        ]);
        for len in [xs.len(), 31, 32, 33, 7] {
            let mut fast = xs[..len].to_vec();
            tanh_f64_in_place(&mut fast);
            let mut plain = xs[..len].to_vec();
            // FMA = true: `mul_add` is exact whether the CPU fuses it or libm does.
            tanh_loop::<true>(&mut plain);
            for (i, (a, b)) in fast.iter().zip(&plain).enumerate() {
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "tanh({}) = {a} here, {b} in the plain loop",
                    xs[i]
                );
            }
        }
    }
}
