//! Sums in numpy's order, so that a cost summed here matches Gymnasium's to the last bit.

/// numpy's pairwise summation of a float64 array (its `np.sum` on contiguous data): below
/// 8 values a plain sum from 0; up to 128, eight running sums over the blocks of 8, added
/// pairwise, then the remainder in order; above that, the halves (cut at a multiple of 8)
/// summed so and added.
pub(crate) fn numpy_sum(values: &[f64]) -> f64 {
    numpy_sum_of(values, |v| v)
}

/// [`numpy_sum`] of `f` of each value (`np.sum(np.square(a))` is `numpy_sum_of(a, |v| v * v)`),
/// without an array of the results: `f` is elementwise, so the sums are the same.
pub(crate) fn numpy_sum_of(values: &[f64], f: impl Fn(f64) -> f64 + Copy) -> f64 {
    let n = values.len();
    if n < 8 {
        return values.iter().fold(0.0, |sum, &v| sum + f(v));
    }
    if n <= 128 {
        let mut r = [0.0; 8];
        for (sum, &v) in r.iter_mut().zip(&values[..8]) {
            *sum = f(v);
        }
        let blocks = n - n % 8;
        for block in values[8..blocks].chunks_exact(8) {
            for (sum, &v) in r.iter_mut().zip(block) {
                *sum += f(v);
            }
        }
        let paired = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        return values[blocks..].iter().fold(paired, |sum, &v| sum + f(v));
    }
    let half = n / 2 - (n / 2) % 8;
    numpy_sum_of(&values[..half], f) + numpy_sum_of(&values[half..], f)
}

/// `np.linalg.norm` of a 3-vector as numpy computes it here: the square root of a BLAS dot
/// product, a chain of fused multiply-adds.
pub(crate) fn norm3([x, y, z]: [f64; 3]) -> f64 {
    z.mul_add(z, y.mul_add(y, x * x)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::numpy_sum;

    /// ((37 i mod 101) − 50.3) / 3 · 10^(i mod 5): values whose sum depends on the order,
    /// each correctly rounded in numpy and here alike.
    fn values(n: usize) -> Vec<f64> {
        let scale = [1.0, 10.0, 100.0, 1000.0, 10000.0];
        (0..n)
            .map(|i| (((i * 37) % 101) as f64 - 50.3) / 3.0 * scale[i % 5])
            .collect()
    }

    #[test]
    fn the_order_is_numpys() {
        // np.sum of the same values (numpy 2, float64), as bits: 84 values take the
        // eight-accumulator path, 300 the split into halves; both differ from the
        // plain sum in the last bits.
        for (n, numpy) in [(84, 0x40f8cc34ccccccda_u64), (300, 0xc0d8cdeaaaaaa9f8)] {
            let v = values(n);
            assert_eq!(numpy_sum(&v).to_bits(), numpy, "{n} values");
            assert_ne!(v.iter().sum::<f64>().to_bits(), numpy, "{n} values");
        }
        // Below 8 values it is the plain sum.
        let few = values(7);
        assert_eq!(numpy_sum(&few), few.iter().fold(0.0, |s, v| s + v));
    }
}
