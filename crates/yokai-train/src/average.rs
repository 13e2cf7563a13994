//! Weight averaging: one policy whose every parameter is the mean of that parameter over
//! several policy files of one network — a run's snapshots over its last stretch
//! (`run.snapshot_every`), as stochastic weight averaging does.
//!
//! Why: PPO's last updates move the weights by noisy steps around where the policy
//! settles; the mean of the weights over a stretch of them averages that noise out, and
//! costs nothing during training. Whether it helps a given preset is a measurement
//! (`docs/results/`), not an assumption: the files are averaged only when asked.

use crate::artifact::names::{snapshot_name, POLICY, SNAPSHOTS};
use crate::artifact::{Container, FileHeader, PolicyFile};
use crate::device::default_device;
use crate::error::TrainError;
use crate::network::{for_network, ActorCritic, Encoder, NetworkJob, Recurrent};
use crate::tensor::{parameters, with_parameters};
use std::path::{Path, PathBuf};

/// The policy files of `run` (one seed's run directory) that cover the last `fraction` of
/// its updates: every snapshot taken after update (1 − `fraction`)·U, U the update of the
/// run's final `policy.ykp`, and that final policy itself — in the order of the run.
///
/// A run without snapshots, a fraction outside (0, 1] or a stretch with no snapshot in it
/// is an error that says so, so that an "average" of one file is never made by mistake.
pub fn last_stretch(run: &Path, fraction: f64) -> Result<Vec<PathBuf>, TrainError> {
    let mismatch = |message: String| TrainError::Mismatch {
        path: run.display().to_string(),
        message,
    };
    if !(fraction > 0.0 && fraction <= 1.0) {
        return Err(mismatch(format!(
            "the stretch to average must be a share of the run in (0, 1], not {fraction}"
        )));
    }
    let final_policy = run.join(POLICY);
    let last = PolicyFile::open(&final_policy)?.header.update;
    let first = ((1.0 - fraction) * last as f64).floor() as u64;
    let snapshots = run.join(SNAPSHOTS);
    let names = std::fs::read_dir(&snapshots).map_err(|e| {
        mismatch(format!(
            "no snapshots to average ({}: {e}); train with run.snapshot_every",
            snapshots.display()
        ))
    })?;
    let mut updates = Vec::new();
    for entry in names {
        let name = entry
            .map_err(|e| mismatch(format!("{}: {e}", snapshots.display())))?
            .file_name();
        let update = name.to_str().and_then(|n| {
            n.strip_prefix("policy-")?
                .strip_suffix(".ykp")?
                .parse()
                .ok()
        });
        if let Some(u) = update.filter(|&u| u > first && u < last) {
            updates.push(u);
        }
    }
    if updates.is_empty() {
        return Err(mismatch(format!(
            "no snapshot after update {first} of {last} in {}: nothing to average with the \
             final policy",
            snapshots.display()
        )));
    }
    updates.sort_unstable();
    let mut files: Vec<PathBuf> = updates
        .into_iter()
        .map(|u| snapshots.join(snapshot_name(u)))
        .collect();
    files.push(final_policy);
    Ok(files)
}

/// The policy whose parameters are the means, element by element, of those of `files`
/// (policy files, checkpoints or run directories, as `yokai eval` takes them), as a
/// policy file's content. Every file must hold the same network for the same game; the
/// header is the last file's, with `averaged` listing every file's update.
pub fn average_policies(files: &[PathBuf]) -> Result<Container, TrainError> {
    let Some(last_path) = files.last() else {
        return Err(TrainError::Mismatch {
            path: "(no files)".into(),
            message: "averaging needs at least one policy file".into(),
        });
    };
    let opened: Vec<PolicyFile> = files
        .iter()
        .map(|p| PolicyFile::open(p))
        .collect::<Result<_, _>>()?;
    let last = opened.last().expect("as many as the paths");
    for file in &opened {
        let differs = if file.config.network != last.config.network {
            Some("network")
        } else if file.game != last.game {
            Some("game")
        } else {
            None
        };
        if let Some(what) = differs {
            return Err(TrainError::Mismatch {
                path: file.path.display().to_string(),
                message: format!(
                    "its {what} differs from that of {}: only policies of one network for \
                     one game can be averaged",
                    last_path.display()
                ),
            });
        }
    }
    let model = for_network(&last.config.network, Average { files: &opened })?;
    let header = FileHeader {
        kind: "policy".into(),
        averaged: opened.iter().map(|f| f.header.update).collect(),
        ..last.header.clone()
    };
    Ok(Container {
        header: serde_json::to_string_pretty(&header).expect("json"),
        sections: vec![("model".into(), model)],
    })
}

/// Averaging as a [`NetworkJob`]: load every file into the network type its config names,
/// sum its parameters ([`parameters`], in module order) in f64, and write the means into
/// the last network ([`with_parameters`]).
struct Average<'a> {
    files: &'a [PolicyFile],
}

impl NetworkJob for Average<'_> {
    type Output = Result<Vec<u8>, TrainError>;
    fn run<E: Encoder + 'static, M: Recurrent + 'static>(self) -> Self::Output {
        let device = default_device();
        let mut sums: Vec<f64> = Vec::new();
        let mut last = None;
        for file in self.files {
            let net = ActorCritic::<E, M>::new(&file.config, &file.game, 0, &device);
            let net = file.load_into(net)?;
            let values = parameters(&net);
            sums.resize(values.len(), 0.0);
            for (s, v) in sums.iter_mut().zip(values) {
                *s += v as f64;
            }
            last = Some(net);
        }
        let n = self.files.len() as f64;
        let means: Vec<f32> = sums.iter().map(|s| (s / n) as f32).collect();
        let model = with_parameters(last.expect("at least one file"), &means, &device);
        Ok(crate::artifact::record_bytes(model))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TrainConfig;
    use crate::policy::TrainedPolicy;
    use crate::{MlpEncoder, Trainer};

    /// A policy file of a tiny network with `hidden` units, weights drawn from `seed`, its
    /// header saying update `update`, at `path`.
    fn policy_file(path: &Path, hidden: usize, seed: u64, update: u64) {
        let c = TrainConfig::tiny_for_tests(hidden);
        let mut file = Trainer::<MlpEncoder>::new(c, seed).unwrap().policy();
        let mut header: FileHeader = serde_json::from_str(&file.header).unwrap();
        header.update = update;
        file.header = serde_json::to_string(&header).unwrap();
        file.write_atomic(path).unwrap();
    }

    #[test]
    fn every_parameter_is_the_mean_of_the_files() {
        let dir = tempfile::tempdir().unwrap();
        let files: Vec<PathBuf> = (0..3u64)
            .map(|seed| {
                let path = dir.path().join(format!("p{seed}.ykp"));
                policy_file(&path, 8, seed, 10 * (seed + 1));
                path
            })
            .collect();
        let out = dir.path().join("mean.ykp");
        average_policies(&files)
            .unwrap()
            .write_atomic(&out)
            .unwrap();
        let each: Vec<Vec<f32>> = files
            .iter()
            .map(|f| TrainedPolicy::load(f).unwrap().parameters())
            .collect();
        assert_ne!(each[0], each[1], "the seeds must give different weights");
        let mean = TrainedPolicy::load(&out).unwrap();
        let got = mean.parameters();
        assert_eq!(got.len(), each[0].len());
        for (i, g) in got.iter().enumerate() {
            let want = ((each[0][i] as f64 + each[1][i] as f64 + each[2][i] as f64) / 3.0) as f32;
            assert_eq!(*g, want, "parameter {i}");
        }
        // The header is the last file's, with every file's update listed.
        assert_eq!(mean.header().update, 30);
        assert_eq!(mean.header().averaged, vec![10, 20, 30]);
    }

    #[test]
    fn a_different_network_is_refused_with_its_file_named() {
        let dir = tempfile::tempdir().unwrap();
        let (a, wide, b) = (
            dir.path().join("a.ykp"),
            dir.path().join("wide.ykp"),
            dir.path().join("b.ykp"),
        );
        policy_file(&a, 8, 0, 1);
        policy_file(&wide, 16, 0, 2);
        policy_file(&b, 8, 1, 3);
        let err = average_policies(&[a, wide, b]).unwrap_err().to_string();
        assert!(
            err.contains("wide.ykp") && err.contains("network differs"),
            "{err}"
        );
        assert!(average_policies(&[]).is_err());
    }

    #[test]
    fn the_last_stretch_is_the_snapshots_after_its_start_and_the_final_policy() {
        let dir = tempfile::tempdir().unwrap();
        let run = dir.path().join("run");
        let snaps = run.join(SNAPSHOTS);
        std::fs::create_dir_all(&snaps).unwrap();
        policy_file(&run.join(POLICY), 8, 0, 100);
        for u in [25u64, 50, 75, 100] {
            policy_file(&snaps.join(snapshot_name(u)), 8, u, u);
        }
        std::fs::write(snaps.join("notes.txt"), "not a snapshot").unwrap();
        let names = |fraction: f64| -> Vec<String> {
            last_stretch(&run, fraction)
                .unwrap()
                .iter()
                .map(|p| p.strip_prefix(&run).unwrap().display().to_string())
                .collect()
        };
        // The snapshot at the final update is the final policy: it counts once.
        assert_eq!(names(0.5), ["snapshots/policy-000075.ykp", "policy.ykp"]);
        assert_eq!(
            names(1.0),
            [
                "snapshots/policy-000025.ykp",
                "snapshots/policy-000050.ykp",
                "snapshots/policy-000075.ykp",
                "policy.ykp"
            ]
        );
        let err = last_stretch(&run, 0.2).unwrap_err().to_string();
        assert!(err.contains("no snapshot after update 80 of 100"), "{err}");
        assert!(last_stretch(&run, 0.0)
            .unwrap_err()
            .to_string()
            .contains("(0, 1]"));
        assert!(last_stretch(&run, 1.5).is_err());
        let bare = dir.path().join("bare");
        std::fs::create_dir_all(&bare).unwrap();
        policy_file(&bare.join(POLICY), 8, 0, 100);
        let err = last_stretch(&bare, 0.5).unwrap_err().to_string();
        assert!(err.contains("run.snapshot_every"), "{err}");
    }
}
