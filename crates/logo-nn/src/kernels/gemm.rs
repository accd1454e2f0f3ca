//! C = start + A·B, then a finish (tanh, ⊙(1 − h²)), for the host MLP, in float64 or
//! float32: the `gemm` crate's kernels (the ones faer and candle use; AVX2, AVX-512 and
//! NEON chosen at run time) for every product, and a direct loop for a few rows
//! (acting), where packing B for a tiled kernel would cost more than the product.
//! docs/benchmarks.md has the measurement behind the choice.
//!
//! Determinism: the result depends only on the operands (the library is called
//! single-threaded; the host MLP parallelises over row blocks itself).

use super::float::KernelFloat;

/// Where C starts from before A·B is added.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a, F> {
    /// C = A·B.
    Zero,
    /// C += A·B.
    Accumulate,
    /// C = bias + A·B, the `n` biases added to every row (a layer's pre-activation).
    Bias(&'a [F]),
}

/// What is done to C once the product is in.
#[derive(Debug, Clone, Copy)]
pub enum Finish<'a, F> {
    None,
    /// C ← tanh(C): a hidden layer's activation.
    Tanh,
    /// C ← C ⊙ (1 − h²), `h` laid out like C: back through a tanh whose output was h.
    TanhDerivative(&'a [F]),
}

/// Up to this many rows of C, [`gemm`] multiplies directly (when B's rows are
/// contiguous) instead of calling the library.
const SMALL_ROWS: usize = 4;

/// C (`m × n`, row-major, dense) = `start` + A·B, then `finish`. A is `m × k` and B
/// `k × n`, each read through explicit (row, column) strides, so a transposed operand is
/// just swapped strides.
#[allow(clippy::too_many_arguments)]
pub fn gemm<F: KernelFloat>(
    (m, k, n): (usize, usize, usize),
    a: &[F],
    a_strides: (usize, usize),
    b: &[F],
    b_strides: (usize, usize),
    c: &mut [F],
    start: Start<F>,
    finish: Finish<F>,
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
    let c = &mut c[..m * n];
    let direct = m <= SMALL_ROWS && b_strides.1 == 1;
    // From zero the library overwrites C itself (`read_dst` false): no fill first.
    let overwrite = matches!(start, Start::Zero) && k > 0 && !direct;
    if !overwrite {
        begin(c, start);
    }
    if direct {
        small_rows((m, k, n), a, a_strides, b, b_strides.0, c);
    } else if m > 0 && n > 0 && k > 0 {
        // SAFETY: `check_operands` keeps every index the product reads inside `a` and
        // `b`, and C is the dense m × n slice written here (row stride n, column stride 1).
        unsafe {
            gemm::gemm(
                m,
                n,
                k,
                c.as_mut_ptr(),
                1,
                n as isize,
                !overwrite,
                a.as_ptr(),
                a_strides.1 as isize,
                a_strides.0 as isize,
                b.as_ptr(),
                b_strides.1 as isize,
                b_strides.0 as isize,
                F::ONE,
                F::ONE,
                false,
                false,
                false,
                gemm::Parallelism::None,
            )
        };
    }
    end(c, finish);
}

/// [`gemm`] into a new `m × n` buffer; `start` is `Zero` or `Bias`. The buffer is not
/// zero-filled first: the start (a bias row per row) or the product itself (from zero)
/// writes every element before anything reads it.
#[allow(clippy::too_many_arguments)]
pub fn gemm_to_vec<F: KernelFloat>(
    (m, k, n): (usize, usize, usize),
    a: &[F],
    a_strides: (usize, usize),
    b: &[F],
    b_strides: (usize, usize),
    start: Start<F>,
    finish: Finish<F>,
) -> Vec<F> {
    assert!(
        !matches!(start, Start::Accumulate),
        "a new buffer has nothing to accumulate into"
    );
    let direct = m <= SMALL_ROWS && b_strides.1 == 1;
    let overwritten = matches!(start, Start::Zero) && k > 0 && !direct && m > 0 && n > 0;
    let mut c: Vec<F> = Vec::with_capacity(m * n);
    match start {
        Start::Bias(bias) if n > 0 => {
            assert_eq!(bias.len(), n, "gemm bias of the wrong length");
            for row in c.spare_capacity_mut()[..m * n].chunks_exact_mut(n) {
                // SAFETY: `row` is n uninitialised elements of `c`'s spare capacity and
                // `bias` n initialised ones; the two do not overlap.
                unsafe {
                    std::ptr::copy_nonoverlapping(bias.as_ptr(), row.as_mut_ptr().cast::<F>(), n)
                };
            }
        }
        _ if overwritten => {}
        _ => c.spare_capacity_mut()[..m * n].iter_mut().for_each(|slot| {
            slot.write(F::ZERO);
        }),
    }
    // SAFETY: every element is initialised: by the bias rows or zeros just written, or
    // (from zero, through the library) by the product, which writes all of C without
    // reading it; `gemm` below is told C already holds its start.
    unsafe { c.set_len(m * n) };
    gemm(
        (m, k, n),
        a,
        a_strides,
        b,
        b_strides,
        &mut c,
        if overwritten {
            Start::Zero
        } else {
            Start::Accumulate
        },
        finish,
    );
    c
}

/// C = `start` (all of C).
fn begin<F: KernelFloat>(c: &mut [F], start: Start<F>) {
    match start {
        Start::Zero => c.fill(F::ZERO),
        Start::Accumulate => {}
        Start::Bias(bias) => c
            .chunks_exact_mut(bias.len())
            .for_each(|row| row.copy_from_slice(bias)),
    }
}

/// `finish` applied to `c`.
fn end<F: KernelFloat>(c: &mut [F], finish: Finish<F>) {
    match finish {
        Finish::None => {}
        Finish::Tanh => F::tanh_in_place(c),
        Finish::TanhDerivative(h) => tanh_derivative(c, h),
    }
}

/// c ← c ⊙ (1 − h²). Element-wise, so every vector width gives the same bits;
/// `multiversion` compiles it for AVX-512 and AVX2 besides the baseline's SSE2.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
fn tanh_derivative<F: KernelFloat>(c: &mut [F], h: &[F]) {
    c.iter_mut()
        .zip(h)
        .for_each(|(d, h)| *d *= F::ONE - *h * *h);
}

/// C += A·B for a few rows, B's rows contiguous (stride `rsb`): each row of C gathers
/// a_ip · B[p, :] over p in order, vectorised across the n columns (a multiply, then an
/// add: never fused, so every copy `multiversion` makes gives the same bits).
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
fn small_rows<F: KernelFloat>(
    (m, k, n): (usize, usize, usize),
    a: &[F],
    (rsa, csa): (usize, usize),
    b: &[F],
    rsb: usize,
    c: &mut [F],
) {
    for (i, c_row) in c[..m * n].chunks_exact_mut(n.max(1)).enumerate() {
        for p in 0..k {
            let (a_ip, b_row) = (a[i * rsa + p * csa], &b[p * rsb..p * rsb + n]);
            c_row
                .iter_mut()
                .zip(b_row)
                .for_each(|(cj, bj)| *cj += a_ip * *bj);
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn check_operands<F>(
    (m, k, n): (usize, usize, usize),
    a: &[F],
    (rsa, csa): (usize, usize),
    b: &[F],
    (rsb, csb): (usize, usize),
    start: Start<F>,
    finish: Finish<F>,
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The same product with its operands placed at every offset (in elements) within
    /// a 64-byte line: bit-identical results, or a run resumed in a fresh process (whose
    /// buffers lie elsewhere) would drift from the one never stopped.
    fn same_bits_wherever_the_operands_lie<F: KernelFloat>() {
        let (m, k, n) = (67, 33, 29);
        let value = |i: usize| F::from_f64(((i * 7919) % 1000) as f64 / 997.0 - 0.5);
        let place = |len: usize, offset: usize| -> Vec<F> {
            (0..len + offset)
                .map(|i| value(i.wrapping_sub(offset)))
                .collect()
        };
        let product = |offset: usize, b_transposed: bool| -> Vec<F> {
            let (b_at, c_at) = ((offset * 3) % 16, (offset * 5) % 16);
            let (a, b) = (place(m * k, offset), place(k * n, b_at));
            let b_strides = if b_transposed { (1, k) } else { (n, 1) };
            let mut c = vec![F::ZERO; m * n + c_at];
            gemm(
                (m, k, n),
                &a[offset..],
                (k, 1),
                &b[b_at..],
                b_strides,
                &mut c[c_at..],
                Start::Zero,
                Finish::None,
            );
            c.split_off(c_at)
        };
        for b_transposed in [false, true] {
            let first = product(0, b_transposed);
            for offset in 1..16 {
                let got = product(offset, b_transposed);
                let differ = first
                    .iter()
                    .zip(&got)
                    .filter(|(x, y)| x.to_f64().to_bits() != y.to_f64().to_bits())
                    .count();
                assert_eq!(differ, 0, "offset {offset}, B transposed {b_transposed}");
            }
        }
    }

    #[test]
    fn float64_products_do_not_depend_on_alignment() {
        same_bits_wherever_the_operands_lie::<f64>();
    }

    #[test]
    fn float32_products_do_not_depend_on_alignment() {
        same_bits_wherever_the_operands_lie::<f32>();
    }
}
