//! The kernels engine: the hand-tuned CPU path of `crate::kernels` behind the seam.
//! Batch columns and outputs are `NdArray<f64>` tensors (host memory, no copy to speak
//! of); the networks' passes run on host buffers over rayon's threads.

use std::sync::Arc;

use burn::backend::NdArray;
use burn::tensor::Tensor;

use super::Engine;
use crate::flat::{from_vec_f64, to_f64};
use crate::kernels::{HostMlp, HostTrace, OutputSensitivities};

/// The default engine: float64, as the reference computes.
#[derive(Debug, Clone, Copy, Default)]
pub struct Kernels;

/// Network inputs in host memory, shared between the passes that read them.
#[derive(Debug, Clone)]
pub struct HostRows {
    values: Arc<Vec<f64>>,
    width: usize,
}

impl Engine for Kernels {
    type B = NdArray<f64>;
    type Net = HostMlp;
    type Rows = HostRows;
    type Trace = HostTrace;
    type Curvature = OutputSensitivities;

    fn describe(&self) -> String {
        "kernels f64".into()
    }

    fn device(&self) -> super::Device<Self> {
        Default::default()
    }

    fn rows(&self, values: &[f64], width: usize) -> HostRows {
        assert!(
            width > 0 && values.len().is_multiple_of(width),
            "rows of the wrong width"
        );
        HostRows {
            values: Arc::new(values.to_vec()),
            width,
        }
    }

    fn select(&self, rows: &HostRows, indices: &[usize]) -> HostRows {
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

    fn num_rows(&self, rows: &HostRows) -> usize {
        rows.values.len() / rows.width
    }

    fn net(&self, dims: &[usize], params: &[f64]) -> HostMlp {
        HostMlp::new(dims.to_vec(), params.to_vec())
    }

    fn params(&self, net: &HostMlp) -> Vec<f64> {
        net.params.clone()
    }

    fn trace(&self, net: &HostMlp, x: &HostRows) -> HostTrace {
        assert_eq!(x.width, net.input_dim(), "rows of the wrong width");
        net.trace(&x.values)
    }

    fn output(&self, trace: &HostTrace) -> Tensor<Self::B, 2> {
        from_vec_f64(
            trace.output(),
            [trace.rows(), trace.output_dim()],
            &self.device(),
        )
    }

    fn vjp(&self, net: &HostMlp, trace: &HostTrace, upstream: Tensor<Self::B, 2>) -> Vec<f64> {
        net.vjp(trace, &to_f64(upstream))
    }

    fn curvature(&self, net: &HostMlp, trace: &HostTrace) -> OutputSensitivities {
        net.output_sensitivities(trace)
    }

    fn gauss_newton(
        &self,
        net: &HostMlp,
        trace: &HostTrace,
        curvature: &OutputSensitivities,
        tangent: &[f64],
        output_weights: &[f64],
    ) -> Vec<f64> {
        net.gauss_newton_product(trace, curvature, tangent, output_weights)
    }
}
