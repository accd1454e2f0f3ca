//! Every random draw of a run, in one table. A run is a function of its seed: each
//! stream below is a ChaCha8 generator derived from the seed, and no two uses share a
//! stream, within an iteration or across iterations.
//!
//! | what draws | generator | when |
//! | --- | --- | --- |
//! | the sampler | ChaCha8(seed), stream 0, one generator for the whole run (its position is in the checkpoint) | one `u64` per env copy per batch, which seeds that copy's action noise for the batch |
//! | env copy i's reset noise | ChaCha8(seed + i), inside the env (its position is in the checkpoint) | every reset |
//! | iteration k's improvement step | ChaCha8(seed), stream [`stream_id`]`(k, ImprovementStep)` | minibatch shuffles (first-order kinds) |
//! | iteration k's guidance step | stream `stream_id(k, GuidanceStep)` | likewise |
//! | iteration k's env critic fit | stream `stream_id(k, EnvCriticFit)` | minibatch shuffles (`method = "adam"`), every net of the set in turn |
//! | iteration k's guidance critic fit | stream `stream_id(k, GuidanceCriticFit)` | likewise |
//! | the discriminator | none | `discriminator_steps` full-batch steps per iteration |
//! | behaviour cloning (`[init] kind = "bc"`, `logo bc`) | ChaCha8(seed), stream [`EVALUATION_STREAMS`] − 1 (`bc::generator`) | minibatch shuffles, once before iteration 0 |
//! | the evaluation (`eval_initial_states = "fixed"`, the default) | none: reset seeds [`crate::episode::evaluation_seed`], the same at every iteration by design, mean actions | every evaluation |
//! | iteration k's evaluation (`"fresh"`) | ChaCha8(seed), stream [`EVALUATION_STREAMS`] + k, apart from every id above | one `u64` reset seed per episode |
//!
//! Derived streams need no state in the checkpoint: a resumed run draws what an
//! uninterrupted one does.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The per-iteration streams, in the order of their ids within an iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    ImprovementStep = 0,
    GuidanceStep = 1,
    EnvCriticFit = 2,
    GuidanceCriticFit = 3,
}

impl Stream {
    pub const ALL: [Stream; 4] = [
        Stream::ImprovementStep,
        Stream::GuidanceStep,
        Stream::EnvCriticFit,
        Stream::GuidanceCriticFit,
    ];
}

/// Stream 0 is the sampler's; iteration k owns the next `Stream::ALL.len()` ids.
pub fn stream_id(iteration: usize, stream: Stream) -> u64 {
    1 + Stream::ALL.len() as u64 * iteration as u64 + stream as u64
}

/// The generator of `stream` in `iteration` of a run with `seed`.
pub fn generator(seed: u64, iteration: usize, stream: Stream) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream_id(iteration, stream));
    rng
}

/// The first stream id of the fresh evaluations: far above any iteration's ids, so that
/// adding them moved no other stream.
pub const EVALUATION_STREAMS: u64 = 1 << 62;

/// The generator of iteration `iteration`'s fresh evaluation reset seeds.
pub fn evaluation(seed: u64, iteration: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(EVALUATION_STREAMS + iteration as u64);
    rng
}

/// The sampler's generator at the start of a run.
pub fn sampler(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}
