//! Generalised advantage estimation on plain host vectors.

/// Per step of a batch of whole episodes laid end to end.
pub struct GaeInput<'a> {
    pub rewards: &'a [f64],
    /// V(s_t).
    pub values: &'a [f64],
    /// The MDP ended at t: nothing to bootstrap.
    pub terminated: &'a [bool],
    /// t is the last step of its episode (terminated or truncated).
    pub episode_end: &'a [bool],
    /// V(s_{t+1}) where the time limit truncated the episode at t (else unused).
    pub truncation_values: &'a [f64],
}

/// Returns (advantages, returns = values + advantages).
///
/// With `cross_episode_bootstrap` a truncated episode bootstraps, as the LOGO reference
/// does (it has no time-limit flag), from the *next episode's first state* and carries
/// its advantage across the boundary; otherwise from V(s_T) of its own final state.
pub fn gae(
    input: &GaeInput,
    gamma: f64,
    lambda: f64,
    cross_episode_bootstrap: bool,
) -> (Vec<f64>, Vec<f64>) {
    let n = input.rewards.len();
    let mut advantages = vec![0.0; n];
    let mut next_advantage = 0.0;
    for t in (0..n).rev() {
        let next_value_in_batch = if t + 1 < n { input.values[t + 1] } else { 0.0 };
        let (next_value, carry) = if input.terminated[t] {
            (0.0, 0.0)
        } else if input.episode_end[t] {
            if cross_episode_bootstrap {
                (next_value_in_batch, 1.0)
            } else {
                (input.truncation_values[t], 0.0)
            }
        } else {
            (next_value_in_batch, 1.0)
        };
        let delta = input.rewards[t] + gamma * next_value - input.values[t];
        next_advantage = delta + gamma * lambda * carry * next_advantage;
        advantages[t] = next_advantage;
    }
    let returns = advantages
        .iter()
        .zip(input.values)
        .map(|(a, v)| a + v)
        .collect();
    (advantages, returns)
}

/// Shifts and scales to mean 0, standard deviation 1 (the reference's per-batch rule;
/// the standard deviation is the unbiased one, as torch's `std()`).
pub fn normalise(x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0).max(1.0);
    let std = var.sqrt();
    x.iter()
        .map(|v| (v - mean) / if std > 0.0 { std } else { 1.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Textbook GAE on one episode, by the definition Â_t = Σ_l (γλ)^l δ_{t+l}.
    fn by_definition(r: &[f64], v: &[f64], v_end: f64, gamma: f64, lambda: f64) -> Vec<f64> {
        let n = r.len();
        let next = |t: usize| if t + 1 < n { v[t + 1] } else { v_end };
        let delta: Vec<f64> = (0..n).map(|t| r[t] + gamma * next(t) - v[t]).collect();
        (0..n)
            .map(|t| {
                (t..n)
                    .map(|l| (gamma * lambda).powi((l - t) as i32) * delta[l])
                    .sum()
            })
            .collect()
    }

    #[test]
    fn matches_the_definition_across_terminated_and_truncated_episodes() {
        let r = [1.0, 0.5, -0.2, 2.0, 0.0, 1.5, 0.3];
        let v = [0.3, -0.1, 0.7, 1.2, 0.4, -0.5, 0.9];
        // Episode A: steps 0..3, terminated. Episode B: steps 3..7, truncated with V(s_T) = 2.5.
        let terminated = [false, false, true, false, false, false, false];
        let end = [false, false, true, false, false, false, true];
        let trunc = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.5];
        let input = GaeInput {
            rewards: &r,
            values: &v,
            terminated: &terminated,
            episode_end: &end,
            truncation_values: &trunc,
        };
        let (adv, ret) = gae(&input, 0.99, 0.95, false);
        let mut want = by_definition(&r[..3], &v[..3], 0.0, 0.99, 0.95);
        want.extend(by_definition(&r[3..], &v[3..], 2.5, 0.99, 0.95));
        for (a, w) in adv.iter().zip(&want) {
            assert!((a - w).abs() < 1e-12, "{adv:?} vs {want:?}");
        }
        assert!((ret[4] - (adv[4] + v[4])).abs() < 1e-15);
        // The reference's option: at a truncation, bootstrap into the next episode.
        let end2 = [false, true, false, false, false, false, true];
        let input = GaeInput {
            rewards: &r,
            values: &v,
            terminated: &[false; 7],
            episode_end: &end2,
            truncation_values: &trunc,
        };
        let (cross, _) = gae(&input, 0.99, 0.95, true);
        let whole = by_definition(&r, &v, 0.0, 0.99, 0.95);
        for (a, w) in cross.iter().zip(&whole) {
            assert!((a - w).abs() < 1e-12);
        }
    }

    #[test]
    fn normalise_gives_mean_zero_unit_std() {
        let z = normalise(&[1.0, 2.0, 3.0, 10.0]);
        let mean: f64 = z.iter().sum::<f64>() / 4.0;
        let var: f64 = z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 3.0;
        assert!(mean.abs() < 1e-15 && (var - 1.0).abs() < 1e-12);
        assert_eq!(normalise(&[2.0, 2.0]), vec![0.0, 0.0]);
    }
}
