//! `logo`: the one command of logo-rl.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use logo_cli::{bc, data, eval, export, rollout, train};
use logo_lab::{bench, compare, plot, summary, sweep};

#[derive(Parser)]
#[command(
    name = "logo",
    version,
    about = "LOGO: reinforcement learning under sparse rewards with offline guidance"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the environment ids with their dimensions.
    Envs,
    /// Train TRPO or LOGO from a TOML config (configs/).
    Train(train::TrainArgs),
    /// List the algorithms, one line each, with their papers and configs.
    Algorithms,
    /// Behaviour cloning: fit a policy to demonstrations, score it, write a checkpoint.
    Bc(bc::BcArgs),
    /// Evaluate a checkpoint's mean-action policy: dense and sparse return, mean ± std.
    Eval(eval::EvalArgs),
    /// Write a checkpoint's policy alone (tensors and observation statistics, bit for
    /// bit): the form a run is kept in; `logo eval` plays it as it does the checkpoint.
    Export(export::ExportArgs),
    /// Run episodes with a fixed (random or zero) policy and print dense and sparse returns.
    Rollout(rollout::RolloutArgs),
    /// Measure throughput (see docs/benchmarks.md).
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Demonstration datasets: import, inspect, record.
    #[command(subcommand)]
    Data(data::DataCommand),
    /// Run configs x seeds, locally or as a Slurm job array; skips finished runs and
    /// resumes interrupted ones.
    Sweep(sweep::SweepArgs),
    /// Compare LOGO with the baselines on a task of your own: every method from one LOGO
    /// config, seeds through `logo sweep`, then report.md and figure.png.
    Compare(compare::CompareArgs),
    /// Plot dense evaluation return against samples: mean ± std over seeds per config.
    Plot(plot::PlotArgs),
    /// The numbers behind a figure: final, peak and late returns per config, mean ± std
    /// over seeds, as a markdown table.
    Summary(summary::SummaryArgs),
    /// One run of a written sweep plan (what a Slurm array task runs).
    #[command(hide = true)]
    SweepTask(sweep::TaskArgs),
}

/// glibc hands every allocation above 128 KiB to `mmap` and returns it on free, so each
/// buffer of a training batch (a block's activations, a tensor op's result) would fault
/// in fresh zeroed pages. Raising the thresholds keeps those buffers in the heap for reuse
/// (docs/benchmarks.md has the measurement).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_large_buffers() {
    unsafe extern "C" {
        fn mallopt(param: i32, value: i32) -> i32;
    }
    const M_TRIM_THRESHOLD: i32 = -1;
    const M_MMAP_THRESHOLD: i32 = -3;
    // SAFETY: mallopt only tunes the allocator; called before any other thread exists.
    unsafe {
        mallopt(M_MMAP_THRESHOLD, 32 << 20); // glibc's maximum on 64-bit
        mallopt(M_TRIM_THRESHOLD, 512 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_large_buffers() {}

/// Output into a closed pipe (`logo summary … | head`) ends the process quietly, as it
/// does other Unix tools, instead of panicking in `println!`: Rust ignores SIGPIPE
/// unless told otherwise. A run killed so keeps its last checkpoint and resumes.
#[cfg(unix)]
fn quiet_on_closed_pipe() {
    unsafe extern "C" {
        fn signal(signum: i32, handler: usize) -> usize;
    }
    const SIGPIPE: i32 = 13;
    const SIG_DFL: usize = 0;
    // SAFETY: restores the default disposition of one signal, before any thread exists.
    unsafe {
        signal(SIGPIPE, SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_on_closed_pipe() {}

/// The error and its causes on one line, each said once: library errors often repeat
/// their source's message in their own, and the chain would print it again.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    line
}

fn main() -> ExitCode {
    keep_large_buffers();
    quiet_on_closed_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Envs => rollout::list_envs(),
        Command::Rollout(args) => rollout::run(&args),
        Command::Train(args) => train::run(&args),
        Command::Algorithms => {
            print!("{}", logo_algo::algorithms::table());
            Ok(())
        }
        Command::Bc(args) => bc::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Bench(cmd) => bench::run(&cmd),
        Command::Data(cmd) => data::run(&cmd),
        Command::Sweep(args) => sweep::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Plot(args) => plot::run(&args),
        Command::Summary(args) => summary::run(&args),
        Command::SweepTask(args) => sweep::run_task(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::{Command, CommandFactory};
    use std::collections::BTreeMap;

    /// docs/cli.md says it lists every command and flag that `--help` does: every visible
    /// command has a row starting with its name, each of its flags stands in one of its
    /// rows, and every flag a row's command line names is one the command has.
    #[test]
    fn cli_md_lists_every_command_and_flag() {
        let page =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md"))
                .expect("docs/cli.md");
        let rows: Vec<&str> = page.lines().filter(|l| l.starts_with("| `logo ")).collect();
        let mut flags = BTreeMap::new();
        visible_flags(&Cli::command(), "logo", &mut flags);
        let mut missing = Vec::new();
        for (name, (leaf, own)) in &flags {
            let head = format!("| `{name}");
            let rows_of: Vec<&str> = rows
                .iter()
                .copied()
                .filter(|r| {
                    r.strip_prefix(&head)
                        .is_some_and(|rest| rest.starts_with([' ', '`']))
                })
                .collect();
            if *leaf && rows_of.is_empty() {
                missing.push(name.clone());
            }
            for flag in own {
                if !rows_of.iter().any(|row| names_flag(row, flag)) {
                    missing.push(format!("{name} {flag}"));
                }
            }
        }
        assert!(missing.is_empty(), "docs/cli.md lacks {missing:?}");
        let unknown: Vec<String> = rows
            .iter()
            .flat_map(|row| unknown_flags(row, &flags))
            .collect();
        assert!(
            unknown.is_empty(),
            "docs/cli.md names flags the commands lack: {unknown:?}"
        );
    }

    /// Every visible command by its full name ("logo data import"): whether it is a leaf
    /// (a command run as it is, so it has rows of its own) and its long flags.
    fn visible_flags(
        command: &Command,
        name: &str,
        out: &mut BTreeMap<String, (bool, Vec<String>)>,
    ) {
        let own = command
            .get_arguments()
            .filter(|a| !a.is_hide_set())
            .filter_map(|a| a.get_long())
            .map(|long| format!("--{long}"))
            .collect();
        out.insert(name.to_string(), (!command.has_subcommands(), own));
        for sub in command.get_subcommands().filter(|c| !c.is_hide_set()) {
            visible_flags(sub, &format!("{name} {}", sub.get_name()), out);
        }
    }

    /// The flags a row's command line (its first cell) names that its command lacks.
    fn unknown_flags(row: &str, flags: &BTreeMap<String, (bool, Vec<String>)>) -> Vec<String> {
        let line = row
            .trim_start_matches("| `")
            .split('`')
            .next()
            .unwrap_or("");
        let words: Vec<&str> = line.split_whitespace().collect();
        let command = (1..=words.len())
            .rev()
            .map(|n| words[..n].join(" "))
            .find(|name| flags.contains_key(name))
            .unwrap_or_default();
        let own = flags
            .get(&command)
            .map(|(_, own)| own.as_slice())
            .unwrap_or_default();
        words
            .iter()
            .flat_map(|w| w.split(['[', ']', '(', ')', '|', '=']))
            .filter(|w| w.starts_with("--") && w.len() > 2)
            .filter(|w| !own.iter().any(|f| f == w))
            .map(|w| format!("{command} {w}"))
            .collect()
    }

    /// `--seed` in a row, not only as the start of `--seeds`.
    fn names_flag(row: &str, flag: &str) -> bool {
        row.match_indices(flag).any(|(at, _)| {
            !row[at + flag.len()..].starts_with(|c: char| c.is_ascii_alphanumeric() || c == '-')
        })
    }
}
