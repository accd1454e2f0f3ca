//! The GPU-shaped data flow, counted: an engine wrapper records every host ↔ device
//! crossing of the seam while LOGO trains (burn on NdArray<f32>, standing in for a GPU
//! backend). Per iteration the batch crosses a fixed, small number of times (its columns
//! up once, GAE's per-row values and rewards down), however many CG iterations, line-search
//! candidates and L-BFGS evaluations there are; everything else that crosses is a flat
//! parameter or direction vector, or a loss value.

use std::path::Path;
use std::sync::Mutex;

use burn::tensor::Tensor;
use logo_algo::{TrainConfig, Trainer};
use logo_nn::{BurnEngine, Cpu32, Engine};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Direction {
    Up,
    Down,
}

/// An engine that counts what crosses, and delegates everything else.
struct Counting<E> {
    inner: E,
    log: Mutex<Vec<(Direction, usize)>>,
}

impl<E> Counting<E> {
    fn record(&self, direction: Direction, floats: usize) {
        self.log.lock().unwrap().push((direction, floats));
    }

    fn take(&self) -> Vec<(Direction, usize)> {
        std::mem::take(&mut self.log.lock().unwrap())
    }
}

impl<E: Engine> Engine for Counting<E> {
    type B = E::B;
    type Net = E::Net;
    type Rows = E::Rows;
    type Trace = E::Trace;
    type Curvature = E::Curvature;

    fn upload<const D: usize>(&self, values: &[f64], shape: [usize; D]) -> Tensor<E::B, D> {
        self.record(Direction::Up, values.len());
        self.inner.upload(values, shape)
    }
    fn download<const D: usize>(&self, t: Tensor<E::B, D>) -> Vec<f64> {
        let values = self.inner.download(t);
        self.record(Direction::Down, values.len());
        values
    }
    fn describe(&self) -> String {
        format!("counting {}", self.inner.describe())
    }
    fn device(&self) -> logo_nn::engine::Device<Self> {
        self.inner.device()
    }
    fn rows(&self, values: &[f64], width: usize) -> E::Rows {
        self.record(Direction::Up, values.len());
        self.inner.rows(values, width)
    }
    fn select(&self, rows: &E::Rows, indices: &[usize]) -> E::Rows {
        self.inner.select(rows, indices)
    }
    fn num_rows(&self, rows: &E::Rows) -> usize {
        self.inner.num_rows(rows)
    }
    fn net(&self, dims: &[usize], params: &[f64]) -> E::Net {
        self.record(Direction::Up, params.len());
        self.inner.net(dims, params)
    }
    fn params(&self, net: &E::Net) -> Vec<f64> {
        let params = self.inner.params(net);
        self.record(Direction::Down, params.len());
        params
    }
    fn trace(&self, net: &E::Net, x: &E::Rows) -> E::Trace {
        self.inner.trace(net, x)
    }
    fn output(&self, trace: &E::Trace) -> Tensor<E::B, 2> {
        self.inner.output(trace)
    }
    fn forward(&self, net: &E::Net, x: &E::Rows) -> Tensor<E::B, 2> {
        self.inner.forward(net, x)
    }
    fn vjp(&self, net: &E::Net, trace: &E::Trace, upstream: Tensor<E::B, 2>) -> Vec<f64> {
        let grad = self.inner.vjp(net, trace, upstream);
        self.record(Direction::Down, grad.len());
        grad
    }
    fn curvature(&self, net: &E::Net, trace: &E::Trace) -> E::Curvature {
        self.inner.curvature(net, trace)
    }
    fn gauss_newton(
        &self,
        net: &E::Net,
        trace: &E::Trace,
        curvature: &E::Curvature,
        tangent: &[f64],
        output_weights: &[f64],
    ) -> Vec<f64> {
        self.record(Direction::Up, tangent.len());
        let product = self
            .inner
            .gauss_newton(net, trace, curvature, tangent, output_weights);
        self.record(Direction::Down, product.len());
        product
    }
}

#[test]
fn the_batch_crosses_a_fixed_number_of_times_per_iteration() {
    let dir = std::env::temp_dir().join(format!("logo-transfers-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let demos =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/logo/inverted_double_pendulum");
    let path = dir.join("config.toml");
    std::fs::write(
        &path,
        format!(
            "env = \"SparseInvertedDoublePendulum-v4\"\niterations = 3\nsamples_per_iter = 1500\n\
             policy_hidden = [32, 32]\neval_steps = 100\n[critic]\nhidden = [32, 32]\n\
             [guidance]\ndemos = {:?}\ndelta0 = 0.2\nalpha = 0.9\nwarmup = 1\n\
             discriminator_hidden = [16, 16]\n",
            demos.to_str().unwrap()
        ),
    )
    .unwrap();
    let engine = Counting {
        inner: BurnEngine::<Cpu32>::new(Default::default(), "ndarray f32"),
        log: Mutex::new(Vec::new()),
    };
    let mut trainer = Trainer::new(engine, TrainConfig::load(&path).unwrap(), &dir).unwrap();
    // The largest flat vector: the policy's or a critic's parameters (under 1500 floats,
    // the smallest a batch column can be).
    let params = 11 * 32 + 32 + 32 * 32 + 32 + 32 + 1 + 1;
    trainer.engine().take(); // building: the networks' parameters go up once
    let mut batch_sized = Vec::new();
    while !trainer.done() {
        let m = trainer.step().unwrap();
        let log = trainer.engine().take();
        let big = |d: Direction| log.iter().filter(|(x, n)| *x == d && *n >= 1500).count();
        let (up, down) = (big(Direction::Up), big(Direction::Down));
        let small = log.iter().filter(|(_, n)| *n < 1500).count();
        eprintln!(
            "iteration {}: {} crossings, batch-sized {up} up and {down} down; {small} of at most {params} floats",
            m.iteration,
            log.len()
        );
        // Up: observations, actions, the discriminator's inputs, both advantage columns,
        // both critics' targets. Down: both critics' values, the guidance rewards.
        assert!(
            up <= 7 && down <= 3,
            "iteration {}: {up} up, {down} down",
            m.iteration
        );
        // The inner loops (CG, line searches, L-BFGS, Adam) moved many flat vectors.
        assert!(small > 50, "{small}");
        assert!(log.iter().all(|(_, n)| *n >= 1500 || *n <= params));
        batch_sized.push((up, down));
    }
    assert!(
        batch_sized.windows(2).all(|w| w[0] == w[1]),
        "{batch_sized:?}"
    );
}
