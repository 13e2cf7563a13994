//! A run directory: one seed of one training config on disk.
//!
//! ```text
//! RUN/config.toml      the resolved training config (every field)
//! RUN/game.toml        the resolved game config
//! RUN/metrics.jsonl    one JSON line per logged update (step, SPS, R, win, SEE, EE, WEE, LEN, losses, entropy)
//! RUN/belief.jsonl     OBL levels ≥ 2: one JSON line per update of the belief model (its
//!                      cross-entropy and the first-hand baseline's, nats per unseen card)
//! RUN/events.out.tfevents.*  the same figures for TensorBoard (`tensorboard --logdir RUN`),
//!                      a new file on each resume
//! RUN/checkpoint.ykc   network, optimiser and loop state, replaced atomically
//! RUN/policy.ykp       the final policy, loadable by `yokai eval` and Python
//! RUN/snapshots/       with `run.snapshot_every`, the policy every that many updates
//! RUN/replays/         at every checkpoint, the last finished training game of env 0
//! ```

use crate::artifact::names::{
    snapshot_name, BELIEF_METRICS, CHECKPOINT, METRICS, POLICY, SNAPSHOTS,
};
use crate::artifact::read_header;
use crate::artifact::tensorboard::{scalars_of, EventWriter};
use crate::backend::Backend;
use crate::config::TrainConfig;
use crate::error::TrainError;
use crate::network::{for_network, Encoder, NetworkJob, Recurrent};
use crate::obl::learn::BeliefStats;
use crate::trainer::{Trainer, UpdateStats};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What a finished (or stopped) run reports.
#[derive(Clone, Debug)]
pub struct RunSummary {
    pub dir: PathBuf,
    pub seed: u64,
    /// Updates and environment steps of the whole run so far.
    pub updates: u64,
    pub env_steps: u64,
    /// Environment steps taken by this call (less than `env_steps` after a resume).
    pub env_steps_here: u64,
    /// The last logged update's figures.
    pub last: Option<UpdateStats>,
    /// Wall-clock seconds of this call.
    pub seconds: f64,
}

fn io(path: &Path, source: std::io::Error) -> TrainError {
    TrainError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// One call of [`train_run`]: what to train, where, and how far.
#[derive(Clone, Copy, Debug)]
pub struct RunRequest<'a> {
    pub config: &'a TrainConfig,
    pub seed: u64,
    /// The run directory. A new run needs one that holds no run yet.
    pub dir: &'a Path,
    /// Continue the run in `dir` from its checkpoint. The checkpoint's config governs then,
    /// except for `ppo.total_steps`, taken from `config` so that a run can be extended.
    pub resume: bool,
    /// Stop after this many updates of this call (the run can be resumed later); `None`
    /// runs to the end of the config's budget.
    pub max_updates: Option<u64>,
    /// Where the network trains (the environment always steps on the CPU).
    pub backend: Backend,
}

/// Start or continue the run described by `request`. `on_update` sees every update (for
/// progress bars).
pub fn train_run(
    request: &RunRequest<'_>,
    on_update: &mut dyn FnMut(&UpdateStats, u64),
) -> Result<RunSummary, TrainError> {
    /// Training as a [`NetworkJob`]: `run` with the config's network types.
    struct Train<'a, 'b, 'c> {
        request: &'a RunRequest<'b>,
        on_update: &'c mut dyn FnMut(&UpdateStats, u64),
    }
    impl NetworkJob for Train<'_, '_, '_> {
        type Output = Result<RunSummary, TrainError>;
        fn run<E: Encoder + 'static, M: Recurrent + 'static>(self) -> Self::Output {
            run::<E, M>(self.request, self.on_update)
        }
    }
    for_network(&request.config.network, Train { request, on_update })
}

/// The training config a run's checkpoint was written with, read from its header.
pub fn checkpoint_config(dir: &Path) -> Result<TrainConfig, TrainError> {
    let path = dir.join(CHECKPOINT);
    let file = crate::artifact::Container::read(&path)?;
    let header = read_header(&file, &path)?;
    Ok(TrainConfig::from_toml_str(
        &header.train_config,
        &path.display().to_string(),
    )?)
}

/// One seed's run with the network types `E`, `M`: open it (new or resumed), then update
/// until the budget or `max_updates`, logging metrics and checkpointing as the config says;
/// a stop leaves a checkpoint and a policy file.
fn run<E: Encoder, M: Recurrent>(
    request: &RunRequest<'_>,
    on_update: &mut dyn FnMut(&UpdateStats, u64),
) -> Result<RunSummary, TrainError> {
    let (dir, max_updates) = (request.dir, request.max_updates);
    let start = std::time::Instant::now();
    let checkpoint = dir.join(CHECKPOINT);
    let metrics_path = dir.join(METRICS);
    let mut trainer = open::<E, M>(request)?;
    write_belief_curve(&trainer, dir)?;
    let total = trainer.config().updates();
    let steps_before = trainer.env_steps();
    let mut log = std::fs::OpenOptions::new()
        .append(true)
        .open(&metrics_path)
        .map_err(|e| io(&metrics_path, e))?;
    let resumed_at = (trainer.update_count() > 0).then_some(steps_before);
    let mut events = EventWriter::create(dir, resumed_at).map_err(|e| io(dir, e))?;
    let (log_every, ckpt_every, snapshot_every) = (
        trainer.config().run.log_every,
        trainer.config().run.checkpoint_every,
        trainer.config().run.snapshot_every,
    );
    let mut last = None;
    let mut done_here = 0;
    while !trainer.is_done() && max_updates.is_none_or(|m| done_here < m) {
        let stats = trainer.update()?;
        done_here += 1;
        on_update(&stats, total);
        let u = stats.update;
        if u % log_every == 0 || u == total {
            // One serialisation serves both logs (its keys in alphabetical order).
            let value = serde_json::to_value(&stats).expect("stats serialise");
            writeln!(log, "{value}").map_err(|e| io(&metrics_path, e))?;
            let scalars = scalars_of(&value, "train", &["update", "env_steps"]);
            events
                .scalars(stats.env_steps, &scalars)
                .map_err(|e| io(events.path(), e))?;
        }
        if u % ckpt_every == 0 || u == total {
            trainer.checkpoint().write_atomic(&checkpoint)?;
            save_training_game(&trainer, dir, u)?;
        }
        if snapshot_every > 0 && u % snapshot_every == 0 {
            let snapshots = dir.join(SNAPSHOTS);
            std::fs::create_dir_all(&snapshots).map_err(|e| io(&snapshots, e))?;
            trainer
                .policy()
                .write_atomic(&snapshots.join(snapshot_name(u)))?;
        }
        last = Some(stats);
    }
    // A stop before the budget still leaves a resumable checkpoint.
    trainer.checkpoint().write_atomic(&checkpoint)?;
    trainer.policy().write_atomic(&dir.join(POLICY))?;
    Ok(RunSummary {
        dir: dir.to_path_buf(),
        seed: trainer.seed(),
        updates: trainer.update_count(),
        env_steps: trainer.env_steps(),
        env_steps_here: trainer.env_steps() - steps_before,
        last,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The run's trainer: resumed from the checkpoint in `request.dir` (its metrics log cut
/// back to the checkpoint), or new in a new run directory with its config, game and an
/// empty log.
fn open<E: Encoder, M: Recurrent>(request: &RunRequest<'_>) -> Result<Trainer<E, M>, TrainError> {
    let RunRequest {
        config,
        seed,
        dir,
        resume,
        backend,
        ..
    } = *request;
    let device = backend.device()?;
    let checkpoint = dir.join(CHECKPOINT);
    let metrics_path = dir.join(METRICS);
    if resume {
        let mut t = Trainer::<E, M>::resume_on(&checkpoint, device)?;
        t.set_total_steps(config.ppo.total_steps);
        truncate_metrics(&metrics_path, t.update_count())?;
        return Ok(t);
    }
    if checkpoint.exists() {
        return Err(TrainError::RunExists {
            dir: dir.to_path_buf(),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let t = Trainer::<E, M>::new_on(config.clone(), seed, device)?;
    let game = t.config().game_config()?;
    write(&dir.join("config.toml"), &t.config().to_toml())?;
    write(&dir.join("game.toml"), &game.to_toml())?;
    write(&metrics_path, "")?;
    Ok(t)
}

/// An OBL run's belief curve, `belief.jsonl`, written at every start and resume (a resume
/// reads the curve from its checkpoint, or trains the belief again identically).
fn write_belief_curve<E: Encoder, M: Recurrent>(
    trainer: &Trainer<E, M>,
    dir: &Path,
) -> Result<(), TrainError> {
    let Some(curve) = trainer.belief_curve() else {
        return Ok(());
    };
    let lines: String = curve
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let mut v = serde_json::to_value(s).expect("belief stats serialise");
            v["update"] = serde_json::json!(k + 1);
            format!("{v}\n")
        })
        .collect();
    write(&dir.join(BELIEF_METRICS), &lines)
}

/// Save the last training game of env 0 as `RUN/replays/update-NNNNNN.jsonl`, so that what
/// the policy did at each checkpoint can be looked at with `yokai replay`.
fn save_training_game<E: Encoder, M: Recurrent>(
    trainer: &Trainer<E, M>,
    dir: &Path,
    update: u64,
) -> Result<(), TrainError> {
    let Some(record) = trainer.last_finished_game() else {
        return Ok(());
    };
    let players = record.config.players();
    let seats = (0..players)
        .map(|s| format!("{} (training, update {update}, seat {s})", dir.display()))
        .collect();
    let seed = match record.deal {
        yokai_engine::DealSource::Seed(seed) => Some(seed),
        yokai_engine::DealSource::Explicit(_) => None,
    };
    let replay = yokai_engine::Replay::from_record(&record, seed, seats).map_err(|e| {
        TrainError::Mismatch {
            path: dir.display().to_string(),
            message: format!("a training game does not replay: {e}"),
        }
    })?;
    let replays = dir.join("replays");
    std::fs::create_dir_all(&replays).map_err(|e| io(&replays, e))?;
    write(
        &replays.join(format!("update-{update:06}.jsonl")),
        &replay.to_jsonl(),
    )
}

fn write(path: &Path, text: &str) -> Result<(), TrainError> {
    std::fs::write(path, text).map_err(|e| io(path, e))
}

/// Drop metric lines past the checkpoint's update, so that a resumed log has no duplicates.
/// The kept lines go to a file beside the log that is then renamed over it: rewriting the
/// log in place truncates it first, and a run killed in that window (seen under load in
/// `tests/crash.rs`) lost every line before the checkpoint for good.
fn truncate_metrics(path: &Path, update: u64) -> Result<(), TrainError> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let kept: String = text
        .lines()
        .filter(|l| serde_json::from_str::<UpdateStats>(l).is_ok_and(|s| s.update <= update))
        .map(|l| format!("{l}\n"))
        .collect();
    let tmp = path.with_extension("jsonl.tmp");
    write(&tmp, &kept)?;
    std::fs::rename(&tmp, path).map_err(|e| io(path, e))
}

/// Read a run's belief curve (`belief.jsonl`, OBL levels ≥ 2): each update's figures in
/// order; `None` for a run without one.
pub fn read_belief_metrics(dir: &Path) -> Result<Option<Vec<BeliefStats>>, TrainError> {
    let path = dir.join(BELIEF_METRICS);
    if !path.exists() {
        return Ok(None);
    }
    read_json_lines(&path, "belief curve line").map(Some)
}

/// Read a run's metrics log.
pub fn read_metrics(dir: &Path) -> Result<Vec<UpdateStats>, TrainError> {
    read_json_lines(&dir.join(METRICS), "metrics line")
}

/// One value per non-blank line of a JSON-lines file; a line that does not parse is an
/// error naming the file, the line and `what` it should have been.
fn read_json_lines<T: serde::de::DeserializeOwned>(
    path: &Path,
    what: &'static str,
) -> Result<Vec<T>, TrainError> {
    let text = std::fs::read_to_string(path).map_err(|e| io(path, e))?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|source| TrainError::Json {
                path: format!("{}:{}", path.display(), i + 1),
                what,
                source,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_belief_curve_reads_back_and_a_broken_line_names_its_place() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_belief_metrics(dir.path()).unwrap(), None);
        let stats = BeliefStats {
            cross_entropy: 0.7,
            uniform_cross_entropy: 0.75,
            uniform_kl: 0.03,
            slots: 12,
        };
        let mut line = serde_json::to_value(stats).unwrap();
        line["update"] = serde_json::json!(1);
        let path = dir.path().join(BELIEF_METRICS);
        std::fs::write(&path, format!("{line}\n")).unwrap();
        assert_eq!(read_belief_metrics(dir.path()).unwrap(), Some(vec![stats]));
        std::fs::write(&path, format!("{line}\n{{\"cross_entropy\": \"x\"}}\n")).unwrap();
        let e = read_belief_metrics(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("belief.jsonl:2") && e.contains("belief curve line"),
            "{e}"
        );
    }
}
