//! The two ways of cutting a batch.

use logo_algo::sampler::{RolloutMode, Sampler};
use logo_envs::{EnvFactory, EnvOptions, VecEnv};
use logo_nn::{Cpu, PolicyConfig};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn setup() -> (VecEnv, logo_nn::ActingPolicy) {
    let factory = EnvFactory::new("Hopper-v4", &EnvOptions::default()).unwrap();
    let venv = VecEnv::new(&factory, 3, 1, 5).unwrap();
    let policy = PolicyConfig::new(11, 3)
        .init::<Cpu>(&Default::default())
        .acting();
    (venv, policy)
}

#[test]
fn steps_mode_takes_a_fixed_number_of_steps_per_copy_and_continues_episodes() {
    let (mut venv, policy) = setup();
    let mut sampler = Sampler::new(RolloutMode::Steps, 3);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut total_reward = 0.0;
    let mut total_logged = 0.0;
    for _ in 0..4 {
        let batch = sampler.collect(&mut venv, &policy, &mut rng, 100).unwrap();
        assert_eq!(batch.len(), 3 * 34, "ceil(100 / 3) steps per copy");
        let ends = batch.episode_end.iter().filter(|e| **e).count();
        let terminated = batch.terminated.iter().filter(|t| **t).count();
        // Every segment ends either terminated or bootstrapped (truncated or cut).
        assert_eq!(ends, terminated + batch.truncations.len());
        // Each copy's batch ends with a cut or an episode end: at least 3 segments.
        assert!(ends >= 3);
        total_reward += batch.rewards.iter().sum::<f64>();
        total_logged += batch.episode_returns.iter().sum::<f64>();
    }
    // Completed episodes are logged with their whole return, earlier batches included;
    // what is not logged is the three episodes still running.
    assert!(total_logged <= total_reward + 1e-9 && total_logged > 0.0);
    assert!(!sampler.at_episode_starts());
}

#[test]
fn episodes_mode_collects_whole_episodes_past_the_sample_count() {
    let (mut venv, policy) = setup();
    let mut sampler = Sampler::new(RolloutMode::Episodes, 3);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let batch = sampler.collect(&mut venv, &policy, &mut rng, 100).unwrap();
    assert!(batch.len() >= 100);
    assert_eq!(batch.episode_end.last(), Some(&true));
    // The reference's rule: the last episode is the one that took the batch past the
    // count (each copy's share alone overshoots by up to an episode per copy).
    for samples in [100, 300, 500] {
        let batch = sampler
            .collect(&mut venv, &policy, &mut rng, samples)
            .unwrap();
        let ends: Vec<usize> = (0..batch.len()).filter(|&t| batch.episode_end[t]).collect();
        let before_last = ends.len().checked_sub(2).map_or(0, |i| ends[i] + 1);
        assert!(batch.len() >= samples);
        assert!(
            before_last < samples,
            "{before_last} steps before the last episode for {samples}"
        );
    }
    let ends = batch.episode_end.iter().filter(|e| **e).count();
    assert_eq!(ends, batch.episode_returns.len(), "only whole episodes");
    let total: f64 = batch.rewards.iter().sum();
    let logged: f64 = batch.episode_returns.iter().sum();
    assert!((total - logged).abs() < 1e-9 * total.abs().max(1.0));
    assert!(venv.reset_points().is_ok(), "every copy freshly reset");
}

#[test]
fn batches_do_not_depend_on_the_number_of_threads() {
    let factory = EnvFactory::new("SparseHopper-v4", &EnvOptions::default()).unwrap();
    let policy = PolicyConfig::new(11, 3)
        .init::<Cpu>(&Default::default())
        .acting();
    let run = |threads: usize, mode: RolloutMode| {
        let mut venv = VecEnv::new(&factory, 3, threads, 9).unwrap();
        let mut sampler = Sampler::new(mode, 3);
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        (0..2)
            .map(|_| {
                let b = sampler.collect(&mut venv, &policy, &mut rng, 200).unwrap();
                (
                    b.obs,
                    b.actions,
                    b.rewards,
                    b.episode_returns,
                    b.truncations,
                )
            })
            .collect::<Vec<_>>()
    };
    for mode in [RolloutMode::Episodes, RolloutMode::Steps] {
        assert_eq!(run(1, mode), run(2, mode), "{mode:?}");
    }
}

/// `clip_actions` reaches the evaluation: a policy whose mean action is far out of range
/// moves Hopper the same with or without clipping (MuJoCo clamps controls), but the
/// clipped evaluation sends actions within [-1, 1] and pays less control cost.
#[test]
fn evaluation_clips_the_mean_action_when_asked() {
    use logo_algo::episode::{EvaluationPlan, SuccessRule, evaluate};
    use logo_nn::kernels::HostMlp;
    let dims = vec![11, 3];
    let params = vec![5.0; logo_nn::mlp::num_params(&dims)];
    let policy = logo_nn::ActingPolicy::new(HostMlp::new(dims, params), vec![0.0; 3]);
    let factory = EnvFactory::new("Hopper-v4", &EnvOptions::default()).unwrap();
    let mut env = factory.build().unwrap();
    let mut run = |clip_actions| {
        let plan = EvaluationPlan {
            min_steps: 50,
            min_episodes: 1,
            clip_actions,
            success: SuccessRule::Task,
        };
        evaluate(env.as_mut(), &policy, |k| k as u64, plan).unwrap()
    };
    let (sent, clipped) = (run(false), run(true));
    assert!(sent.action_rms > 1.0, "{}", sent.action_rms);
    assert!(clipped.action_rms <= 1.0, "{}", clipped.action_rms);
    assert_eq!(sent.moved, clipped.moved);
    assert!(clipped.dense_return > sent.dense_return);
}
