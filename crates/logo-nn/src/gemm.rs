//! C = A·B (+ C) in f64 for the host MLP: an AVX-512 kernel where the CPU has it,
//! matrixmultiply's portable dgemm elsewhere.
//!
//! Why a kernel of our own: the critic fits are two dozen forward and reverse passes of a
//! 128-128 net over 20k rows per reward stream, and matrixmultiply 0.3 has no AVX-512
//! path for f64, so it ran at about 20 GFLOP/s per core where the FMA units allow ~4×
//! that. The products here are all narrow (n ≤ 128, k ≤ one block of rows), so one
//! register-blocked micro-kernel over packed panels is enough: no outer cache blocking
//! beyond cutting k into chunks whose packed panels stay in L1/L2.
//!
//! Determinism: every element of C is accumulated over k in order, chunk by chunk, with
//! fused multiply-adds; the result depends only on the operands, never on threads.

/// C (`m × n`, row-major, dense) = A·B, or C + A·B if `accumulate`. A is `m × k` and B
/// `k × n`, each read through explicit (row, column) strides, so a transposed operand is
/// just swapped strides.
#[allow(clippy::too_many_arguments)]
pub fn gemm(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    a_strides: (usize, usize),
    b: &[f64],
    b_strides: (usize, usize),
    c: &mut [f64],
    accumulate: bool,
) {
    check_operands((m, k, n), a, a_strides, b, b_strides, c);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU has AVX-512F (checked just above) and `check_operands` keeps
        // every index the kernel reads or writes inside the slices.
        unsafe {
            avx512::gemm(
                (m, k, n),
                a.as_ptr(),
                a_strides,
                b.as_ptr(),
                b_strides,
                c.as_mut_ptr(),
                accumulate,
            )
        };
        return;
    }
    gemm_portable((m, k, n), a, a_strides, b, b_strides, c, accumulate);
}

/// The same product through matrixmultiply's dgemm (any CPU); [`gemm`] falls back to it
/// and the tests compare the two.
#[allow(clippy::too_many_arguments)]
pub fn gemm_portable(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    (rsb, csb): (usize, usize),
    c: &mut [f64],
    accumulate: bool,
) {
    check_operands((m, k, n), a, (rsa, csa), b, (rsb, csb), c);
    // SAFETY: `check_operands` keeps every index dgemm touches inside the slices.
    unsafe {
        matrixmultiply::dgemm(
            m,
            k,
            n,
            1.0,
            a.as_ptr(),
            rsa as isize,
            csa as isize,
            b.as_ptr(),
            rsb as isize,
            csb as isize,
            if accumulate { 1.0 } else { 0.0 },
            c.as_mut_ptr(),
            n as isize,
            1,
        );
    }
}

fn check_operands(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    (rsb, csb): (usize, usize),
    c: &[f64],
) {
    let fits = |len: usize, rows: usize, cols: usize, rs: usize, cs: usize| {
        rows == 0 || cols == 0 || len > (rows - 1) * rs + (cols - 1) * cs
    };
    assert!(
        fits(a.len(), m, k, rsa, csa) && fits(b.len(), k, n, rsb, csb),
        "gemm operand shorter than its shape and strides"
    );
    assert!(c.len() >= m * n, "gemm output shorter than m × n");
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use std::arch::x86_64::*;
    use std::cell::RefCell;

    /// Rows of C per micro-tile: 12 rows × 2 zmm = 24 accumulators, plus the two B
    /// vectors and a broadcast, within the 32 zmm registers.
    const MR: usize = 12;
    /// Columns of C per micro-tile: two zmm of 8 doubles.
    const NR: usize = 16;
    /// k per packed chunk: a 12 × 256 A panel (24 KiB) stays in L1 while the B panels
    /// (256 × 16 each, 32 KiB) stream from L2.
    const KC: usize = 256;

    thread_local! {
        /// Packing buffers, reused across calls (the blocks of one pass run on the same
        /// few threads).
        static PACKED: RefCell<(Vec<f64>, Vec<f64>)> = const { RefCell::new((Vec::new(), Vec::new())) };
    }

    /// # Safety
    /// The CPU must have AVX-512F, and A, B and C must hold every element their shapes
    /// and strides address (C dense row-major, `m × n`).
    #[target_feature(enable = "avx512f")]
    pub unsafe fn gemm(
        (m, k, n): (usize, usize, usize),
        a: *const f64,
        (rsa, csa): (usize, usize),
        b: *const f64,
        (rsb, csb): (usize, usize),
        c: *mut f64,
        accumulate: bool,
    ) {
        if !accumulate {
            // SAFETY: C holds m × n elements.
            unsafe { std::ptr::write_bytes(c, 0, m * n) };
        }
        if m == 0 || n == 0 || k == 0 {
            return;
        }
        let panels = n.div_ceil(NR);
        PACKED.with_borrow_mut(|(a_pack, b_pack)| {
            a_pack.resize(MR * KC, 0.0);
            b_pack.resize(panels * NR * KC, 0.0);
            for k0 in (0..k).step_by(KC) {
                let kc = KC.min(k - k0);
                // B[k0.., :] as column panels of NR, each kc × NR row-major, zero-padded.
                for p in 0..panels {
                    let (j0, nr) = (p * NR, NR.min(n - p * NR));
                    let panel = &mut b_pack[p * KC * NR..p * KC * NR + kc * NR];
                    for (kk, row) in panel.chunks_exact_mut(NR).enumerate() {
                        for (jj, value) in row.iter_mut().enumerate() {
                            *value = if jj < nr {
                                // SAFETY: (k0 + kk, j0 + jj) lies inside B's shape.
                                unsafe { *b.add((k0 + kk) * rsb + (j0 + jj) * csb) }
                            } else {
                                0.0
                            };
                        }
                    }
                }
                for i0 in (0..m).step_by(MR) {
                    let mr = MR.min(m - i0);
                    // A[i0.., k0..] as one kc × MR panel (column of MR per k), zero-padded.
                    for (kk, column) in a_pack[..kc * MR].chunks_exact_mut(MR).enumerate() {
                        for (ii, value) in column.iter_mut().enumerate() {
                            *value = if ii < mr {
                                // SAFETY: (i0 + ii, k0 + kk) lies inside A's shape.
                                unsafe { *a.add((i0 + ii) * rsa + (k0 + kk) * csa) }
                            } else {
                                0.0
                            };
                        }
                    }
                    for p in 0..panels {
                        let (j0, nr) = (p * NR, NR.min(n - p * NR));
                        // SAFETY: the panels hold kc rows; the tile (i0.., j0..) of
                        // mr × nr lies inside C; the CPU has AVX-512F (caller).
                        unsafe {
                            kernel(
                                kc,
                                a_pack.as_ptr(),
                                b_pack.as_ptr().add(p * KC * NR),
                                c.add(i0 * n + j0),
                                n,
                                (mr, nr),
                            )
                        };
                    }
                }
            }
        });
    }

    /// C[..mr, ..nr] += A_panel · B_panel over `kc`, C with row stride `ldc`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn kernel(
        kc: usize,
        a: *const f64,
        b: *const f64,
        c: *mut f64,
        ldc: usize,
        (mr, nr): (usize, usize),
    ) {
        let lanes = |count: usize| -> __mmask8 { ((1u32 << count.min(8)) - 1) as __mmask8 };
        let (mask_lo, mask_hi) = (lanes(nr), lanes(nr.saturating_sub(8)));
        let mut acc = [[_mm512_setzero_pd(); 2]; MR];
        for (r, row) in acc.iter_mut().enumerate().take(mr) {
            // Masked lanes are never read, so the pointers may run past C's end.
            let c_row = c.wrapping_add(r * ldc);
            // SAFETY: the unmasked lanes are C's elements (r, ..nr).
            unsafe {
                row[0] = _mm512_maskz_loadu_pd(mask_lo, c_row);
                row[1] = _mm512_maskz_loadu_pd(mask_hi, c_row.wrapping_add(8));
            }
        }
        for kk in 0..kc {
            // SAFETY: both panels hold kc rows (B: NR wide, A: MR wide).
            let (b0, b1) = unsafe {
                (
                    _mm512_loadu_pd(b.add(kk * NR)),
                    _mm512_loadu_pd(b.add(kk * NR + 8)),
                )
            };
            for (r, row) in acc.iter_mut().enumerate() {
                // SAFETY: as above.
                let a_r = _mm512_set1_pd(unsafe { *a.add(kk * MR + r) });
                row[0] = _mm512_fmadd_pd(a_r, b0, row[0]);
                row[1] = _mm512_fmadd_pd(a_r, b1, row[1]);
            }
        }
        for (r, row) in acc.iter().enumerate().take(mr) {
            let c_row = c.wrapping_add(r * ldc);
            // SAFETY: the unmasked lanes are C's elements (r, ..nr).
            unsafe {
                _mm512_mask_storeu_pd(c_row, mask_lo, row[0]);
                _mm512_mask_storeu_pd(c_row.wrapping_add(8), mask_hi, row[1]);
            }
        }
    }
}
