//! An MLP (the burn definition of `crate::mlp`) on plain host buffers of F or f32: the kernels
//! engine's forward pass, reverse product Jᵀ·u and Gauss–Newton product, for the CPU hot
//! loops (the critics' L-BFGS fits, the policy gradient, the Fisher-vector products), which
//! evaluate the same network on the same batch 10–60 times per step.
//!
//! Parameters and cached activations stay on the host between calls, bias and tanh are
//! fused into the products, and the batch is cut into fixed blocks that run on rayon's
//! threads. The tests in `tests/kernels.rs` hold every product to the burn definition.
//!
//! Determinism: the blocks are a fixed partition of the rows (not of the threads), and
//! per-block parameter gradients are summed in block order, so results are bit-identical
//! whatever the number of threads.

use rayon::prelude::*;

use super::float::KernelFloat;
use super::gemm::{Finish, Start, gemm, gemm_to_vec};
use crate::mlp::num_params;

/// Rows per block: small enough that a block's activations (256 × 128 × 8 B = 256 KiB
/// each) stay in a core's 1 MiB L2 while the next layer reads them, and that a 5k-row
/// batch splits evenly over two threads; large enough for the GEMM to run at full speed.
pub const BLOCK_ROWS: usize = 256;

/// An MLP's layer sizes and flat parameters, laid out as [`crate::flat::params_to_vec`]
/// lays out a [`crate::Mlp`]: for each layer, weight `[in, out]` row-major, then bias `[out]`.
#[derive(Debug, Clone, PartialEq)]
pub struct HostMlp<F: KernelFloat = f64> {
    /// `[input, hidden..., output]`.
    pub dims: Vec<usize>,
    pub params: Vec<F>,
}

/// The activations of every block of a batch: `[x, h1, ..., output]` per block.
pub struct HostTrace<F: KernelFloat = f64> {
    rows: usize,
    output_dim: usize,
    blocks: Vec<Vec<Vec<F>>>,
}

impl<F: KernelFloat> HostTrace<F> {
    pub fn rows(&self) -> usize {
        self.rows
    }

    pub fn output_dim(&self) -> usize {
        self.output_dim
    }

    /// The network's output for every row, `[rows, out]` row-major.
    pub fn output(&self) -> Vec<F> {
        self.blocks
            .iter()
            .flat_map(|acts| acts.last().expect("a trace has an output").iter().copied())
            .collect()
    }
}

impl<F: KernelFloat> HostMlp<F> {
    pub fn new(dims: Vec<usize>, params: Vec<F>) -> Self {
        assert!(dims.len() >= 2, "an MLP has at least one layer");
        assert_eq!(
            params.len(),
            num_params(&dims),
            "parameters of the wrong length"
        );
        Self { dims, params }
    }

    pub fn input_dim(&self) -> usize {
        self.dims[0]
    }

    pub fn output_dim(&self) -> usize {
        *self.dims.last().expect("dims is not empty")
    }

    pub fn num_params(&self) -> usize {
        self.params.len()
    }

    /// (weight, bias) of layer `i` within a flat vector laid out like `params`.
    fn layer<'a>(&self, flat: &'a [F], i: usize) -> (&'a [F], &'a [F]) {
        let offset = num_params(&self.dims[..=i]);
        let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
        let w = &flat[offset..offset + fan_in * fan_out];
        (
            w,
            &flat[offset + fan_in * fan_out..offset + fan_in * fan_out + fan_out],
        )
    }

    fn layers(&self) -> usize {
        self.dims.len() - 1
    }

    /// Σ fan_in · fan_out over `layers`: one row's multiply-adds through them.
    fn products(&self, layers: std::ops::Range<usize>) -> u64 {
        layers
            .map(|i| (self.dims[i] * self.dims[i + 1]) as u64)
            .sum()
    }

    /// The activations of `x` (`[rows, input]` row-major).
    pub fn trace(&self, x: &[F]) -> HostTrace<F> {
        let input = self.input_dim();
        assert_eq!(x.len() % input, 0, "input rows of the wrong width");
        crate::flops::add(2 * (x.len() / input) as u64 * self.products(0..self.layers()));
        // One block (rollouts, evaluation) runs inline: a trip through rayon's pool
        // costs more than a forward pass at batch 1.
        let blocks = if x.len() <= BLOCK_ROWS * input {
            vec![self.trace_block(x)]
        } else {
            x.par_chunks(BLOCK_ROWS * input)
                .map(|block| self.trace_block(block))
                .collect()
        };
        HostTrace {
            rows: x.len() / input,
            output_dim: self.output_dim(),
            blocks,
        }
    }

    fn trace_block(&self, x: &[F]) -> Vec<Vec<F>> {
        let rows = x.len() / self.input_dim();
        let mut acts = Vec::with_capacity(self.dims.len());
        acts.push(x.to_vec());
        for i in 0..self.layers() {
            let (w, b) = self.layer(&self.params, i);
            let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
            let hidden = i + 1 < self.layers();
            let z = gemm_to_vec(
                (rows, fan_in, fan_out),
                &acts[i],
                (fan_in, 1),
                w,
                (fan_out, 1),
                Start::Bias(b),
                if hidden { Finish::Tanh } else { Finish::None },
            );
            acts.push(z);
        }
        acts
    }

    /// The output for every row of `x`.
    pub fn forward(&self, x: &[F]) -> Vec<F> {
        self.trace(x).output()
    }

    /// ∂output/∂z of every hidden layer but the last, at the rows of `trace`: what
    /// [`Self::gauss_newton_product`] needs besides the trace. Costs `output_dim` reverse
    /// passes through those layers, once per batch.
    pub fn output_sensitivities(&self, trace: &HostTrace<F>) -> OutputSensitivities<F> {
        let transposed = self.transposed_weights();
        let (layers, outputs) = (self.layers(), self.output_dim());
        let below_last_hidden = 1..layers.saturating_sub(1);
        crate::flops::add(2 * (trace.rows * outputs) as u64 * self.products(below_last_hidden));
        let blocks = trace
            .blocks
            .par_iter()
            .map(|acts| {
                let rows = acts[0].len() / self.input_dim();
                // sens[i][k]: ∂output_k/∂z_i, [rows, dims[i + 1]] row-major, for the hidden
                // layers i < layers - 2, built back from the last hidden layer's, which is
                // (1 − h²) ⊙ W[:, k] of the output layer W and is not kept.
                if layers < 3 {
                    return Vec::new();
                }
                let (w_out, _) = self.layer(&self.params, layers - 1);
                let units = self.dims[layers - 1];
                let h = &acts[layers - 1];
                let last_hidden: Vec<Vec<F>> = (0..outputs)
                    .map(|k| {
                        let column: Vec<F> =
                            w_out.iter().skip(k).step_by(outputs).copied().collect();
                        h.chunks_exact(units)
                            .flat_map(|row| {
                                row.iter()
                                    .zip(&column)
                                    .map(|(h, w)| (F::ONE - *h * *h) * *w)
                            })
                            .collect()
                    })
                    .collect();
                let mut sens: Vec<Vec<Vec<F>>> = vec![Vec::new(); layers - 2];
                for i in (0..layers - 2).rev() {
                    let above = sens.get(i + 1).unwrap_or(&last_hidden);
                    let (fan_in, fan_out) = (self.dims[i + 1], self.dims[i + 2]);
                    let below: Vec<Vec<F>> = above
                        .iter()
                        .map(|s| {
                            gemm_to_vec(
                                (rows, fan_out, fan_in),
                                s,
                                (fan_out, 1),
                                &transposed[i],
                                (fan_in, 1),
                                Start::Zero,
                                Finish::TanhDerivative(&acts[i + 1]),
                            )
                        })
                        .collect();
                    sens[i] = below;
                }
                sens
            })
            .collect();
        OutputSensitivities { blocks, transposed }
    }

    /// Σ_rows J_rᵀ diag(`output_weights`) J_r `tangent`, J_r the Jacobian of row r's output
    /// with respect to the parameters (`tangent` and the result laid out like `params`):
    /// the Gauss–Newton (for a Gaussian policy's mean, Fisher) matrix times a vector.
    ///
    /// Exact, and cheaper than a forward-mode pass followed by a reverse one: with the
    /// sensitivities ∂output/∂z cached, each layer contributes x·dW + db contracted with
    /// them, and receives xᵀ·(sensitivities · u), so a hidden-to-hidden layer costs two
    /// matrix products per call instead of four (the dx·W of the forward-mode pass and the
    /// dz·Wᵀ of the reverse one are gone). The last hidden layer's sensitivities are
    /// (1 − h²) ⊙ W_out, applied on the fly. Each block runs both halves while its
    /// activations are in cache.
    pub fn gauss_newton_product(
        &self,
        trace: &HostTrace<F>,
        sensitivities: &OutputSensitivities<F>,
        tangent: &[F],
        output_weights: &[F],
    ) -> Vec<F> {
        assert_eq!(
            tangent.len(),
            self.num_params(),
            "tangent of the wrong length"
        );
        assert_eq!(
            output_weights.len(),
            self.output_dim(),
            "one weight per output"
        );
        assert_eq!(
            sensitivities.blocks.len(),
            trace.blocks.len(),
            "sensitivities of another trace"
        );
        // J·v: every layer's x·dW, carried to the outputs (its fan_out × outputs); Jᵀ·u:
        // every layer's xᵀ·g and 1ᵀ·g, g from the outputs likewise.
        let outputs = self.output_dim() as u64;
        let carried: u64 = self.dims[1..self.dims.len() - 1]
            .iter()
            .map(|&w| w as u64)
            .sum();
        let per_row = 2 * self.products(0..self.layers())
            + 2 * carried * outputs
            + self.dims[1..].iter().map(|&w| w as u64).sum::<u64>();
        crate::flops::add(2 * trace.rows as u64 * per_row);
        let per_block: Vec<Vec<F>> = trace
            .blocks
            .par_iter()
            .zip(&sensitivities.blocks)
            .map(|(acts, sens)| {
                let jv = self.jvp_block(acts, sens, tangent);
                let upstream: Vec<F> = jv
                    .chunks_exact(self.output_dim())
                    .flat_map(|row| row.iter().zip(output_weights).map(|(x, w)| *x * *w))
                    .collect();
                self.jtu_block(acts, sens, &upstream, &sensitivities.transposed)
            })
            .collect();
        sum_in_order(self.num_params(), &per_block)
    }

    /// J·tangent for one block, `[rows, out]`: every layer's direct term x·dW + db, carried
    /// to the output by the cached sensitivities (the hidden layers before the last), by
    /// (1 − h²) and W_out (the last hidden layer), or as it is (the output layer).
    fn jvp_block(&self, acts: &[Vec<F>], sens: &[Vec<Vec<F>>], tangent: &[F]) -> Vec<F> {
        let (layers, outputs) = (self.layers(), self.output_dim());
        let rows = acts[0].len() / self.input_dim();
        let mut jv = vec![F::ZERO; rows * outputs];
        for i in 0..layers {
            let (dw, db) = self.layer(tangent, i);
            let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
            let last_hidden = i + 2 == layers;
            let finish = if last_hidden {
                Finish::TanhDerivative(&acts[i + 1])
            } else {
                Finish::None
            };
            let dz = gemm_to_vec(
                (rows, fan_in, fan_out),
                &acts[i],
                (fan_in, 1),
                dw,
                (fan_out, 1),
                Start::Bias(db),
                finish,
            );
            if i + 1 == layers {
                jv.iter_mut().zip(&dz).for_each(|(j, d)| *j += *d);
            } else if last_hidden {
                let (w_out, _) = self.layer(&self.params, layers - 1);
                gemm(
                    (rows, fan_out, outputs),
                    &dz,
                    (fan_out, 1),
                    w_out,
                    (outputs, 1),
                    &mut jv,
                    Start::Accumulate,
                    Finish::None,
                );
            } else {
                dot_rows(&mut jv, &dz, &sens[i], fan_out);
            }
        }
        jv
    }

    /// Jᵀ·upstream for one block, laid out like `params`: every layer's gradient
    /// xᵀ·g and 1ᵀ·g, with g = ∂(Σ output ⊙ upstream)/∂z from the same three cases as
    /// [`Self::jvp_block`].
    fn jtu_block(
        &self,
        acts: &[Vec<F>],
        sens: &[Vec<Vec<F>>],
        upstream: &[F],
        transposed: &[Vec<F>],
    ) -> Vec<F> {
        let (layers, outputs) = (self.layers(), self.output_dim());
        let rows = acts[0].len() / self.input_dim();
        let mut grad = vec![F::ZERO; self.num_params()];
        for i in 0..layers {
            let fan_out = self.dims[i + 1];
            let g = if i + 1 == layers {
                upstream.to_vec()
            } else if i + 2 == layers {
                gemm_to_vec(
                    (rows, outputs, fan_out),
                    upstream,
                    (outputs, 1),
                    &transposed[i],
                    (fan_out, 1),
                    Start::Zero,
                    Finish::TanhDerivative(&acts[i + 1]),
                )
            } else {
                let mut g = vec![F::ZERO; rows * fan_out];
                combine_rows(&mut g, &sens[i], upstream, fan_out);
                g
            };
            self.layer_gradient(i, &acts[i], &g, &mut grad);
        }
        grad
    }

    /// Reverse-mode: the parameter gradient of Σ output ⊙ `upstream` (`[rows, out]`),
    /// laid out like `params`.
    pub fn vjp(&self, trace: &HostTrace<F>, upstream: &[F]) -> Vec<F> {
        assert_eq!(
            upstream.len(),
            trace.rows * self.output_dim(),
            "upstream of the wrong shape"
        );
        // xᵀ·dz and 1ᵀ·dz of every layer, dz·Wᵀ of every layer past the first.
        let per_row = 2 * self.products(0..self.layers()) - self.products(0..1)
            + self.dims[1..].iter().map(|&w| w as u64).sum::<u64>();
        crate::flops::add(2 * trace.rows as u64 * per_row);
        let transposed = self.transposed_weights();
        let per_block: Vec<Vec<F>> = trace
            .blocks
            .par_iter()
            .zip(upstream.par_chunks(BLOCK_ROWS * self.output_dim()))
            .map(|(acts, upstream)| self.vjp_block(acts, upstream, &transposed))
            .collect();
        sum_in_order(self.num_params(), &per_block)
    }

    /// Wᵀ (`[out, in]` row-major) of every layer past the first, `[i - 1]` for layer i, once
    /// per call: each block's dz·Wᵀ then reads a row-major operand, which the GEMM packs
    /// with vector copies instead of gathering Wᵀ's columns element by element per block.
    fn transposed_weights(&self) -> Vec<Vec<F>> {
        (1..self.layers())
            .map(|i| {
                let (w, _) = self.layer(&self.params, i);
                let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
                let mut wt = vec![F::ZERO; fan_in * fan_out];
                for (r, row) in w.chunks_exact(fan_out).enumerate() {
                    for (o, value) in row.iter().enumerate() {
                        wt[o * fan_in + r] = *value;
                    }
                }
                wt
            })
            .collect()
    }

    /// Layer i's gradient from its input x and ∂/∂z = `dz`: gW = xᵀ·dz, gb = 1ᵀ·dz,
    /// written into its place in `grad`.
    fn layer_gradient(&self, i: usize, x: &[F], dz: &[F], grad: &mut [F]) {
        let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
        let rows = x.len() / fan_in;
        let offset = num_params(&self.dims[..=i]);
        let (gw, gb) =
            grad[offset..offset + fan_in * fan_out + fan_out].split_at_mut(fan_in * fan_out);
        // x read transposed through its strides.
        gemm(
            (fan_in, rows, fan_out),
            x,
            (1, fan_in),
            dz,
            (fan_out, 1),
            gw,
            Start::Zero,
            Finish::None,
        );
        // gb = Σ_rows dz as the one-row product 1ᵀ·dz (a single 1.0 read with zero
        // strides): the GEMM's few-rows path keeps gb in registers and adds the rows in
        // order, as a plain loop would.
        gb.fill(F::ZERO);
        gemm(
            (1, rows, fan_out),
            &[F::ONE],
            (0, 0),
            dz,
            (fan_out, 1),
            gb,
            Start::Accumulate,
            Finish::None,
        );
    }

    /// `transposed[i - 1]` is layer i's Wᵀ (`[out, in]` row-major).
    fn vjp_block(&self, acts: &[Vec<F>], upstream: &[F], transposed: &[Vec<F>]) -> Vec<F> {
        let rows = acts[0].len() / self.input_dim();
        let mut grad = vec![F::ZERO; self.num_params()];
        let mut dz = upstream.to_vec();
        for i in (0..self.layers()).rev() {
            let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
            self.layer_gradient(i, &acts[i], &dz, &mut grad);
            if i > 0 {
                // dx = dz·Wᵀ, then through the previous layer's tanh.
                dz = gemm_to_vec(
                    (rows, fan_out, fan_in),
                    &dz,
                    (fan_out, 1),
                    &transposed[i - 1],
                    (fan_in, 1),
                    Start::Zero,
                    Finish::TanhDerivative(&acts[i]),
                );
            }
        }
        grad
    }
}

/// What [`HostMlp::output_sensitivities`] caches: per block, per hidden layer before the
/// last, per output k, ∂output_k/∂z as `[rows, units]` row-major; and the weights'
/// transposes they were built with, which every product's reverse half reads again.
pub struct OutputSensitivities<F: KernelFloat = f64> {
    blocks: Vec<Vec<Vec<Vec<F>>>>,
    transposed: Vec<Vec<F>>,
}

/// The element-wise sum of per-block vectors, in block order (the same bits whatever the
/// number of threads that made them).
fn sum_in_order<F: KernelFloat>(len: usize, per_block: &[Vec<F>]) -> Vec<F> {
    let mut sum = vec![F::ZERO; len];
    for block in per_block {
        sum.iter_mut().zip(block).for_each(|(s, b)| *s += *b);
    }
    sum
}

/// jv[r, k] += Σ_j dz[r, j] · sens[k][r, j] for every row r and output k: a layer's
/// direct term carried to the outputs (`width` units per row). These loops stream the
/// cached sensitivities; `multiversion` compiles them for AVX-512 and AVX2 as well.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
fn dot_rows<F: KernelFloat>(jv: &mut [F], dz: &[F], sens: &[Vec<F>], width: usize) {
    let outputs = sens.len();
    for (r, (d, jv)) in dz
        .chunks_exact(width)
        .zip(jv.chunks_exact_mut(outputs))
        .enumerate()
    {
        for (j, s) in jv.iter_mut().zip(sens) {
            *j += dot(d, &s[r * width..(r + 1) * width]);
        }
    }
}

/// g[r, j] = Σ_k sens[k][r, j] · u[r, k]: the gradient at a layer's pre-activations from
/// the outputs' upstream `u`.
#[multiversion::multiversion(targets("x86_64+avx512f+avx512vl+avx2+fma", "x86_64+avx2+fma"))]
fn combine_rows<F: KernelFloat>(g: &mut [F], sens: &[Vec<F>], u: &[F], width: usize) {
    let outputs = sens.len();
    for (r, (g, u)) in g
        .chunks_exact_mut(width)
        .zip(u.chunks_exact(outputs))
        .enumerate()
    {
        for (s, u) in sens.iter().zip(u) {
            let s = &s[r * width..(r + 1) * width];
            g.iter_mut().zip(s).for_each(|(g, s)| *g += *s * *u);
        }
    }
}

/// Σ a_i b_i with 32 running sums, so that the loop vectorises into four independent
/// chains.
#[inline(always)]
fn dot<F: KernelFloat>(a: &[F], b: &[F]) -> F {
    const LANES: usize = 32;
    let mut sums = [F::ZERO; LANES];
    let (a_chunks, b_chunks) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let tail: F = a_chunks
        .remainder()
        .iter()
        .zip(b_chunks.remainder())
        .fold(F::ZERO, |sum, (x, y)| sum + *x * *y);
    for (x, y) in a_chunks.zip(b_chunks) {
        for l in 0..LANES {
            sums[l] += x[l] * y[l];
        }
    }
    sums.iter().fold(F::ZERO, |a, &b| a + b) + tail
}
