//! The belief convention played with the true colouring as every seat's posterior: an upper
//! bound that says how much of the gap to a perfect score is information and how much is
//! move quality (docs/bots.md). Analysis only: a real seat never sees these colours.
//!
//! `cargo run --release -p yokai-agents --example full_information -- [CONFIG] [GAMES]`

use yokai_agents::belief::colouring::Colouring;
use yokai_agents::belief::convention::{decide, BeliefParams};
use yokai_engine::{Config, Game, MetricsAccumulator};

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "9c-2p-perfect".into());
    let games: u64 = match args.next() {
        Some(g) => g.parse().map_err(|e| format!("GAMES `{g}`: {e}"))?,
        None => 2000,
    };
    let config = Config::resolve(&name).map_err(|e| e.to_string())?;
    let params = BeliefParams::default();
    let mut metrics = MetricsAccumulator::default();
    for seed in 0..games {
        let mut game = Game::new(config, seed);
        let truth = Colouring::from_colours(&game.deal().card_colours);
        loop {
            let seat = game.current_seat();
            let view = game.view(seat);
            let action = decide(&view.public(), seat, &[truth], &[truth], &params);
            if game.apply(action).map_err(|e| e.to_string())?.done {
                metrics.add(&game.outcome().expect("the game is over"));
                break;
            }
        }
    }
    let m = metrics.metrics().ok_or("no games played (GAMES is 0)")?;
    println!(
        "{config}, {games} games, full information: R {:.2}, win {:.1} %, LEN {:.1}",
        m.reward,
        100.0 * m.win_rate,
        m.length
    );
    Ok(())
}
