//! Fuzz tests of every parser of outside input the engine has: game config TOML, replay
//! files (JSONL), episode records (JSON) and action names. Arbitrary bytes and mutations of
//! valid inputs must never panic, and a mutated input that is accepted must mean what it
//! says (an accepted config deals a playable game; an accepted replay writes back as the
//! same replay; an accepted action name prints back as itself). The case count is small in
//! CI; `YOKAI_FUZZ_CASES=200000 cargo test --release -p yokai-engine --test fuzz` runs a
//! long session (docs/reliability.md).

use proptest::prelude::*;
use yokai_engine::{Action, Config, EpisodeRecord, Game, RecordedGame, Replay};

fn cases() -> u32 {
    std::env::var("YOKAI_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(512)
}

/// A valid replay file of a random game, to mutate.
fn valid_replay(seed: u64) -> String {
    let config = Config::from_name("9c-2p-perfect").unwrap();
    let mut game = RecordedGame::new(config, seed);
    let mut k = seed;
    while !game.game().is_over() {
        let legal = game.game().legal_actions(game.game().current_seat());
        k = k
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        game.apply(legal[(k >> 33) as usize % legal.len()]).unwrap();
    }
    Replay::from_record(game.record(), Some(seed), vec!["random".into(); 2])
        .unwrap()
        .to_jsonl()
}

const VALID_CONFIG: &str = "cards = 12\ncolours = 3\ngrid = 8\nplayers = 5\nhints = [2, 3]\n";

/// Replace, insert or delete bytes of `text` at positions and values drawn by proptest.
fn mutate(text: &str, edits: &[(usize, u8, u8)]) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    for &(at, kind, value) in edits {
        if bytes.is_empty() {
            bytes.push(value);
            continue;
        }
        let at = at % bytes.len();
        match kind % 3 {
            0 => bytes[at] = value,
            1 => bytes.insert(at, value),
            _ => {
                bytes.remove(at);
            }
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn game_config_toml_never_panics(text in "\\PC{0,200}", edits in prop::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 0..8)) {
        let _ = Config::from_toml_str(&text, "fuzz");
        let mutated = String::from_utf8_lossy(&mutate(VALID_CONFIG, &edits)).into_owned();
        if let Ok(config) = Config::from_toml_str(&mutated, "fuzz") {
            // An accepted config is playable: a game deals and has a legal action.
            let game = Game::new(config, 1);
            prop_assert!(!game.legal_actions(game.current_seat()).is_empty());
        }
        let _ = Config::from_name(&text);
    }

    #[test]
    fn replay_files_never_panic_and_accepted_ones_replay(seed in 0u64..64, edits in prop::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..6)) {
        let text = valid_replay(seed);
        prop_assert!(Replay::from_jsonl(&text).is_ok());
        let mutated = String::from_utf8_lossy(&mutate(&text, &edits)).into_owned();
        if let Ok(replay) = Replay::from_jsonl(&mutated) {
            // (Reading already replays the record under the rules.) What is accepted is
            // written back as a file that reads as the same replay.
            prop_assert_eq!(Replay::from_jsonl(&replay.to_jsonl()).unwrap(), replay);
        }
    }

    #[test]
    fn episode_records_and_action_names_never_panic(text in "\\PC{0,120}", index in any::<usize>()) {
        let _ = EpisodeRecord::from_json(&text);
        if let Ok(action) = text.parse::<Action>() {
            prop_assert_eq!(action.to_string().parse::<Action>().unwrap(), action);
        }
        let config = Config::from_name("16c-4p-imperfect").unwrap();
        if let Ok(action) = config.decode(index) {
            prop_assert_eq!(config.encode(action), index);
            prop_assert_eq!(action.to_string().parse::<Action>().unwrap(), action);
        }
    }
}
