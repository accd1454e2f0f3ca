//! The two engines against each other, method by method, and the closed forms the losses
//! keep for speed against burn's autodiff.

use burn::backend::Autodiff;
use burn::tensor::Tensor;
use logo_nn::flat::{from_f64, to_f64, vec_to_params};
use logo_nn::loss::{fisher_output_weights, gaussian_kl, value_and_grad};
use logo_nn::{BurnEngine, Cpu, Cpu32, Engine, Kernels, MlpConfig};
use logo_testkit::max_relative_error;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ROWS: usize = 700;

fn random(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-scale..scale)).collect()
}

/// Every result of the seam on one engine, for one random net and batch.
struct Results {
    params: Vec<f64>,
    output: Vec<f64>,
    selected: Vec<f64>,
    vjp: Vec<f64>,
    gauss_newton: Vec<f64>,
}

fn run<E: Engine>(engine: &E, dims: &[usize], seed: u64) -> Results {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let config = MlpConfig {
        input: dims[0],
        hidden: dims[1..dims.len() - 1].to_vec(),
        output: *dims.last().unwrap(),
        output_scale: None,
    };
    let theta = random(&mut rng, config.num_params(), 0.6);
    let x = random(&mut rng, ROWS * dims[0], 2.0);
    let out_dim = config.output;
    let upstream = random(&mut rng, ROWS * out_dim, 1.0);
    let tangent = random(&mut rng, theta.len(), 1.0);
    let weights: Vec<f64> = random(&mut rng, out_dim, 1.0)
        .iter()
        .map(|w| w.abs())
        .collect();

    let net = engine.net(dims, &theta);
    let rows = engine.rows(&x, dims[0]);
    assert_eq!(engine.num_rows(&rows), ROWS);
    let trace = engine.trace(&net, &rows);
    let curvature = engine.curvature(&net, &trace);
    let picked = [5, 0, ROWS - 1, 5];
    Results {
        params: engine.params(&net),
        output: to_f64(engine.output(&trace)),
        selected: to_f64(engine.forward(&net, &engine.select(&rows, &picked))),
        vjp: engine.vjp(&net, &trace, engine.upload(&upstream, [ROWS, out_dim])),
        gauss_newton: engine.gauss_newton(&net, &trace, &curvature, &tangent, &weights),
    }
}

#[test]
fn the_kernels_and_burn_engines_agree_on_every_method() {
    let burn = BurnEngine::<Cpu>::new(Default::default(), "ndarray f64");
    for dims in [vec![5, 16, 3], vec![5, 16, 12, 3], vec![4, 9, 16, 12, 1]] {
        let (k, b) = (run(&Kernels, &dims, 3), run(&burn, &dims, 3));
        assert_eq!(k.params, b.params, "{dims:?}: parameters round-trip");
        for (what, a, b, tol) in [
            ("output", &k.output, &b.output, 1e-13),
            ("select", &k.selected, &b.selected, 1e-13),
            ("vjp", &k.vjp, &b.vjp, 1e-12),
            ("gauss_newton", &k.gauss_newton, &b.gauss_newton, 1e-12),
        ] {
            let err = max_relative_error(a, b);
            assert!(err < tol, "{dims:?} {what}: {err:e}");
        }
        // The selected rows are the forward pass of those rows, in the order asked (to
        // rounding: a few rows take the kernels' direct product, which sums in another
        // order than the blocked one).
        let width = *dims.last().unwrap();
        let row = |r: usize| k.output[r * width..(r + 1) * width].to_vec();
        let want: Vec<f64> = [5, 0, ROWS - 1, 5].iter().flat_map(|&r| row(r)).collect();
        let err = max_relative_error(&k.selected, &want);
        assert!(err < 1e-14, "{dims:?} selected rows: {err:e}");
    }
}

/// The burn engine in float32 computes the same things to float32 precision.
#[test]
fn the_burn_engine_runs_in_float32() {
    let burn32 = BurnEngine::<Cpu32>::new(Default::default(), "ndarray f32");
    let dims = [5, 16, 12, 3];
    let (k, b) = (run(&Kernels, &dims, 4), run(&burn32, &dims, 4));
    for (what, a, b, tol) in [
        ("output", &k.output, &b.output, 1e-5),
        ("vjp", &k.vjp, &b.vjp, 1e-4),
        ("gauss_newton", &k.gauss_newton, &b.gauss_newton, 1e-4),
    ] {
        let err = max_relative_error(b, a);
        assert!(err < tol, "{what}: {err:e}");
        assert!(err > 0.0, "{what}: f32 cannot be exactly f64");
    }
}

/// The Fisher's weights on the mean outputs, kept in closed form (1/σ²), are the Hessian
/// of the KL with respect to the new means at new = old, by autodiff.
#[test]
fn fisher_output_weights_are_the_hessian_of_the_kl() {
    let device = Default::default();
    let log_std = [-0.7, 0.0, 0.4];
    let old_mean = [0.3, -1.2, 2.0];
    let old = from_f64::<Cpu, 2>(&old_mean, [1, 3], &device);
    let ls = from_f64::<Cpu, 1>(&log_std, [3], &device);
    // ∂KL/∂μ_new at μ_new = μ_old + ε e_j, central differences of autodiff gradients.
    let grad_at = |mean: &[f64]| -> Vec<f64> {
        let (_, g) = value_and_grad(from_f64::<Cpu, 2>(mean, [1, 3], &device), |m| {
            gaussian_kl(
                Tensor::<Autodiff<Cpu>, 2>::from_inner(old.clone()),
                Tensor::from_inner(ls.clone()),
                m,
                Tensor::from_inner(ls.clone()),
            )
            .sum()
        });
        to_f64(g)
    };
    let weights = fisher_output_weights(&log_std);
    let eps = 1e-5;
    for j in 0..3 {
        let (mut plus, mut minus) = (old_mean.to_vec(), old_mean.to_vec());
        plus[j] += eps;
        minus[j] -= eps;
        let (gp, gm) = (grad_at(&plus), grad_at(&minus));
        for i in 0..3 {
            let hessian = (gp[i] - gm[i]) / (2.0 * eps);
            let want = if i == j { weights[j] } else { 0.0 };
            assert!(
                (hessian - want).abs() < 1e-8,
                "H[{i}][{j}] = {hessian}, closed form {want}"
            );
        }
    }
}

/// A module's parameters reach the engine in the module's order (what checkpoints and
/// the burn definition rely on).
#[test]
fn engine_parameters_follow_the_module_layout() {
    let device = Default::default();
    let config = MlpConfig {
        input: 3,
        hidden: vec![4],
        output: 2,
        output_scale: Some(0.1),
    };
    let mlp = config.init::<Cpu>(&device);
    let theta: Vec<f64> = (0..config.num_params()).map(|k| k as f64 * 0.01).collect();
    let mlp = vec_to_params(mlp, &theta);
    let x = [0.5, -0.25, 1.0];
    let want = to_f64(mlp.forward(from_f64::<Cpu, 2>(&x, [1, 3], &device)));
    for engine_out in [
        to_f64(Kernels.forward(&Kernels.net(&mlp.dims(), &theta), &Kernels.rows(&x, 3))),
        {
            let burn = BurnEngine::<Cpu>::new(device, "ndarray f64");
            to_f64(burn.forward(&burn.net(&mlp.dims(), &theta), &burn.rows(&x, 3)))
        },
    ] {
        assert!(max_relative_error(&engine_out, &want) < 1e-14);
    }
}

/// burn 0.21 takes a device's default float type from the first backend that used the
/// device: NdArray<f64> and NdArray<f32> share the CPU device, so without an explicit
/// dtype a "float32" engine made its tensors in f64 once anything f64 had run. Every
/// tensor the engines make says its dtype.
#[test]
fn float32_engines_hold_float32_after_float64_ran() {
    use burn::tensor::DType;
    let _ = Kernels.upload(&[1.0, 2.0], [2]); // f64 first
    let burn32 = BurnEngine::<Cpu32>::new(Default::default(), "ndarray f32");
    assert_eq!(burn32.upload(&[1.0, 2.0], [2]).dtype(), DType::F32);
    let kernels32 = Kernels::<f32>::default();
    assert_eq!(kernels32.upload(&[1.0], [1]).dtype(), DType::F32);
    let net = kernels32.net(&[2, 3, 1], &[0.1; 13]);
    let out = kernels32.forward(&net, &kernels32.rows(&[0.5, -0.5], 2));
    assert_eq!(out.dtype(), DType::F32);
    let net = burn32.net(&[2, 3, 1], &[0.1; 13]);
    assert_eq!(
        burn32.forward(&net, &burn32.rows(&[0.5, -0.5], 2)).dtype(),
        DType::F32
    );
}

/// The float32 kernels compute what float64 does, to float32 precision.
#[test]
fn the_kernels_run_in_float32() {
    let dims = [5, 16, 12, 3];
    let (k64, k32) = (
        run(&Kernels, &dims, 5),
        run(&Kernels::<f32>::default(), &dims, 5),
    );
    for (what, a, b, tol) in [
        ("output", &k64.output, &k32.output, 1e-5),
        ("vjp", &k64.vjp, &k32.vjp, 1e-4),
        ("gauss_newton", &k64.gauss_newton, &k32.gauss_newton, 1e-4),
    ] {
        let err = max_relative_error(b, a);
        assert!(err < tol && err > 0.0, "{what}: {err:e}");
    }
}
