//! Diagnostic: train a config, then measure how often the policy's OBSERVE actions look at a
//! card its seat has never seen (what the shaping reward pays for), against random play.
use yokai_agents::{play_episode, Policy, RandomPolicy};
use yokai_engine::{Action, Config, RecordedGame, Seat};
use yokai_train::{MlpEncoder, TrainConfig, Trainer};

fn new_observation_share(config: Config, seats: &mut [Box<dyn Policy>]) -> f64 {
    let (mut new, mut all) = (0u64, 0u64);
    for g in 0..300u64 {
        let episode = play_episode(config, g, g, seats).unwrap();
        let mut game = RecordedGame::new(config, g);
        for &a in &episode.record.actions {
            let action = config.decode(a as usize).unwrap();
            let seat = game.game().current_seat();
            if let Action::Observe(card) = action {
                all += 1;
                new += !game.game().ever_observed(seat).contains(card) as u64;
            }
            game.apply(action).unwrap();
        }
    }
    new as f64 / all as f64
}

fn main() {
    let path = std::env::args().nth(1).expect("config path");
    let updates: u64 = std::env::args().nth(2).map_or(100, |s| s.parse().unwrap());
    let config = TrainConfig::from_file(std::path::Path::new(&path)).unwrap();
    let game = config.game_config().unwrap();
    let mut random: Vec<Box<dyn Policy>> = (0..2)
        .map(|s| Box::new(RandomPolicy::new(s)) as Box<dyn Policy>)
        .collect();
    println!("random: {:.3}", new_observation_share(game, &mut random));
    let mut t = Trainer::<MlpEncoder>::new(config, 0).unwrap();
    let dir = std::env::temp_dir().join("probe-observe");
    std::fs::create_dir_all(&dir).unwrap();
    for u in 0..updates {
        t.update().unwrap();
        if (u + 1) % 25 == 0 {
            let path = dir.join("p.ykp");
            t.policy().write_atomic(&path).unwrap();
            let p = yokai_train::TrainedPolicy::load(&path).unwrap();
            let mut seats: Vec<Box<dyn Policy>> = (0..2).map(|s| p.build(s)).collect();
            let _ = Seat(0);
            println!(
                "update {}: {:.3}",
                u + 1,
                new_observation_share(game, &mut seats)
            );
        }
    }
}
