//! Every pretrained agent built in plays at the self-play score `pretrained.toml` documents
//! for it: 500 fresh games of each seed with itself (other deals than the documented
//! evaluation's), whose mean R must lie within 3 standard errors of the documented one.

use yokai_agents::eval::{play_group, PolicyFactory};
use yokai_train::pretrained::{entries, names, PREFIX};
use yokai_train::PolicySource;

const GAMES: u64 = 500;

#[test]
fn every_pretrained_agent_plays_at_its_documented_self_play_score() {
    let mut checked = 0;
    for entry in entries() {
        for (k, &seed) in entry.seeds.iter().enumerate() {
            let name = format!("{PREFIX}{}/{seed}", entry.preset);
            let source = PolicySource::parse(&name).unwrap();
            let config = *source.trained().expect("a trained policy").game();
            let make = |s: u64| source.build(s);
            let seats: Vec<&PolicyFactory<'_>> = vec![&make; config.players()];
            let m = play_group(config, &seats, GAMES, 0x9e37_79b9, &|_| {})
                .unwrap()
                .metrics()
                .expect("games were played");
            assert_eq!(m.games, GAMES);
            let (documented, doc_se) = (entry.sp_r[k], entry.sp_se[k]);
            let se = (m.reward_se.powi(2) + doc_se.powi(2)).sqrt();
            assert!(
                (m.reward - documented).abs() <= 3.0 * se,
                "{name}: R {:.3} ± {:.3} over {GAMES} games, documented {documented} ± {doc_se}",
                m.reward,
                m.reward_se
            );
            // Every agent shipped plays far above random play (R −4.0).
            assert!(m.reward > 1.0, "{name}: {m:?}");
            checked += 1;
        }
    }
    // Every agent built in, not a hand-kept count that goes stale as agents are added.
    assert_eq!(
        checked,
        names().len(),
        "agents checked against agents built in"
    );
}
