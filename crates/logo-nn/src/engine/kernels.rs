//! The kernels engine: the hand-tuned CPU path of `crate::kernels` behind the seam, in
//! float64 (the default, the reference's precision) or float32. Batch columns and
//! outputs are `NdArray<F>` tensors (host memory, no copy to speak of); the networks'
//! passes run on host buffers over rayon's threads. Flat vectors cross the seam as f64.

use std::marker::PhantomData;
use std::sync::Arc;

use burn::backend::NdArray;
use burn::backend::ndarray::{FloatNdArrayElement, NdArrayTensor, SharedArray};
use burn::tensor::{Tensor, TensorCreationOptions, TensorData};

use super::Engine;
use crate::kernels::{HostMlp, HostTrace, KernelFloat, OutputSensitivities};

/// The default engine, float64; `Kernels::<f32>::default()` computes in float32.
#[derive(Debug, Clone, Copy)]
pub struct Kernels<F = f64> {
    _float: PhantomData<F>,
}

impl<F> Default for Kernels<F> {
    fn default() -> Self {
        Self {
            _float: PhantomData,
        }
    }
}

/// The float64 kernels engine as a value, so that `Trainer::new(Kernels, …)` reads as
/// the unit struct it was before the engine had a float type.
#[allow(non_upper_case_globals)]
pub const Kernels: Kernels<f64> = Kernels {
    _float: PhantomData,
};

/// Network inputs in host memory, shared between the passes that read them.
#[derive(Debug, Clone)]
pub struct HostRows<F> {
    values: Arc<Vec<F>>,
    width: usize,
}

/// " +avx512" where the `avx512` build's GEMM kernels run (built with the feature, on a
/// CPU that has AVX-512F): they sum in another order than the default build's, so a
/// run's engine history says which it trained on. Empty otherwise.
fn gemm_build() -> &'static str {
    #[cfg(all(feature = "avx512", target_arch = "x86_64"))]
    if std::arch::is_x86_feature_detected!("avx512f") {
        return " +avx512";
    }
    ""
}

fn to_host<F: KernelFloat>(values: &[f64]) -> Vec<F> {
    values.iter().map(|&v| F::from_f64(v)).collect()
}

fn to_f64<F: KernelFloat>(values: &[F]) -> Vec<f64> {
    values.iter().map(|v| v.to_f64()).collect()
}

impl<F: KernelFloat + FloatNdArrayElement> Engine for Kernels<F>
where
    NdArrayTensor: From<SharedArray<F>>,
{
    type B = NdArray<F>;
    type Net = HostMlp<F>;
    type Rows = HostRows<F>;
    type Trace = HostTrace<F>;
    type Curvature = OutputSensitivities<F>;

    fn describe(&self) -> String {
        format!("kernels {}{}", F::NAME, gemm_build())
    }

    fn device(&self) -> super::Device<Self> {
        Default::default()
    }

    fn rows(&self, values: &[f64], width: usize) -> HostRows<F> {
        assert!(
            width > 0 && values.len().is_multiple_of(width),
            "rows of the wrong width"
        );
        HostRows {
            values: Arc::new(to_host(values)),
            width,
        }
    }

    fn select(&self, rows: &HostRows<F>, indices: &[usize]) -> HostRows<F> {
        let w = rows.width;
        let values = indices
            .iter()
            .flat_map(|&r| rows.values[r * w..(r + 1) * w].iter().copied())
            .collect();
        HostRows {
            values: Arc::new(values),
            width: w,
        }
    }

    fn num_rows(&self, rows: &HostRows<F>) -> usize {
        rows.values.len() / rows.width
    }

    fn net(&self, dims: &[usize], params: &[f64]) -> HostMlp<F> {
        HostMlp::new(dims.to_vec(), to_host(params))
    }

    fn params(&self, net: &HostMlp<F>) -> Vec<f64> {
        to_f64(&net.params)
    }

    fn trace(&self, net: &HostMlp<F>, x: &HostRows<F>) -> HostTrace<F> {
        assert_eq!(x.width, net.input_dim(), "rows of the wrong width");
        net.trace(&x.values)
    }

    fn output(&self, trace: &HostTrace<F>) -> Tensor<Self::B, 2> {
        let options = TensorCreationOptions::new(self.device())
            .with_dtype(<F as burn::tensor::Element>::dtype());
        Tensor::from_data(
            TensorData::new(trace.output(), [trace.rows(), trace.output_dim()]),
            options,
        )
    }

    fn vjp(
        &self,
        net: &HostMlp<F>,
        trace: &HostTrace<F>,
        upstream: Tensor<Self::B, 2>,
    ) -> Vec<f64> {
        let upstream = upstream
            .into_data()
            .into_vec::<F>()
            .expect("an NdArray<F> tensor holds F");
        to_f64(&net.vjp(trace, &upstream))
    }

    fn curvature(&self, net: &HostMlp<F>, trace: &HostTrace<F>) -> OutputSensitivities<F> {
        net.output_sensitivities(trace)
    }

    fn gauss_newton(
        &self,
        net: &HostMlp<F>,
        trace: &HostTrace<F>,
        curvature: &OutputSensitivities<F>,
        tangent: &[f64],
        output_weights: &[f64],
    ) -> Vec<f64> {
        to_f64(&net.gauss_newton_product(
            trace,
            curvature,
            &to_host(tangent),
            &to_host(output_weights),
        ))
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    /// The engine's name carries the GEMM build where it is the `avx512` one, so that a
    /// checkpoint's history tells the two builds' runs apart.
    #[test]
    fn the_name_says_which_gemm_kernels_ran() {
        let avx512 = cfg!(all(feature = "avx512", target_arch = "x86_64"))
            && std::arch::is_x86_feature_detected!("avx512f");
        let tag = if avx512 { " +avx512" } else { "" };
        assert_eq!(
            Kernels::<f64>::default().describe(),
            format!("kernels f64{tag}")
        );
        assert_eq!(
            Kernels::<f32>::default().describe(),
            format!("kernels f32{tag}")
        );
    }
}
