//! burn 0.21 fixes a CPU device's default dtypes the first time a tensor is made on it
//! without a dtype of its own, from that tensor's backend; NdArray<f32> and NdArray<f64>
//! share the device. The networks are float64 modules made with burn's initialisers
//! (which use the default), so float32 engine work must never be what fixes it. One test
//! in its own binary: the order of backends is then the test's, not the test runner's
//! (in a shared binary this raced, and `engines.rs` failed now and then).

use burn::tensor::{DType, Tensor};
use logo_nn::flat::{from_f64, params_to_vec, to_f64, vec_to_params};
use logo_nn::{
    BurnEngine, Cpu, Cpu32, DiscriminatorConfig, Engine, Kernels, MlpConfig, ObservationStats,
    PolicyConfig, ValueNetConfig,
};

/// Every method of the seam once, on a float32 engine.
fn float32_work<E: Engine>(engine: &E) {
    let dims = [3, 4, 2];
    let net = engine.net(&dims, &[0.05; 26]);
    let rows = engine.rows(&[0.5, -0.5, 1.0, 0.25, 0.0, -1.0], 3);
    let trace = engine.trace(&net, &rows);
    let curvature = engine.curvature(&net, &trace);
    let _ = engine.forward(&net, &engine.select(&rows, &[1, 0]));
    let _ = engine.vjp(&net, &trace, engine.upload(&[1.0; 4], [2, 2]));
    let _ = engine.gauss_newton(&net, &trace, &curvature, &[1.0; 26], &[1.0, 1.0]);
}

#[test]
fn float64_modules_hold_float64_after_float32_engines_ran() {
    float32_work(&BurnEngine::<Cpu32>::new(Default::default(), "ndarray f32"));
    float32_work(&Kernels::<f32>::default());

    let device = Default::default();
    let config = MlpConfig {
        input: 3,
        hidden: vec![4],
        output: 2,
        output_scale: Some(0.1),
    };
    let mlp = config.init::<Cpu>(&device);
    for layer in &mlp.layers {
        assert_eq!(layer.weight.val().dtype(), DType::F64);
        assert_eq!(layer.bias.as_ref().unwrap().val().dtype(), DType::F64);
    }
    let theta: Vec<f64> = (0..config.num_params()).map(|k| k as f64 * 0.01).collect();
    let mlp = vec_to_params(mlp, &theta);
    assert_eq!(params_to_vec(&mlp), theta, "parameters lost precision");
    let out = mlp.forward(from_f64::<Cpu, 2>(&[0.5, -0.25, 1.0], [1, 3], &device));
    assert_eq!(out.dtype(), DType::F64);
    assert_eq!(to_f64(out).len(), 2);

    let policy = PolicyConfig::new(3, 2).init::<Cpu>(&device);
    assert_eq!(policy.log_std.val().dtype(), DType::F64);
    let critic = ValueNetConfig::new(3).init::<Cpu>(&device);
    assert_eq!(critic.net.layers[0].weight.val().dtype(), DType::F64);
    let discriminator = DiscriminatorConfig::new(3, 2).init::<Cpu>(&device);
    assert_eq!(discriminator.net.layers[0].weight.val().dtype(), DType::F64);
    let norm = ObservationStats::new(3).module::<Cpu>(&device);
    assert_eq!(norm.mean.val().dtype(), DType::F64);
    assert_eq!(Tensor::<Cpu, 1>::zeros([2], &device).dtype(), DType::F64);
}
