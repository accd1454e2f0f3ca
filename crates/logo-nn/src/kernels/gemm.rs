//! C = start + A·B, then a finish (tanh, ⊙(1 − h²)), in f64 for the host MLP: an
//! AVX-512 kernel where the CPU has it, matrixmultiply's portable dgemm elsewhere, and
//! direct loops for a few rows (acting) or one output column.
//!
//! Why a kernel of our own: the critic fits are two dozen forward and reverse passes of a
//! 128-128 net over 20k rows per reward stream. matrixmultiply packs both operands on
//! every call, and here one of them is always a block of activations: its
//! packing was a fifth of its time in a Hopper iteration's profile. The kernel below
//! reads A in place (row-major or transposed), packs only B (a weight matrix or one
//! block's upstream gradients) and runs 12 × 16 tiles of AVX-512 fused multiply-adds.
//! `logo bench nn` compares the two on the three shapes of a block (docs/benchmarks.md).
//!
//! Determinism: every element of C is accumulated over k in order, chunk by chunk, with
//! fused multiply-adds; the result depends only on the operands, never on threads.

/// Where C starts from before A·B is added.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// C = A·B.
    Zero,
    /// C += A·B.
    Accumulate,
    /// C = bias + A·B, the `n` biases added to every row (a layer's pre-activation).
    Bias(&'a [f64]),
}

/// What is done to C once the product is in, a few rows at a time while they are still
/// in cache (instead of another pass over the whole block).
#[derive(Debug, Clone, Copy)]
pub enum Finish<'a> {
    None,
    /// C ← tanh(C): a hidden layer's activation.
    Tanh,
    /// C ← C ⊙ (1 − h²), `h` laid out like C: back through a tanh whose output was h.
    TanhDerivative(&'a [f64]),
}

/// C (`m × n`, row-major, dense) = `start` + A·B, then `finish`. A is `m × k` and B
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
    start: Start,
    finish: Finish,
) {
    check_operands(
        (m, k, n),
        a,
        a_strides,
        b,
        b_strides,
        start,
        finish,
        c.len(),
    );
    if outer_applies(k, b_strides, start) {
        // SAFETY: the CPU has AVX-512F; the operands passed check_operands and B's one
        // row is contiguous.
        #[cfg(target_arch = "x86_64")]
        unsafe {
            avx512::outer((m, n), a, a_strides.0, b, c, finish)
        };
    } else if kernel_applies(m, k, n) {
        // SAFETY: the kernel applies (the CPU has AVX-512F) and `check_operands` keeps
        // every index it reads or writes inside the slices; C is initialised.
        unsafe {
            kernel(
                (m, k, n),
                a,
                a_strides,
                b,
                b_strides,
                c.as_mut_ptr(),
                start,
                finish,
            )
        };
    } else if m <= SMALL_ROWS && b_strides.1 == 1 {
        // Acting (a row or two per call): packing B would cost more than the product.
        begin(&mut c[..m * n], start);
        if avx512_available() {
            // SAFETY: the CPU has AVX-512F; the operands passed check_operands.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                avx512::small_rows((m, k, n), a, a_strides, b, b_strides.0, c)
            };
        } else {
            small_rows((m, k, n), a, a_strides, b, b_strides.0, c);
        }
        end_at(&mut c[..m * n], finish, 0);
    } else if n == 1 || k == 0 {
        // A single output column (a value net's last layer, a 1-D policy's mean): a
        // 16-wide tile would waste 15 of its lanes.
        begin(&mut c[..m * n], start);
        if avx512_available() && n == 1 && a_strides.0 == 1 && k > 0 {
            // c = Aᵀ's rows weighted by b: as a one-row product bᵀ·Aᵀ, whose rows are
            // A's contiguous columns (the same multiplies and adds in the same order).
            // SAFETY: the CPU has AVX-512F; bᵀ (1 × k, stride b_stride) and Aᵀ (k × m,
            // rows at a_strides.1) hold what A and b held.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                avx512::small_rows((1, k, m), b, (0, b_strides.0), a, a_strides.1, c)
            };
        } else if avx512_available() {
            // SAFETY: the CPU has AVX-512F.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                avx512::gemv((m, k), a, a_strides, b, b_strides.0, c)
            };
        } else {
            gemv((m, k), a, a_strides, b, b_strides.0, c);
        }
        end_at(&mut c[..m * n], finish, 0);
    } else {
        gemm_portable((m, k, n), a, a_strides, b, b_strides, c, start, finish);
    }
}

/// [`gemm`] into a new `m × n` buffer; `start` is `Zero` or `Bias`. Where the AVX-512
/// kernel runs it writes every element, so the buffer is not zero-filled first (that
/// fill was a tenth of a Hopper iteration's profile).
#[allow(clippy::too_many_arguments)]
pub fn gemm_to_vec(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    a_strides: (usize, usize),
    b: &[f64],
    b_strides: (usize, usize),
    start: Start,
    finish: Finish,
) -> Vec<f64> {
    assert!(
        !matches!(start, Start::Accumulate),
        "a new buffer has nothing to accumulate into"
    );
    if !kernel_applies(m, k, n) || outer_applies(k, b_strides, start) {
        let mut c = vec![0.0; m * n];
        gemm((m, k, n), a, a_strides, b, b_strides, &mut c, start, finish);
        return c;
    }
    let mut c = Vec::with_capacity(m * n);
    // The capacity is m × n; check_operands reads only its length.
    check_operands((m, k, n), a, a_strides, b, b_strides, start, finish, m * n);
    // SAFETY: the kernel applies; the operands passed check_operands; C has room for m × n
    // elements and, starting from Zero or Bias, the kernel writes each of them before
    // reading it, so all m × n are initialised when set_len runs.
    unsafe {
        kernel(
            (m, k, n),
            a,
            a_strides,
            b,
            b_strides,
            c.as_mut_ptr(),
            start,
            finish,
        );
        c.set_len(m * n);
    }
    c
}

/// Up to this many rows of C, [`gemm`] multiplies directly (when B's rows are
/// contiguous) instead of packing B for the kernel.
const SMALL_ROWS: usize = 4;

/// Whether the CPU has AVX-512F (the kernel and the AVX-512 copies of the direct loops).
fn avx512_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("avx512f");
    #[cfg(not(target_arch = "x86_64"))]
    return false;
}

/// Whether C = a·bᵀ (k = 1, from zero, B's row contiguous) goes through the outer
/// product instead of the kernel, whose tiles would each run one step of their loop
/// between all their set-up (a value net's or a 1-D policy's output layer, backwards).
fn outer_applies(k: usize, b_strides: (usize, usize), start: Start) -> bool {
    k == 1 && b_strides.1 == 1 && matches!(start, Start::Zero) && avx512_available()
}

/// Whether the AVX-512 kernel computes a product with these sizes: the CPU has it, and
/// there are more than a few rows, more than one output column and something to sum.
fn kernel_applies(m: usize, k: usize, n: usize) -> bool {
    m > SMALL_ROWS && n > 1 && k > 0 && avx512_available()
}

/// # Safety
/// As `avx512::gemm`, and only where [`kernel_applies`].
#[allow(clippy::too_many_arguments)]
unsafe fn kernel(
    dims: (usize, usize, usize),
    a: &[f64],
    a_strides: (usize, usize),
    b: &[f64],
    b_strides: (usize, usize),
    c: *mut f64,
    start: Start,
    finish: Finish,
) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: passed on from the caller.
    unsafe {
        avx512::gemm(
            dims,
            a.as_ptr(),
            a_strides,
            b.as_ptr(),
            b_strides,
            c,
            start,
            finish,
        )
    };
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (dims, a, a_strides, b, b_strides, c, start, finish);
        unreachable!("kernel_applies is false off x86-64");
    }
}

/// C = `start` (all of C).
fn begin(c: &mut [f64], start: Start) {
    match start {
        Start::Zero => c.fill(0.0),
        Start::Accumulate => {}
        Start::Bias(bias) => c
            .chunks_exact_mut(bias.len())
            .for_each(|row| row.copy_from_slice(bias)),
    }
}

/// `finish` applied to `c`, whose elements are `h`'s from `offset` on.
fn end_at(c: &mut [f64], finish: Finish, offset: usize) {
    match finish {
        Finish::None => {}
        Finish::Tanh => super::tanh::tanh_f64_in_place(c),
        Finish::TanhDerivative(h) => c
            .iter_mut()
            .zip(&h[offset..])
            .for_each(|(d, h)| *d *= 1.0 - h * h),
    }
}

/// c (`m`) += A·b, the `n = 1` case of [`gemm`]: dot products along A's rows when
/// they are contiguous, otherwise c += b_p · A[:, p] column by column (A transposed).
/// (`k = 0` comes here too: nothing to add.)
#[inline(always)]
fn gemv(
    (m, k): (usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    b_stride: usize,
    c: &mut [f64],
) {
    if k == 0 || m == 0 {
        return;
    }
    let c = &mut c[..m];
    if csa == 1 && b_stride == 1 {
        for (i, ci) in c.iter_mut().enumerate() {
            let row = &a[i * rsa..i * rsa + k];
            // Eight running sums, so the compiler can keep them in one vector register
            // instead of one serial chain of additions.
            let mut lanes = [0.0; 8];
            for (x, y) in row.chunks_exact(8).zip(b.chunks_exact(8)) {
                for l in 0..8 {
                    lanes[l] += x[l] * y[l];
                }
            }
            let tail = k - k % 8;
            let tail_sum: f64 = row[tail..]
                .iter()
                .zip(&b[tail..k])
                .map(|(x, y)| x * y)
                .sum();
            *ci += lanes.iter().sum::<f64>() + tail_sum;
        }
    } else if rsa == 1 {
        for p in 0..k {
            let (column, bp) = (&a[p * csa..p * csa + m], b[p * b_stride]);
            c.iter_mut().zip(column).for_each(|(ci, x)| *ci += bp * x);
        }
    } else {
        for (i, ci) in c.iter_mut().enumerate() {
            *ci += (0..k)
                .map(|p| a[i * rsa + p * csa] * b[p * b_stride])
                .sum::<f64>();
        }
    }
}

/// C += A·B for a few rows, B's rows contiguous (stride `rsb`): each row of C gathers
/// a_ip · B[p, :] over p in order, vectorised across the n columns.
fn small_rows(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    rsb: usize,
    c: &mut [f64],
) {
    for (i, c_row) in c[..m * n].chunks_exact_mut(n).enumerate() {
        for p in 0..k {
            let (a_ip, b_row) = (a[i * rsa + p * csa], &b[p * rsb..p * rsb + n]);
            c_row
                .iter_mut()
                .zip(b_row)
                .for_each(|(cj, bj)| *cj += a_ip * bj);
        }
    }
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
    start: Start,
    finish: Finish,
) {
    check_operands(
        (m, k, n),
        a,
        (rsa, csa),
        b,
        (rsb, csb),
        start,
        finish,
        c.len(),
    );
    begin(&mut c[..m * n], start);
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
            1.0,
            c.as_mut_ptr(),
            n as isize,
            1,
        );
    }
    end_at(&mut c[..m * n], finish, 0);
}

#[allow(clippy::too_many_arguments)]
fn check_operands(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    (rsb, csb): (usize, usize),
    start: Start,
    finish: Finish,
    c_len: usize,
) {
    let fits = |len: usize, rows: usize, cols: usize, rs: usize, cs: usize| {
        rows == 0 || cols == 0 || len > (rows - 1) * rs + (cols - 1) * cs
    };
    assert!(
        fits(a.len(), m, k, rsa, csa) && fits(b.len(), k, n, rsb, csb),
        "gemm operand shorter than its shape and strides"
    );
    assert!(c_len >= m * n, "gemm output shorter than m × n");
    if let Start::Bias(bias) = start {
        assert_eq!(bias.len(), n, "gemm bias of the wrong length");
    }
    if let Finish::TanhDerivative(h) = finish {
        assert!(h.len() >= m * n, "gemm tanh output shorter than m × n");
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use std::arch::x86_64::*;
    use std::cell::RefCell;

    use super::{Finish, Start};

    /// Rows of C per micro-tile: 12 rows × 2 zmm = 24 accumulators, plus the two B
    /// vectors and a broadcast, within the 32 zmm registers.
    const MR: usize = 12;
    /// Columns of C per micro-tile: two zmm of 8 doubles.
    const NR: usize = 16;
    /// k per chunk: a 12 × 256 tile of A (24 KiB) stays in L1 while the packed B panels
    /// (256 × 16 each, 32 KiB) stream from L2.
    const KC: usize = 256;

    thread_local! {
        /// Packing buffers, reused across calls (the blocks of one pass run on the same
        /// few threads).
        static PACKED: RefCell<(Vec<f64>, Vec<f64>)> = const { RefCell::new((Vec::new(), Vec::new())) };
    }

    /// # Safety
    /// The CPU must have AVX-512F; A and B must hold every element their shapes and
    /// strides address; `k > 0`; C must hold `m × n` elements, initialised unless
    /// `start` is `Zero` or `Bias` (then every element is written before it is read);
    /// a bias must hold `n` values and a tanh output `m × n`.
    #[allow(clippy::too_many_arguments)]
    #[target_feature(enable = "avx512f")]
    pub unsafe fn gemm(
        (m, k, n): (usize, usize, usize),
        a: *const f64,
        (rsa, csa): (usize, usize),
        b: *const f64,
        (rsb, csb): (usize, usize),
        c: *mut f64,
        start: Start,
        finish: Finish,
    ) {
        if m == 0 {
            return;
        }
        let panels = n.div_ceil(NR);
        PACKED.with_borrow_mut(|(a_pack, b_pack)| {
            a_pack.resize(MR * KC, 0.0);
            // Panels start on a 64-byte line so that no zmm load splits across two.
            b_pack.resize(panels * NR * KC + 8, 0.0);
            let align = b_pack.as_ptr().align_offset(64);
            let b_pack = &mut b_pack[align..];
            for k0 in (0..k).step_by(KC) {
                let kc = KC.min(k - k0);
                // B[k0.., :] as column panels of NR, each kc × NR row-major, zero-padded.
                for p in 0..panels {
                    let (j0, nr) = (p * NR, NR.min(n - p * NR));
                    let panel = &mut b_pack[p * kc * NR..(p + 1) * kc * NR];
                    // SAFETY: the panel holds kc rows of NR; B holds (k0 + kk, j0..j0 + nr).
                    unsafe {
                        pack_panel(b.wrapping_add(k0 * rsb + j0 * csb), (rsb, csb), nr, panel)
                    };
                }
                let (first, last) = (k0 == 0, k0 + kc == k);
                for i0 in (0..m).step_by(MR) {
                    let mr = MR.min(m - i0);
                    // A row-major (a block of activations, the weights' inputs) is read
                    // in place when its MR rows are whole. A transposed (xᵀ in a weight
                    // gradient: each step's MR values are contiguous, the steps a row
                    // apart) is copied into a contiguous kc × MR panel first, with vector
                    // loads: the kernel then reads one stream instead of kc rows, 3-4%
                    // faster (alternated in one process), and partial panels cost no
                    // element-by-element copy. Anything else goes through the
                    // element-by-element copy below.
                    let (a_tile, a_rs, a_cs) = if rsa == 1 {
                        let (lo, hi) = masks(mr);
                        for kk in 0..kc {
                            let from = a.wrapping_add(i0 + (k0 + kk) * csa);
                            let to = a_pack[kk * MR..].as_mut_ptr();
                            // SAFETY: the unmasked lanes are A's (i0..i0 + mr, k0 + kk);
                            // the panel holds kc rows of MR (12 = 8 + 4 lanes).
                            unsafe {
                                _mm512_storeu_pd(to, _mm512_maskz_loadu_pd(lo, from));
                                _mm512_mask_storeu_pd(
                                    to.add(8),
                                    0x0F,
                                    _mm512_maskz_loadu_pd(hi, from.wrapping_add(8)),
                                );
                            }
                        }
                        (a_pack.as_ptr(), 1, MR)
                    } else if mr == MR && csa == 1 {
                        (a.wrapping_add(i0 * rsa + k0 * csa), rsa, csa)
                    } else {
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
                        (a_pack.as_ptr(), 1, MR)
                    };
                    let rows = c.wrapping_add(i0 * n);
                    for p in 0..panels {
                        let (j0, nr) = (p * NR, NR.min(n - p * NR));
                        let b_panel = b_pack[p * kc * NR..].as_ptr();
                        let tile_start = match start {
                            _ if !first => TileStart::Load,
                            Start::Zero => TileStart::Zero,
                            Start::Accumulate => TileStart::Load,
                            Start::Bias(bias) => TileStart::Bias(bias[j0..].as_ptr()),
                        };
                        let c_tile = rows.wrapping_add(j0);
                        // SAFETY: A's tile holds MR × kc elements through its strides,
                        // the B panel kc × NR; the tile (j0.., mr × nr) lies inside
                        // `rows`; a bias holds n values; the CPU has AVX-512F (caller).
                        unsafe {
                            if a_cs == 1 {
                                kernel::<true>(
                                    kc,
                                    a_tile,
                                    a_rs,
                                    b_panel,
                                    c_tile,
                                    n,
                                    (mr, nr),
                                    tile_start,
                                )
                            } else {
                                kernel::<false>(
                                    kc,
                                    a_tile,
                                    a_cs,
                                    b_panel,
                                    c_tile,
                                    n,
                                    (mr, nr),
                                    tile_start,
                                )
                            }
                        };
                    }
                    if last {
                        // SAFETY: every panel has written its columns of these mr rows.
                        let rows = unsafe { std::slice::from_raw_parts_mut(rows, mr * n) };
                        super::end_at(rows, finish, i0 * n);
                    }
                }
            }
        });
    }

    /// One kc × NR panel of B from `source` (B's element (kk, jj) at `source[kk * rsb +
    /// jj * csb]`), its columns from `nr` on zero: vector copies when B's rows are
    /// contiguous (no library call per row), element by element when transposed.
    ///
    /// # Safety
    /// B must hold (kk, jj) for every kk < panel rows and jj < nr; the CPU has AVX-512F.
    #[target_feature(enable = "avx512f")]
    unsafe fn pack_panel(
        source: *const f64,
        (rsb, csb): (usize, usize),
        nr: usize,
        panel: &mut [f64],
    ) {
        let (mask_lo, mask_hi) = masks(nr);
        for (kk, row) in panel.chunks_exact_mut(NR).enumerate() {
            let from = source.wrapping_add(kk * rsb);
            if csb == 1 {
                // SAFETY: the unmasked lanes are B's (kk, ..nr); the row holds NR values.
                unsafe {
                    let (lo, hi) = (
                        _mm512_maskz_loadu_pd(mask_lo, from),
                        _mm512_maskz_loadu_pd(mask_hi, from.wrapping_add(8)),
                    );
                    _mm512_storeu_pd(row.as_mut_ptr(), lo);
                    _mm512_storeu_pd(row.as_mut_ptr().add(8), hi);
                }
            } else {
                for (jj, value) in row.iter_mut().enumerate() {
                    // SAFETY: (kk, jj) lies inside B's shape when jj < nr.
                    *value = if jj < nr {
                        unsafe { *from.add(jj * csb) }
                    } else {
                        0.0
                    };
                }
            }
        }
    }

    /// Lane masks for the first `count` of 16 columns, as two halves of 8.
    #[inline(always)]
    fn masks(count: usize) -> (__mmask8, __mmask8) {
        let lanes = |count: usize| -> __mmask8 { ((1u32 << count.min(8)) - 1) as __mmask8 };
        (lanes(count), lanes(count.saturating_sub(8)))
    }

    /// [`super::small_rows`] with each row's columns held in registers across the sum
    /// over p (64 at a time) instead of loaded and stored at every p. The same
    /// multiplies and adds in the same order, so the same result to the bit.
    ///
    /// # Safety
    /// The CPU must have AVX-512F; the operands must have passed `check_operands` with
    /// B's column stride 1.
    #[target_feature(enable = "avx512f")]
    pub unsafe fn small_rows(
        (m, k, n): (usize, usize, usize),
        a: &[f64],
        (rsa, csa): (usize, usize),
        b: &[f64],
        rsb: usize,
        c: &mut [f64],
    ) {
        const VECTORS: usize = 8;
        for i in 0..m {
            for j0 in (0..n).step_by(VECTORS * 8) {
                let width = (VECTORS * 8).min(n - j0);
                let mask = |v: usize| -> __mmask8 {
                    let count = width.saturating_sub(v * 8).min(8);
                    ((1u32 << count) - 1) as __mmask8
                };
                let c_row = c[i * n + j0..].as_mut_ptr();
                let mut acc = [_mm512_setzero_pd(); VECTORS];
                for (v, acc) in acc.iter_mut().enumerate() {
                    // SAFETY: the unmasked lanes are C's (i, j0 + 8v..): inside C.
                    *acc = unsafe { _mm512_maskz_loadu_pd(mask(v), c_row.wrapping_add(v * 8)) };
                }
                for p in 0..k {
                    let a_ip = _mm512_set1_pd(a[i * rsa + p * csa]);
                    let b_row = b[p * rsb + j0..].as_ptr();
                    for (v, acc) in acc.iter_mut().enumerate() {
                        // SAFETY: the unmasked lanes are B's (p, j0 + 8v..).
                        let b_v =
                            unsafe { _mm512_maskz_loadu_pd(mask(v), b_row.wrapping_add(v * 8)) };
                        *acc = _mm512_add_pd(*acc, _mm512_mul_pd(a_ip, b_v));
                    }
                }
                for (v, acc) in acc.iter().enumerate() {
                    // SAFETY: as the loads above.
                    unsafe { _mm512_mask_storeu_pd(c_row.wrapping_add(v * 8), mask(v), *acc) };
                }
            }
        }
    }

    /// C (`m × n`) = a·bᵀ for a column `a` (stride `rsa`) and a contiguous row `b`, then
    /// `finish`, a row at a time. Each element is fma(a_i, b_j, 0), as the kernel's
    /// one-step tile computes it (the same bits, the sign of a zero product included).
    ///
    /// # Safety
    /// The CPU must have AVX-512F; the operands must have passed `check_operands` for
    /// k = 1 with B's column stride 1.
    #[target_feature(enable = "avx512f")]
    pub unsafe fn outer(
        (m, n): (usize, usize),
        a: &[f64],
        rsa: usize,
        b: &[f64],
        c: &mut [f64],
        finish: Finish,
    ) {
        let zero = _mm512_setzero_pd();
        let one = _mm512_set1_pd(1.0);
        for (i, row) in c[..m * n].chunks_exact_mut(n).enumerate() {
            let a_i = _mm512_set1_pd(a[i * rsa]);
            for j0 in (0..n).step_by(8) {
                let mask = ((1u32 << (n - j0).min(8)) - 1) as __mmask8;
                // SAFETY: the unmasked lanes are B's (0, j0..) and the row's (j0..).
                unsafe {
                    let mut v = _mm512_fmadd_pd(
                        a_i,
                        _mm512_maskz_loadu_pd(mask, b.as_ptr().wrapping_add(j0)),
                        zero,
                    );
                    if let Finish::TanhDerivative(h) = finish {
                        // d ⊙ (1 − h²), the operations of `end_at`.
                        let h = _mm512_maskz_loadu_pd(mask, h.as_ptr().wrapping_add(i * n + j0));
                        v = _mm512_mul_pd(v, _mm512_sub_pd(one, _mm512_mul_pd(h, h)));
                    }
                    _mm512_mask_storeu_pd(row.as_mut_ptr().wrapping_add(j0), mask, v);
                }
            }
            if let Finish::Tanh = finish {
                crate::kernels::tanh::tanh_f64_in_place(row);
            }
        }
    }

    /// [`super::gemv`] compiled for AVX-512 (the same code: same result to the bit).
    ///
    /// # Safety
    /// The CPU must have AVX-512F; the operands must have passed `check_operands`.
    #[target_feature(enable = "avx512f")]
    pub unsafe fn gemv(
        dims: (usize, usize),
        a: &[f64],
        a_strides: (usize, usize),
        b: &[f64],
        b_stride: usize,
        c: &mut [f64],
    ) {
        super::gemv(dims, a, a_strides, b, b_stride, c);
    }

    /// What a tile's accumulators start from.
    #[derive(Clone, Copy)]
    enum TileStart {
        Zero,
        /// C's current values.
        Load,
        /// The same row of biases for every row.
        Bias(*const f64),
    }

    /// C[..mr, ..nr] = `start` + A_tile · B_panel over `kc`, C with row stride `ldc`. A's element
    /// (r, kk) is at `a[r * a_stride + kk]` when `ROWS_CONTIGUOUS` (a row-major operand),
    /// else at `a[kk * a_stride + r]` (a transposed one, or the packed panel).
    #[allow(clippy::too_many_arguments)]
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn kernel<const ROWS_CONTIGUOUS: bool>(
        kc: usize,
        a: *const f64,
        a_stride: usize,
        b: *const f64,
        c: *mut f64,
        ldc: usize,
        (mr, nr): (usize, usize),
        start: TileStart,
    ) {
        let (mask_lo, mask_hi) = masks(nr);
        let mut acc = [[_mm512_setzero_pd(); 2]; MR];
        match start {
            TileStart::Zero => {}
            TileStart::Load => {
                // Over all MR rows with a test (not `take(mr)`): a loop of constant length
                // is unrolled and the accumulators stay in registers instead of going
                // through the stack around the product.
                for (r, row) in acc.iter_mut().enumerate() {
                    if r >= mr {
                        continue;
                    }
                    // Masked lanes are never read, so the pointers may run past C's end.
                    let c_row = c.wrapping_add(r * ldc);
                    // SAFETY: the unmasked lanes are C's elements (r, ..nr).
                    unsafe {
                        row[0] = _mm512_maskz_loadu_pd(mask_lo, c_row);
                        row[1] = _mm512_maskz_loadu_pd(mask_hi, c_row.wrapping_add(8));
                    }
                }
            }
            TileStart::Bias(bias) => {
                // SAFETY: the unmasked lanes are the biases of columns ..nr.
                let (lo, hi) = unsafe {
                    (
                        _mm512_maskz_loadu_pd(mask_lo, bias),
                        _mm512_maskz_loadu_pd(mask_hi, bias.wrapping_add(8)),
                    )
                };
                acc.iter_mut().for_each(|row| *row = [lo, hi]);
            }
        }
        if ROWS_CONTIGUOUS {
            // SAFETY: passed on from the caller (MR rows of kc elements, kc > 0).
            unsafe { rows_loop(kc, a, a_stride, b, &mut acc) };
        } else {
            for kk in 0..kc {
                // SAFETY: the B panel holds kc rows of NR.
                let (b0, b1) = unsafe {
                    (
                        _mm512_loadu_pd(b.add(kk * NR)),
                        _mm512_loadu_pd(b.add(kk * NR + 8)),
                    )
                };
                let column = a.wrapping_add(kk * a_stride);
                for (r, row) in acc.iter_mut().enumerate() {
                    // SAFETY: A's tile holds kc columns of MR elements (caller).
                    let a_r = _mm512_set1_pd(unsafe { *column.add(r) });
                    row[0] = _mm512_fmadd_pd(a_r, b0, row[0]);
                    row[1] = _mm512_fmadd_pd(a_r, b1, row[1]);
                }
            }
        }
        for (r, row) in acc.iter().enumerate() {
            if r >= mr {
                continue;
            }
            let c_row = c.wrapping_add(r * ldc);
            // SAFETY: the unmasked lanes are C's elements (r, ..nr).
            unsafe {
                _mm512_mask_storeu_pd(c_row, mask_lo, row[0]);
                _mm512_mask_storeu_pd(c_row.wrapping_add(8), mask_hi, row[1]);
            }
        }
    }

    /// acc[r] += Σ_kk A[r, kk] · B[kk, :] for a row-major A tile (row stride `a_stride`)
    /// and a packed B panel: the kernel's loop, written out because the compiler,
    /// short of registers for twelve row pointers, recomputes each row's address with a
    /// chain of adds on every step (12 extra µops per 24 FMAs: a tenth slower). Here
    /// three pointers (rows 0, 4, 8) move along k and rows +1, +2, +3 are addressed
    /// through the stride and 3 × stride: 45 µops per step, under the 12 cycles its
    /// 24 FMAs take. It also prefetches the B panel 8 steps ahead (1-4% on a critic
    /// evaluation, alternated in one process). The FMAs are the same as the loop's, in
    /// the same order.
    ///
    /// # Safety
    /// The CPU must have AVX-512F; `kc > 0`; A holds rows 0..12 of kc elements at
    /// `a + r · a_stride`; the B panel holds kc rows of 16 (64-byte aligned or not).
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn rows_loop(
        kc: usize,
        a: *const f64,
        a_stride: usize,
        b: *const f64,
        acc: &mut [[__m512d; 2]; MR],
    ) {
        let stride = a_stride * 8;
        let [
            [c00, c01],
            [c10, c11],
            [c20, c21],
            [c30, c31],
            [c40, c41],
            [c50, c51],
            [c60, c61],
            [c70, c71],
            [c80, c81],
            [c90, c91],
            [ca0, ca1],
            [cb0, cb1],
        ] = acc;
        // SAFETY: reads A's 12 × kc tile and B's kc × 16 panel only (caller), writes
        // only the named registers, touches no stack.
        unsafe {
            std::arch::asm!(
                "2:",
                "vmovupd {b0}, zmmword ptr [{bp}]",
                "vmovupd {b1}, zmmword ptr [{bp} + 64]",
                "prefetcht0 [{bp} + 1024]",
                "prefetcht0 [{bp} + 1088]",
                "vbroadcastsd {t}, qword ptr [{a0}]",
                "vfmadd231pd {c00}, {t}, {b0}",
                "vfmadd231pd {c01}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a0} + {s}]",
                "vfmadd231pd {c10}, {t}, {b0}",
                "vfmadd231pd {c11}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a0} + {s}*2]",
                "vfmadd231pd {c20}, {t}, {b0}",
                "vfmadd231pd {c21}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a0} + {s3}]",
                "vfmadd231pd {c30}, {t}, {b0}",
                "vfmadd231pd {c31}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a4}]",
                "vfmadd231pd {c40}, {t}, {b0}",
                "vfmadd231pd {c41}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a4} + {s}]",
                "vfmadd231pd {c50}, {t}, {b0}",
                "vfmadd231pd {c51}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a4} + {s}*2]",
                "vfmadd231pd {c60}, {t}, {b0}",
                "vfmadd231pd {c61}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a4} + {s3}]",
                "vfmadd231pd {c70}, {t}, {b0}",
                "vfmadd231pd {c71}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a8}]",
                "vfmadd231pd {c80}, {t}, {b0}",
                "vfmadd231pd {c81}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a8} + {s}]",
                "vfmadd231pd {c90}, {t}, {b0}",
                "vfmadd231pd {c91}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a8} + {s}*2]",
                "vfmadd231pd {ca0}, {t}, {b0}",
                "vfmadd231pd {ca1}, {t}, {b1}",
                "vbroadcastsd {t}, qword ptr [{a8} + {s3}]",
                "vfmadd231pd {cb0}, {t}, {b0}",
                "vfmadd231pd {cb1}, {t}, {b1}",
                "add {a0}, 8",
                "add {a4}, 8",
                "add {a8}, 8",
                "add {bp}, 128",
                "dec {count}",
                "jnz 2b",
                a0 = inout(reg) a => _,
                a4 = inout(reg) a.wrapping_add(4 * a_stride) => _,
                a8 = inout(reg) a.wrapping_add(8 * a_stride) => _,
                bp = inout(reg) b => _,
                count = inout(reg) kc => _,
                s = in(reg) stride,
                s3 = in(reg) 3 * stride,
                b0 = out(zmm_reg) _,
                b1 = out(zmm_reg) _,
                t = out(zmm_reg) _,
                c00 = inout(zmm_reg) *c00,
                c01 = inout(zmm_reg) *c01,
                c10 = inout(zmm_reg) *c10,
                c11 = inout(zmm_reg) *c11,
                c20 = inout(zmm_reg) *c20,
                c21 = inout(zmm_reg) *c21,
                c30 = inout(zmm_reg) *c30,
                c31 = inout(zmm_reg) *c31,
                c40 = inout(zmm_reg) *c40,
                c41 = inout(zmm_reg) *c41,
                c50 = inout(zmm_reg) *c50,
                c51 = inout(zmm_reg) *c51,
                c60 = inout(zmm_reg) *c60,
                c61 = inout(zmm_reg) *c61,
                c70 = inout(zmm_reg) *c70,
                c71 = inout(zmm_reg) *c71,
                c80 = inout(zmm_reg) *c80,
                c81 = inout(zmm_reg) *c81,
                c90 = inout(zmm_reg) *c90,
                c91 = inout(zmm_reg) *c91,
                ca0 = inout(zmm_reg) *ca0,
                ca1 = inout(zmm_reg) *ca1,
                cb0 = inout(zmm_reg) *cb0,
                cb1 = inout(zmm_reg) *cb1,
                options(nostack, readonly),
            );
        }
    }
}
