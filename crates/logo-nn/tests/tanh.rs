//! The fast f64 tanh against libm's.

use logo_nn::kernels::tanh::tanh_f64_in_place;

#[test]
fn fast_tanh_is_within_a_few_ulp_of_libm() {
    let mut xs: Vec<f64> = (-200_000..=200_000).map(|i| i as f64 * 1e-4).collect(); // [-20, 20]
    xs.extend([
        0.0,
        -0.0,
        1e-300,
        -1e-300,
        1e-12,
        0.4999999999,
        0.5,
        0.5000000001,
        19.0,
        25.0,
        700.0,
        -700.0,
        1e300,
    ]);
    let mut ys = xs.clone();
    tanh_f64_in_place(&mut ys);
    let mut worst_ulp = 0u64;
    for (x, y) in xs.iter().zip(&ys) {
        let want = x.tanh();
        let ulp = (y.to_bits() as i64 - want.to_bits() as i64).unsigned_abs();
        assert!(
            ulp <= 4 || (y - want).abs() <= 1e-16,
            "tanh({x}) = {y}, libm {want}"
        );
        worst_ulp = worst_ulp.max(ulp);
    }
    assert!(ys.iter().all(|y| y.abs() <= 1.0));
    let mut nan = [f64::NAN, 1.0];
    tanh_f64_in_place(&mut nan);
    assert!(nan[0].is_nan(), "NaN must stay NaN, got {}", nan[0]);
    eprintln!("worst: {worst_ulp} ulp");
}

#[test]
fn fast_tanh_is_faster_than_libm() {
    let xs: Vec<f64> = (0..1_000_000)
        .map(|i| ((i as f64) * 0.001).sin() * 3.0)
        .collect();
    let time = |f: &dyn Fn(&mut Vec<f64>)| {
        (0..5)
            .map(|_| {
                let mut v = xs.clone();
                let t = std::time::Instant::now();
                f(&mut v);
                std::hint::black_box(&v);
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let fast = time(&|v| tanh_f64_in_place(v));
    let libm = time(&|v| v.iter_mut().for_each(|x| *x = x.tanh()));
    eprintln!(
        "1M tanh: fast {:.2} ms, libm {:.2} ms",
        fast * 1e3,
        libm * 1e3
    );
    assert!(
        fast < libm,
        "the fast path must be faster, or it has no reason to exist"
    );
}
