//! Golden playthroughs: one game per preset config, written again and compared with the
//! committed file line by line. A rules or encoding change fails here at the first step it
//! touches; if the change is intended, write the files again with
//! `YOKAI_BLESS=1 cargo test -p yokai-engine --test playthroughs` (or
//! `yokai playthrough --write crates/yokai-engine/tests/playthroughs`) and commit the diff.

use std::path::PathBuf;
use yokai_engine::{golden_set, playthrough, Chooser, Config};

#[test]
fn every_preset_plays_through_as_its_golden_file_says() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/playthroughs");
    let bless = std::env::var_os("YOKAI_BLESS").is_some();
    let set = golden_set();
    assert_eq!(set.len(), 24, "12 preset configs, two games each");
    for game in set {
        let text = playthrough(game.config, game.seed, game.chooser);
        let path = dir.join(&game.file_name);
        if bless {
            std::fs::write(&path, &text).unwrap();
            continue;
        }
        let golden = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (YOKAI_BLESS=1 writes it)", path.display()));
        if let Some((i, (want, got))) = golden
            .lines()
            .zip(text.lines())
            .enumerate()
            .find(|(_, (a, b))| a != b)
        {
            panic!(
                "{} line {}: the file says\n  {want}\nthe engine now writes\n  {got}",
                path.display(),
                i + 1
            );
        }
        assert_eq!(
            golden,
            text,
            "{}: same lines, different length",
            path.display()
        );
    }
}

#[test]
fn a_playthrough_is_a_function_of_config_and_seed() {
    let config = Config::from_name("9c-3p-imperfect").unwrap();
    let random = |seed| playthrough(config, seed, Chooser::Random);
    assert_eq!(random(5), random(5));
    assert_ne!(random(5), random(6));
    let text = playthrough(config, 5, Chooser::NeverEnd);
    assert!(!text.contains("(end)"), "the never-END player never ends");
    assert!(text.contains("early_end: false"));
    // Every step lists the legal actions, a digest line per seat and the action taken.
    let steps = text.matches("\n## step ").count();
    assert!(steps >= 1);
    assert_eq!(text.matches("\nlegal for seat ").count(), steps);
    assert_eq!(text.matches(" -> reward ").count(), steps);
    assert_eq!(text.matches(" image-hwc-full ").count(), 3 * (steps + 1));
}
