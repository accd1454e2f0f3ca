//! tanh of a buffer in place, branch-free and vectorised: the activation of every hidden
//! layer on the kernels engine, where libm's scalar `tanh` would cost more than the
//! products around it (docs/benchmarks.md).

/// tanh of every value, within a few ulp of libm's (tested), several times faster: the
/// loop is branch-free so the compiler vectorises it, and `multiversion` compiles a copy
/// for AVX-512 and one for AVX2, both with FMA, chosen at run time.
///
/// tanh|x| = e/(e + 2) with e = expm1(2|x|). expm1 by range reduction, 2|x| = n ln 2 + r,
/// |r| ≤ ln2/2: expm1 = 2ⁿ·expm1(r) + (2ⁿ − 1), and expm1(r) = r·Σ r^k/(k+1)! (14 terms),
/// which keeps full relative precision near 0 without a second polynomial.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
pub fn tanh_f64_in_place(values: &mut [f64]) {
    // Fused multiply-adds only where the CPU has them: elsewhere `mul_add` is a slow
    // library call (the results differ in the last bits, the same on every such CPU).
    if multiversion::target::target_cfg_f!(target_feature = "fma") {
        tanh_loop::<true>(values)
    } else {
        tanh_loop::<false>(values)
    }
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

/// tanh of every float32 value, the same scheme as [`tanh_f64_in_place`] with float32
/// constants: 2|x| saturates at 20 (tanh rounds to ±1 from 9.01 on), and expm1(r) needs
/// 8 terms for float32's 24 bits (|r| ≤ ln2/2). Within a few ulp of the float64 tanh
/// rounded to float32 (tested).
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
pub fn tanh_f32_in_place(values: &mut [f32]) {
    if multiversion::target::target_cfg_f!(target_feature = "fma") {
        tanh_loop_f32::<true>(values)
    } else {
        tanh_loop_f32::<false>(values)
    }
}

#[inline(always)]
fn tanh_loop_f32<const FMA: bool>(values: &mut [f32]) {
    let step = |acc: f32, x: f32, c: f32| if FMA { acc.mul_add(x, c) } else { acc * x + c };
    // ln 2 split so that n·LN2_HI is exact for |n| < 2^9 (float32's 24-bit mantissa).
    const LN2_HI: f32 = 0.693_145_75;
    const LN2_LO: f32 = 1.428_606_8e-6;
    const INV_LN2: f32 = std::f32::consts::LOG2_E;
    // 1.5·2^23: adding it rounds to an integer held in the low mantissa bits.
    const SHIFT: f32 = 12_582_912.0;
    for v in values.iter_mut() {
        let x = *v;
        let z = (2.0 * x.abs()).min(20.0);
        let t = z * INV_LN2 + SHIFT;
        let n = t - SHIFT;
        let r = (z - n * LN2_HI) - n * LN2_LO;
        let mut q = INV_FACTORIALS_F32[8];
        for k in (1..8).rev() {
            q = step(q, r, INV_FACTORIALS_F32[k]);
        }
        let expm1_r = q * r;
        let two_to_n =
            f32::from_bits(t.to_bits().wrapping_sub(SHIFT.to_bits()).wrapping_add(127) << 23);
        let e = step(two_to_n, expm1_r, two_to_n - 1.0);
        let y = (e / (e + 2.0)).copysign(x);
        *v = if x.is_nan() { x } else { y };
    }
}

/// 1/k! for k = 0..=8, in float32.
const INV_FACTORIALS_F32: [f32; 9] = {
    let mut inv = [1.0f32; 9];
    let mut k = 0;
    while k < 9 {
        inv[k] = INV_FACTORIALS[k] as f32;
        k += 1;
    }
    inv
};

#[cfg(test)]
mod tests {
    use super::*;

    /// float32: within 4 ulp of the float64 tanh rounded to float32, ±1 far out, NaN kept.
    #[test]
    fn the_float32_tanh_is_within_a_few_ulp() {
        let mut worst = 0u32;
        let xs: Vec<f32> = (-200_000..=200_000)
            .map(|i| i as f32 * 1e-4)
            .chain([
                1e-30,
                -1e-30,
                0.0,
                -0.0,
                8.9,
                9.1,
                30.0,
                -1e30,
                f32::INFINITY,
            ])
            .collect();
        let mut got = xs.clone();
        tanh_f32_in_place(&mut got);
        for (x, y) in xs.iter().zip(&got) {
            let want = (*x as f64).tanh() as f32;
            assert_eq!(y.is_sign_negative(), want.is_sign_negative(), "tanh({x})");
            let ulps = (y.to_bits() as i64 - want.to_bits() as i64).unsigned_abs() as u32;
            worst = worst.max(ulps);
        }
        assert!(worst <= 4, "{worst} ulp");
        let mut nan = [f32::NAN];
        tanh_f32_in_place(&mut nan);
        assert!(nan[0].is_nan());
        // Every copy gives the plain loop's bits, as for float64.
        let mut plain = xs.clone();
        tanh_loop_f32::<true>(&mut plain);
        assert!(
            got.iter()
                .zip(&plain)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }

    /// Whichever copy `tanh_f64_in_place` picks on this CPU (AVX-512, AVX2, or the plain
    /// loop) gives the plain loop's result to the bit: the copies exist for speed only, so
    /// a change in them must not move a training run.
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
