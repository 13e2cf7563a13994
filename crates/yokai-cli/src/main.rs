//! `yokai`: the command-line front end of the Yōkai Learning Environment.

mod average;
mod bench;
mod compare;
mod eval;
mod export;
mod paper;
mod play;
mod playthrough;
mod plots;
mod probe;
mod probe_end;
mod random;
mod replay;
mod serve;
mod show;
mod soak;
mod summary;
mod svg;
mod table;
mod train;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "yokai",
    version,
    about = "The Yōkai Learning Environment: a benchmark for zero-shot coordination",
    long_about = "The Yōkai Learning Environment: the cooperative card game Yōkai as a fast, exact \
                  engine for multi-agent RL research.\n\nConfigs are short names such as \
                  9c-2p-perfect, 16c-3p-imperfect (cards-players-memory) or a path to a TOML file."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Play games with uniformly random legal actions and print the paper's metrics.
    Random(random::Args),
    /// Measure environment steps per second (random legal actions, all seats observed).
    Bench(bench::Args),
    /// Self-play and cross-play of policies (every pair, every seating) with the paper's
    /// metrics, as Markdown, CSV and JSON.
    Eval(eval::Args),
    /// Train seeds of a config (IPPO, HE, OP on burn), then evaluate them: self-play,
    /// cross-play and the paper's table. Default: the CPU `quick` preset, seeds 0..3.
    Train(train::Args),
    /// Play in the terminal with any mix of humans, bots and trained policies (a TUI, or
    /// plain lines with --line); --save writes a replay.
    Play(play::Args),
    /// Step through a replay file, or render each turn as SVG/PNG pictures.
    Replay(replay::Args),
    /// Write a trained network's weights as a SafeTensors file (PyTorch, NumPy, JAX), with
    /// its training config and game as metadata.
    Export(export::Args),
    /// Average the weights of several policy files of one network into one policy: a run's
    /// snapshots over its last stretch (`--last 0.2`, runs trained with
    /// `run.snapshot_every`), or files named one by one.
    Average(average::Args),
    /// Put several evaluations side by side in the paper's table (e.g. IPPO vs HE vs OP),
    /// with the paper's numbers as reference rows where the game matches.
    Compare(compare::Args),
    /// Show one game's deal and the board as text (ground truth).
    Show(show::Args),
    /// Write one game step by step (board, legal actions, observation digests, rewards), or
    /// with --write the golden set the engine's tests compare against.
    Playthrough(playthrough::Args),
    /// Random legal play across every preset through the batched environment, checking the
    /// rules' invariants at every step and replaying a sample against the reference.
    Soak(soak::Args),
    /// Linear probes of card colours in trained policies' memories, by game step, in
    /// self-play and with partners, against chance and a perfect-memory oracle; for a
    /// network with a belief head (`ppo.belief_aux`), the head's own guesses beside them.
    Probe(probe::Args),
    /// Where trained policies could END, what they did against what the seat knew
    /// first-hand: do they reach boards they know to be clustered, and END there?
    ProbeEnd(probe_end::Args),
    /// Play with agents in a web browser: a local server with the board, clickable moves,
    /// bots shown step by step, replays, and every game recorded (docs/play.md).
    Serve(serve::Args),
}

/// Keep memory that `free` returns in the process (glibc's malloc): training allocates
/// and frees buffers of megabytes (each minibatch's tensors and gradients) every update
/// from several threads. By default glibc hands the free top of a thread's arena back to
/// the kernel once it passes the trim threshold (128 kB, raised as large blocks come and
/// go), and the next update faults it in again. With the rollout's buffers kept from one
/// update to the next, 3 `cpu-fast` seeds side by side made 0.6–1.0M page faults in 100
/// updates and spent 5–7 % of their CPU time in the kernel; with the thresholds below,
/// 25k faults and 1 % (docs/results/rollout-buffers.md). They keep up to 1 GiB free per
/// arena and serve blocks up to 32 MiB (glibc's largest setting) from the arenas. Other
/// C libraries: nothing to do.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters; called before any thread starts.
    unsafe {
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
    }
}

fn main() -> ExitCode {
    // Like other Unix tools, stop quietly when the reader of our output goes away
    // (`yokai bench | head`) instead of panicking on the failed write. Rust ignores SIGPIPE
    // by default; restoring the default action is safe before any thread starts.
    #[cfg(unix)]
    // SAFETY: signal() with SIG_DFL installs no handler code and runs single-threaded here.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    keep_freed_memory();
    let cli = Cli::parse();
    // Before any thread starts: burn's default device is where a resumed run's optimiser
    // state is first loaded (Backend::make_burn_default says why).
    match &cli.command {
        Command::Train(args) => args.device(),
        _ => yokai_train::Backend::Cpu,
    }
    .make_burn_default();
    let result = match cli.command {
        Command::Random(args) => random::run(args),
        Command::Show(args) => show::run(args),
        Command::Playthrough(args) => playthrough::run(args),
        Command::Soak(args) => soak::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Eval(args) => eval::run(args),
        Command::Train(args) => train::run(args),
        Command::Play(args) => play::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Export(args) => export::run(args),
        Command::Average(args) => average::run(args),
        Command::Replay(args) => replay::run(args),
        Command::Probe(args) => probe::run(args),
        Command::ProbeEnd(args) => probe_end::run(args),
        Command::Serve(args) => serve::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // `{:#}` prints the context chain on one line: "cannot read x.toml: not found".
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
