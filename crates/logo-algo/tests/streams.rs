//! Every random stream of a run is its own: no two uses share a ChaCha8 stream, within an
//! iteration or across iterations (issue 27: iteration k's critic-fit shuffles used to be
//! iteration k+1's improvement-step shuffles).

use logo_algo::streams::{Stream, generator, sampler, stream_id};
use rand::Rng;

#[test]
fn every_iteration_and_use_has_its_own_stream_and_none_is_the_samplers() {
    let mut seen = std::collections::HashSet::new();
    for k in 0..20_000 {
        for stream in Stream::ALL {
            let id = stream_id(k, stream);
            assert_ne!(id, 0, "stream 0 is the sampler's");
            assert!(
                seen.insert(id),
                "iteration {k}'s {stream:?} shares stream {id}"
            );
        }
    }
}

fn draws(mut rng: rand_chacha::ChaCha8Rng) -> Vec<u64> {
    (0..16).map(|_| rng.random()).collect()
}

#[test]
fn a_critic_fit_and_the_next_iterations_policy_step_shuffle_differently() {
    let seed = 3;
    for k in [0, 1, 7, 499] {
        for fit in [Stream::EnvCriticFit, Stream::GuidanceCriticFit] {
            for step in [Stream::ImprovementStep, Stream::GuidanceStep] {
                assert_ne!(
                    draws(generator(seed, k, fit)),
                    draws(generator(seed, k + 1, step)),
                    "iteration {k}'s {fit:?} and iteration {}'s {step:?}",
                    k + 1
                );
            }
        }
        let within: Vec<Vec<u64>> = Stream::ALL
            .iter()
            .map(|&s| draws(generator(seed, k, s)))
            .collect();
        for (i, a) in within.iter().enumerate() {
            assert_ne!(
                a,
                &draws(sampler(seed)),
                "{:?} is the sampler's",
                Stream::ALL[i]
            );
            for b in &within[i + 1..] {
                assert_ne!(a, b, "two streams of iteration {k} draw alike");
            }
        }
    }
}

#[test]
fn the_same_seed_iteration_and_use_draw_the_same_numbers() {
    assert_eq!(
        draws(generator(9, 12, Stream::GuidanceStep)),
        draws(generator(9, 12, Stream::GuidanceStep))
    );
    assert_ne!(
        draws(generator(9, 12, Stream::GuidanceStep)),
        draws(generator(10, 12, Stream::GuidanceStep))
    );
}
