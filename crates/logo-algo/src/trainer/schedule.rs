//! How an iteration's steps 4-8 are laid over the run's worker threads: the one place
//! that says what runs beside what.

/// How an iteration's steps are laid over the run's worker threads. Either way every
/// step computes the same numbers: a run's metrics and checkpoints are bit-identical
/// under both (tested).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Schedule {
    /// One step after another, in Algorithm 1's order.
    #[cfg_attr(feature = "clap", value(help = "One step after another"))]
    Sequential,
    /// The critic fits of iteration k (step 7) beside its policy steps and discriminator
    /// update (4-6), then beside the sampling of batch k+1 and the evaluation of π_{k+1}:
    /// nothing among those reads the fitted critics, which iteration k+1's advantages
    /// need first.
    #[default]
    #[cfg_attr(
        feature = "clap",
        value(
            help = "Critic fits beside the policy steps, the next batch's sampling and the evaluation"
        )
    )]
    Pipelined,
}

impl Schedule {
    /// Steps 4-8 of one iteration: `steps` changes the policy (4-6) and `fit` the
    /// critics (7); `evaluate` and `collect` read the new policy in its `acting` form
    /// (8, and batch k + 1). Nothing among the others reads the fitted critics, so the
    /// pipelined schedule fits them beside everything else.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run<P, A, S, F, V, N, Error>(
        self,
        policy: &mut P,
        acting: impl FnOnce(&P) -> A + Send,
        steps: impl FnOnce(&mut P) -> Result<S, Error> + Send,
        fit: impl FnOnce() -> F + Send,
        evaluate: impl FnOnce(&A) -> Result<V, Error> + Send,
        collect: impl FnOnce(&A) -> Result<N, Error> + Send,
    ) -> Result<(S, F, V, N), Error>
    where
        P: Send,
        A: Sync,
        S: Send,
        F: Send,
        V: Send,
        N: Send,
        Error: Send,
    {
        match self {
            Schedule::Sequential => {
                let steps = steps(policy)?;
                let fits = fit();
                let acting = acting(policy);
                Ok((steps, fits, evaluate(&acting)?, collect(&acting)?))
            }
            Schedule::Pipelined => {
                let (fits, rest) = rayon::join(fit, || -> Result<_, Error> {
                    let steps = steps(policy)?;
                    let acting = acting(policy);
                    let (evaluated, next) = rayon::join(|| evaluate(&acting), || collect(&acting));
                    Ok((steps, evaluated?, next?))
                });
                let (steps, evaluated, next) = rest?;
                Ok((steps, fits, evaluated, next))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Schedule;
    use std::sync::Mutex;

    /// Both schedules give the same results, and only the pipelined one fits beside the
    /// policy steps; an error in the steps stops either.
    #[test]
    fn schedules_order_the_steps_and_agree() {
        for schedule in [Schedule::Sequential, Schedule::Pipelined] {
            let log = Mutex::new(Vec::new());
            let mut policy = 1.0_f64;
            let out = schedule.run(
                &mut policy,
                |p: &f64| *p * 10.0,
                |p: &mut f64| -> Result<f64, String> {
                    *p += 1.0;
                    log.lock().unwrap().push("steps");
                    Ok(*p)
                },
                || {
                    log.lock().unwrap().push("fit");
                    7
                },
                |a: &f64| Ok::<_, String>(*a + 0.5),
                |a: &f64| Ok::<_, String>(*a + 0.25),
            );
            assert_eq!(out, Ok((2.0, 7, 20.5, 20.25)), "{schedule:?}");
            if schedule == Schedule::Sequential {
                assert_eq!(*log.lock().unwrap(), ["steps", "fit"]);
            }
            let failed = schedule.run(
                &mut policy,
                |p: &f64| *p,
                |_: &mut f64| Err::<f64, _>("bad step".to_string()),
                || 0,
                |a: &f64| Ok(*a),
                |a: &f64| Ok(*a),
            );
            assert_eq!(failed, Err("bad step".to_string()));
        }
    }
}
