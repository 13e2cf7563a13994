//! Files written before a rename still load. Until 2026-11-25 the network's memory was the
//! field `gru` (also when it held a Transformer-XL), so old policy files and checkpoints
//! name its tensors `gru.…`; the field is now `memory`. The files under
//! `tests/golden/memory-named-gru/` were written then (a tiny pointer-head network after 20
//! updates); `games.json` holds the games the policy played then, and the checkpoint's
//! parameters. Bless with `YOKAI_BLESS=1 cargo test --release -p yokai-train --test
//! old_files` only when the games change on purpose.

use std::path::{Path, PathBuf};
use yokai_agents::{play_episode, Policy};
use yokai_train::{MlpEncoder, TrainedPolicy, Trainer};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/memory-named-gru")
}

#[test]
fn a_policy_file_and_a_checkpoint_with_the_old_memory_name_load_and_play_as_before() {
    let policy = TrainedPolicy::load(&dir().join("policy.ykp")).unwrap();
    let game = *policy.game();
    let games: Vec<yokai_engine::EpisodeRecord> = (0..3)
        .map(|g| {
            let mut seats: Vec<Box<dyn Policy>> = (0..2).map(|s| policy.build(g * 2 + s)).collect();
            play_episode(game, g, g, &mut seats).unwrap().record
        })
        .collect();
    let trainer = Trainer::<MlpEncoder>::resume(&dir().join("checkpoint.ykc")).unwrap();
    assert_eq!(trainer.update_count(), 20);
    let parameters = trainer.parameters();
    assert_eq!(
        parameters,
        policy.parameters(),
        "the run's last weights, twice"
    );
    let got = serde_json::json!({
        "games": games,
        "parameters": parameters.len(),
        "parameter_sum": parameters.iter().map(|&x| x as f64).sum::<f64>(),
    });
    // Compared as text: serde_json's default parser does not round-trip every float.
    let got = serde_json::to_string_pretty(&got).unwrap() + "\n";
    let path = dir().join("games.json");
    if std::env::var_os("YOKAI_BLESS").is_some() {
        std::fs::write(&path, &got).unwrap();
    }
    let want = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        got == want,
        "the old files play otherwise than they did: {}",
        path.display()
    );
}
