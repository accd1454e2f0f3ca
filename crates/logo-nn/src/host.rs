//! The MLP of [`crate::Mlp`] on plain host `f64` buffers, for the CPU hot loops: the
//! critics' L-BFGS fits, the surrogate gradient and the Fisher-vector products, which
//! evaluate the same network on the same batch 10–60 times per step.
//!
//! Why a second copy of the forward/reverse passes: burn-ndarray allocates and copies
//! around every op and its dgemm calls are single-threaded; here the parameters and the
//! cached activations stay on the host between calls, bias and tanh are fused in place,
//! and the batch is cut into fixed blocks that run on rayon's threads. The burn version in
//! `mlp.rs` stays the definition (and the path for every other backend); the tests in
//! `tests/host.rs` hold this one to it within 1e-12.
//!
//! Determinism: the blocks are a fixed partition of the rows (not of the threads), and
//! per-block parameter gradients are summed in block order, so results are bit-identical
//! whatever the number of threads.

use burn::tensor::backend::Backend;
use rayon::prelude::*;

use crate::flat::params_to_vec;
use crate::gemm::{Finish, Start, gemm, gemm_to_vec};
use crate::mlp::Mlp;

/// Whether `B` is the default CPU backend (`NdArray<f64>`), whose hot loops run here.
pub fn is_host_backend<B: Backend>() -> bool {
    std::any::TypeId::of::<B>() == std::any::TypeId::of::<crate::Cpu>()
}

/// Rows per block: small enough that a block's activations (256 × 128 × 8 B = 256 KiB
/// each) stay in a core's 1 MiB L2 while the next layer reads them, and that a 5k-row
/// batch splits evenly over two threads; large enough for the GEMM to run at full speed.
const BLOCK_ROWS: usize = 256;

/// An MLP's layer sizes and flat parameters, laid out as [`crate::flat::params_to_vec`]
/// lays out an [`Mlp`]: for each layer, weight `[in, out]` row-major, then bias `[out]`.
#[derive(Debug, Clone, PartialEq)]
pub struct HostMlp {
    /// `[input, hidden..., output]`.
    pub dims: Vec<usize>,
    pub params: Vec<f64>,
}

/// The activations of every block of a batch: `[x, h1, ..., output]` per block.
pub struct HostTrace {
    rows: usize,
    blocks: Vec<Vec<Vec<f64>>>,
}

impl HostTrace {
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The network's output for every row, `[rows, out]` row-major.
    pub fn output(&self) -> Vec<f64> {
        self.blocks
            .iter()
            .flat_map(|acts| acts.last().expect("a trace has an output").iter().copied())
            .collect()
    }
}

fn num_params(dims: &[usize]) -> usize {
    dims.windows(2).map(|w| w[0] * w[1] + w[1]).sum()
}

impl HostMlp {
    pub fn new(dims: Vec<usize>, params: Vec<f64>) -> Self {
        assert!(dims.len() >= 2, "an MLP has at least one layer");
        assert_eq!(
            params.len(),
            num_params(&dims),
            "parameters of the wrong length"
        );
        Self { dims, params }
    }

    /// A host copy of `mlp`'s parameters.
    pub fn from_mlp<B: Backend>(mlp: &Mlp<B>) -> Self {
        let mut dims = vec![mlp.layers[0].weight.dims()[0]];
        dims.extend(mlp.layers.iter().map(|l| l.weight.dims()[1]));
        Self::new(dims, params_to_vec(mlp))
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
    fn layer<'a>(&self, flat: &'a [f64], i: usize) -> (&'a [f64], &'a [f64]) {
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

    /// The activations of `x` (`[rows, input]` row-major).
    pub fn trace(&self, x: &[f64]) -> HostTrace {
        let input = self.input_dim();
        assert_eq!(x.len() % input, 0, "input rows of the wrong width");
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
            blocks,
        }
    }

    fn trace_block(&self, x: &[f64]) -> Vec<Vec<f64>> {
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
    pub fn forward(&self, x: &[f64]) -> Vec<f64> {
        self.trace(x).output()
    }

    /// Forward-mode derivative of the output along the parameter direction `tangent`
    /// (laid out like `params`): dz = x·dW + db + dx·W, dh = (1 − h²) ⊙ dz.
    pub fn jvp(&self, trace: &HostTrace, tangent: &[f64]) -> Vec<f64> {
        assert_eq!(
            tangent.len(),
            self.num_params(),
            "tangent of the wrong length"
        );
        let blocks: Vec<Vec<f64>> = trace
            .blocks
            .par_iter()
            .map(|acts| {
                let rows = acts[0].len() / self.input_dim();
                let mut d_input: Option<Vec<f64>> = None;
                for i in 0..self.layers() {
                    let (w, _) = self.layer(&self.params, i);
                    let (dw, db) = self.layer(tangent, i);
                    let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
                    // Through this layer's tanh (not after the output layer).
                    let finish = if i + 1 < self.layers() {
                        Finish::TanhDerivative(&acts[i + 1])
                    } else {
                        Finish::None
                    };
                    let mut dz = gemm_to_vec(
                        (rows, fan_in, fan_out),
                        &acts[i],
                        (fan_in, 1),
                        dw,
                        (fan_out, 1),
                        Start::Bias(db),
                        if d_input.is_some() {
                            Finish::None
                        } else {
                            finish
                        },
                    );
                    if let Some(dx) = &d_input {
                        gemm(
                            (rows, fan_in, fan_out),
                            dx,
                            (fan_in, 1),
                            w,
                            (fan_out, 1),
                            &mut dz,
                            Start::Accumulate,
                            finish,
                        );
                    }
                    d_input = Some(dz);
                }
                d_input.expect("an MLP has at least one layer")
            })
            .collect();
        blocks.concat()
    }

    /// Reverse-mode: the parameter gradient of Σ output ⊙ `upstream` (`[rows, out]`),
    /// laid out like `params`.
    pub fn vjp(&self, trace: &HostTrace, upstream: &[f64]) -> Vec<f64> {
        assert_eq!(
            upstream.len(),
            trace.rows * self.output_dim(),
            "upstream of the wrong shape"
        );
        // Wᵀ of every layer past the first, once per call: each block's dz·Wᵀ then reads
        // a row-major operand, which the GEMM packs with vector copies instead of
        // gathering Wᵀ's columns element by element for every block.
        let transposed: Vec<Vec<f64>> = (1..self.layers())
            .map(|i| {
                let (w, _) = self.layer(&self.params, i);
                let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
                let mut wt = vec![0.0; fan_in * fan_out];
                for (r, row) in w.chunks_exact(fan_out).enumerate() {
                    for (o, value) in row.iter().enumerate() {
                        wt[o * fan_in + r] = *value;
                    }
                }
                wt
            })
            .collect();
        let per_block: Vec<Vec<f64>> = trace
            .blocks
            .par_iter()
            .zip(upstream.par_chunks(BLOCK_ROWS * self.output_dim()))
            .map(|(acts, upstream)| self.vjp_block(acts, upstream, &transposed))
            .collect();
        let mut grad = vec![0.0; self.num_params()];
        for block in &per_block {
            grad.iter_mut().zip(block).for_each(|(g, b)| *g += b);
        }
        grad
    }

    /// `transposed[i - 1]` is layer i's Wᵀ (`[out, in]` row-major).
    fn vjp_block(&self, acts: &[Vec<f64>], upstream: &[f64], transposed: &[Vec<f64>]) -> Vec<f64> {
        let rows = acts[0].len() / self.input_dim();
        let mut grad = vec![0.0; self.num_params()];
        let mut dz = upstream.to_vec();
        for i in (0..self.layers()).rev() {
            let (fan_in, fan_out) = (self.dims[i], self.dims[i + 1]);
            let offset = num_params(&self.dims[..=i]);
            let (gw, gb) =
                grad[offset..offset + fan_in * fan_out + fan_out].split_at_mut(fan_in * fan_out);
            // gW = xᵀ·dz: x read transposed through its strides.
            gemm(
                (fan_in, rows, fan_out),
                &acts[i],
                (1, fan_in),
                &dz,
                (fan_out, 1),
                gw,
                Start::Zero,
                Finish::None,
            );
            // gb += Σ_rows dz, as the one-row product 1ᵀ·dz (a single 1.0 read with zero
            // strides): the GEMM's few-rows path keeps gb in registers, and adds the rows
            // in order, as a plain loop would.
            gemm(
                (1, rows, fan_out),
                &[1.0],
                (0, 0),
                &dz,
                (fan_out, 1),
                gb,
                Start::Accumulate,
                Finish::None,
            );
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
