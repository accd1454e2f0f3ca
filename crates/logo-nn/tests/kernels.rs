//! The kernels' host-buffer MLP (`logo_nn::kernels`) against the burn definition in
//! `mlp.rs`.

use burn::backend::ndarray::NdArrayDevice;
use logo_nn::flat::{flatten_layers, from_f64, params_to_vec, split_layers, to_f64, vec_to_params};
use logo_nn::kernels::HostMlp;
use logo_nn::{Cpu, Mlp, MlpConfig};
use logo_testkit::max_relative_error;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// 2500 rows: nine full blocks of 256 and a partial one.
const ROWS: usize = 2500;

fn random(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-scale..scale)).collect()
}

fn setup() -> (Mlp<Cpu>, HostMlp, Vec<f64>, ChaCha8Rng) {
    let device = NdArrayDevice::Cpu;
    let config = MlpConfig {
        input: 5,
        hidden: vec![16, 12],
        output: 3,
        output_scale: None,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let theta = random(&mut rng, config.num_params(), 0.6);
    let mlp = vec_to_params(config.init::<Cpu>(&device), &theta);
    let host = HostMlp::new(mlp.dims(), params_to_vec(&mlp));
    assert_eq!(host.params, theta);
    assert_eq!(host.dims, vec![5, 16, 12, 3]);
    let x = random(&mut rng, ROWS * 5, 2.0);
    (mlp, host, x, rng)
}

#[test]
fn forward_and_vjp_match_the_burn_mlp() {
    let (mlp, host, x, mut rng) = setup();
    let device = NdArrayDevice::Cpu;
    let x_tensor = from_f64::<Cpu, 2>(&x, [ROWS, 5], &device);
    let (inputs, out) = mlp.forward_trace(x_tensor);
    let trace = host.trace(&x);
    assert_eq!(trace.rows(), ROWS);
    let forward_error = max_relative_error(&trace.output(), &to_f64(out));
    assert!(forward_error < 1e-13, "forward: {forward_error:e}");

    let upstream = random(&mut rng, ROWS * 3, 1.0);
    let burn_vjp = flatten_layers(mlp.vjp(&inputs, from_f64(&upstream, [ROWS, 3], &device)));
    let vjp_error = max_relative_error(&host.vjp(&trace, &upstream), &burn_vjp);
    assert!(vjp_error < 1e-12, "vjp: {vjp_error:e}");
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let (_, host, x, mut rng) = setup();
    let upstream = random(&mut rng, ROWS * 3, 1.0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let trace = host.trace(&x);
            let sens = host.output_sensitivities(&trace);
            let tangent = &upstream[..host.num_params()];
            (
                trace.output(),
                host.vjp(&trace, &upstream),
                host.gauss_newton_product(&trace, &sens, tangent, &[0.5, 2.0, 1.0]),
            )
        })
    };
    let one = run(1);
    assert_eq!(one, run(2), "1 vs 2 threads");
    assert_eq!(one, run(3), "1 vs 3 threads");
}

#[test]
#[should_panic(expected = "upstream of the wrong shape")]
fn a_wrong_upstream_shape_is_caught() {
    let (_, host, x, _) = setup();
    let trace = host.trace(&x);
    host.vjp(&trace, &[0.0; 3]);
}

#[test]
fn small_batches_take_the_direct_product_and_agree_with_burn() {
    let (mlp, host, x, _) = setup();
    let device = NdArrayDevice::Cpu;
    for rows in [1, 2, 4, 5] {
        let x = &x[..rows * 5];
        let want = to_f64(mlp.forward(from_f64::<Cpu, 2>(x, [rows, 5], &device)));
        let err = max_relative_error(&host.forward(x), &want);
        assert!(err < 1e-13, "{rows} rows: {err:e}");
    }
}

/// Jᵀ diag(w) J v against burn's forward-mode pass followed by its reverse pass, for nets
/// with one, two and three hidden layers (no cached sensitivities, the last hidden layer's
/// only, and a chain of them) and one or several outputs.
#[test]
fn the_gauss_newton_product_equals_burns_jvp_then_vjp() {
    let device = NdArrayDevice::Cpu;
    for (hidden, output) in [
        (vec![16], 3),
        (vec![16, 12], 3),
        (vec![16, 12], 1),
        (vec![9, 16, 12], 4),
    ] {
        let config = MlpConfig {
            input: 5,
            hidden: hidden.clone(),
            output,
            output_scale: None,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mlp = vec_to_params(
            config.init::<Cpu>(&device),
            &random(&mut rng, config.num_params(), 0.6),
        );
        let host = HostMlp::new(mlp.dims(), params_to_vec(&mlp));
        let x = random(&mut rng, ROWS * 5, 2.0);
        let tangent = random(&mut rng, host.num_params(), 1.0);
        let weights = random(&mut rng, output, 1.0);

        let (inputs, _) = mlp.forward_trace(from_f64::<Cpu, 2>(&x, [ROWS, 5], &device));
        let jv = to_f64(mlp.jvp(&inputs, &split_layers(&mlp, &tangent, &device)));
        let weighted: Vec<f64> = jv
            .chunks_exact(output)
            .flat_map(|row| row.iter().zip(&weights).map(|(j, w)| j * w))
            .collect();
        let want = flatten_layers(mlp.vjp(&inputs, from_f64(&weighted, [ROWS, output], &device)));

        let trace = host.trace(&x);
        let sens = host.output_sensitivities(&trace);
        let got = host.gauss_newton_product(&trace, &sens, &tangent, &weights);
        let error = max_relative_error(&got, &want);
        assert!(
            error < 1e-12,
            "hidden {hidden:?}, {output} outputs: {error:e}"
        );
    }
}
