//! The kernels' GEMM (the `gemm` crate, and the direct product for a few rows) against a
//! plain triple loop, over the shapes that exercise its edges: a few rows, one column,
//! k = 0 and 1, partial tiles, transposed operands, accumulate or not, and the fused
//! bias / tanh starts and finishes.

use logo_nn::kernels::gemm::{Finish, Start, gemm, gemm_to_vec};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn reference(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (rsa, csa): (usize, usize),
    b: &[f64],
    (rsb, csb): (usize, usize),
    c: &mut [f64],
    accumulate: bool,
) -> Vec<f64> {
    // Also returns Σ|a||b| per element: the scale the rounding error is relative to.
    let mut scale = vec![0.0; m * n];
    for i in 0..m {
        for j in 0..n {
            let mut sum = if accumulate { c[i * n + j] } else { 0.0 };
            let mut abs = sum.abs();
            for p in 0..k {
                let product = a[i * rsa + p * csa] * b[p * rsb + j * csb];
                sum += product;
                abs += product.abs();
            }
            c[i * n + j] = sum;
            scale[i * n + j] = abs;
        }
    }
    scale
}

fn start(accumulate: bool) -> Start<'static, f64> {
    if accumulate {
        Start::Accumulate
    } else {
        Start::Zero
    }
}

#[test]
fn gemm_matches_the_definition_on_every_edge() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut checked = 0;
    let shapes = [
        (1, 1, 1),
        (12, 256, 16),
        (13, 257, 17),
        (11, 1024, 128),
        (128, 1024, 128),
        (1024, 128, 128),
        (1000, 11, 128),
        (300, 128, 1),
        (5, 0, 7),
        (0, 5, 7),
        (25, 600, 3),
        (37, 33, 40),
        // A few rows (acting): the direct product, columns in and across chunks of 64.
        (3, 130, 70),
        (4, 11, 128),
        (2, 64, 200),
        // One column (a value net's output layer).
        (128, 256, 1),
        (70, 3, 1),
        // k = 1: an outer product (a net's output layer, backwards).
        (300, 1, 128),
        (37, 1, 20),
    ];
    for &(m, k, n) in &shapes {
        for transposed_a in [false, true] {
            for transposed_b in [false, true] {
                for accumulate in [false, true] {
                    let sa = if transposed_a { (1, m) } else { (k, 1) };
                    let sb = if transposed_b { (1, k) } else { (n, 1) };
                    let a: Vec<f64> = (0..m * k).map(|_| rng.random_range(-1.0..1.0)).collect();
                    let b: Vec<f64> = (0..k * n).map(|_| rng.random_range(-1.0..1.0)).collect();
                    let c0: Vec<f64> = (0..m * n).map(|_| rng.random_range(-1.0..1.0)).collect();
                    let mut expected = c0.clone();
                    let scale = reference((m, k, n), &a, sa, &b, sb, &mut expected, accumulate);
                    let mut fast = c0.clone();
                    gemm(
                        (m, k, n),
                        &a,
                        sa,
                        &b,
                        sb,
                        &mut fast,
                        start(accumulate),
                        Finish::None,
                    );
                    for idx in 0..m * n {
                        let err = (fast[idx] - expected[idx]).abs();
                        assert!(
                            err <= 1e-14 * (scale[idx] + 1.0),
                            "{m}x{k}x{n} ta={transposed_a} tb={transposed_b} \
                             acc={accumulate} at {idx}: {} vs {}",
                            fast[idx],
                            expected[idx]
                        );
                    }
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, shapes.len() * 8);
}

#[test]
fn gemm_writes_only_its_output() {
    // C is a slice into a longer buffer: nothing past m × n may change.
    let (m, k, n) = (13, 20, 9);
    let a = vec![1.0; m * k];
    let b = vec![1.0; k * n];
    let mut buffer = vec![-3.0; m * n + 40];
    gemm(
        (m, k, n),
        &a,
        (k, 1),
        &b,
        (n, 1),
        &mut buffer[..m * n],
        Start::Zero,
        Finish::None,
    );
    assert!(buffer[..m * n].iter().all(|&v| v == k as f64));
    assert!(buffer[m * n..].iter().all(|&v| v == -3.0));
}

#[test]
fn bias_and_tanh_finishes_match_the_separate_passes() {
    // Start::Bias then Finish::Tanh == bias + A·B then tanh; Finish::TanhDerivative(h)
    // == (A·B) ⊙ (1 − h²); on shapes with partial tiles, few rows, k = 0 and k = 1.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for &(m, k, n) in &[
        (13, 130, 17),
        (256, 128, 128),
        (300, 11, 1),
        (5, 0, 9),
        (300, 1, 128),
        (7, 1, 13),
    ] {
        let a: Vec<f64> = (0..m * k).map(|_| rng.random_range(-0.3..0.3)).collect();
        let b: Vec<f64> = (0..k * n).map(|_| rng.random_range(-0.3..0.3)).collect();
        let bias: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let h: Vec<f64> = (0..m * n).map(|_| rng.random_range(-1.0..1.0)).collect();
        let mut product = vec![0.0; m * n];
        let scale = reference((m, k, n), &a, (k, 1), &b, (n, 1), &mut product, false);
        let pre: Vec<f64> = product
            .iter()
            .enumerate()
            .map(|(i, p)| p + bias[i % n])
            .collect();
        let tanh: Vec<f64> = pre.iter().map(|z| z.tanh()).collect();
        let back: Vec<f64> = product
            .iter()
            .zip(&h)
            .map(|(p, h)| p * (1.0 - h * h))
            .collect();
        // Each fused finish against its separate passes: within 1e-14 of the product's
        // scale plus a slack for what the finish adds (the bias; the factor 1 − h²).
        let finishes = [
            ("tanh", Start::Bias(&bias), Finish::Tanh, &tanh, 2.0),
            ("tanh'", Start::Zero, Finish::TanhDerivative(&h), &back, 1.0),
        ];
        for (name, start, finish, expected, slack) in finishes {
            let mut got = vec![f64::NAN; m * n];
            gemm((m, k, n), &a, (k, 1), &b, (n, 1), &mut got, start, finish);
            for i in 0..m * n {
                assert!(
                    (got[i] - expected[i]).abs() <= 1e-14 * (scale[i] + slack),
                    "{name} {m}x{k}x{n} at {i}"
                );
            }
        }
    }
}

#[test]
fn gemm_to_vec_equals_gemm_into_a_zeroed_buffer() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for &(m, k, n) in &[
        (13, 300, 17),
        (256, 128, 128),
        (7, 11, 1),
        (4, 0, 5),
        (0, 3, 4),
    ] {
        for transposed_a in [false, true] {
            let sa = if transposed_a { (1, m) } else { (k, 1) };
            let a: Vec<f64> = (0..m * k).map(|_| rng.random_range(-0.5..0.5)).collect();
            let b: Vec<f64> = (0..k * n).map(|_| rng.random_range(-0.5..0.5)).collect();
            let bias: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            for (start, finish) in [
                (Start::Zero, Finish::None),
                (Start::Bias(&bias), Finish::Tanh),
            ] {
                let mut expected = vec![0.0; m * n];
                gemm((m, k, n), &a, sa, &b, (n, 1), &mut expected, start, finish);
                let got = gemm_to_vec((m, k, n), &a, sa, &b, (n, 1), start, finish);
                assert_eq!(got, expected, "{m}x{k}x{n} transposed_a={transposed_a}");
            }
        }
    }
}
