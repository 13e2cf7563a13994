//! Self-play metrics of a built-in policy: `cargo run --release -p yokai-agents --example
//! selfplay -- belief 9c-2p-perfect 2000`.

use yokai_agents::eval::{play_group, PolicyFactory};
use yokai_agents::PolicySpec;
use yokai_engine::Config;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let spec: PolicySpec = args
        .get(1)
        .map_or("belief", |s| s)
        .parse()
        .expect("policy name");
    let config = Config::resolve(args.get(2).map_or("9c-2p-perfect", |s| s)).expect("config");
    let games: u64 = args.get(3).map_or(Ok(2000), |s| s.parse()).expect("games");
    let make = |seed: u64| spec.build(seed);
    let seats: Vec<&PolicyFactory> = (0..config.players())
        .map(|_| &make as &PolicyFactory)
        .collect();
    let start = std::time::Instant::now();
    let acc = play_group(config, &seats, games, 0, &|_| {}).expect("legal play");
    let m = acc.metrics().expect("games");
    println!(
        "{spec} on {config}: R {:.2} ± {:.2}, win {:.1}%, EE {:.1}%, SEE {:.1}%, LEN {:.1}, hints {:.2}/{:.2}  ({:.2} s)",
        m.reward, m.reward_se, 100.0 * m.win_rate, 100.0 * m.early_end, 100.0 * m.successful_early_end,
        m.length, m.correct_hints, m.wrong_hints, start.elapsed().as_secs_f64()
    );
}
