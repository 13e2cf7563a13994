//! `yokai probe-end`: where trained policies could END, what they did against what their
//! seat knew first-hand (the study lives in `yokai_train::probe::ending`).

use anyhow::{bail, Context};
use std::fmt::Write as _;
use std::path::PathBuf;
use yokai_train::probe::ending::{study, EndSummary};
use yokai_train::{EndRule, PlayRule, PolicySource};

#[derive(clap::Args)]
pub struct Args {
    /// Trained policies: pretrained agents (`pretrained:obl-cpu/0`), policy files,
    /// checkpoints, run directories, or a method directory of `seed-N` runs (each seed
    /// studied on its own). Each plays self-play.
    #[arg(required = true)]
    policies: Vec<String>,
    /// Self-play games per policy.
    #[arg(short, long, default_value_t = 2_000)]
    games: usize,
    /// Seed of the deals and of the draws.
    #[arg(short, long, default_value_t = 0)]
    seed: u64,
    /// How the policies choose END, as in `yokai eval`: `file`, `draw`, or a probability.
    #[arg(long, default_value = "file")]
    end: EndRule,
    /// Temperature of the other moves, as in `yokai eval` (default: each file's).
    #[arg(long, value_name = "T")]
    temperature: Option<f64>,
    /// Also write probe-end.md and probe-end.json here.
    #[arg(short, long)]
    out: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.games == 0 {
        bail!("--games must be at least 1");
    }
    let rule = PlayRule {
        end: args.end,
        temperature: args.temperature,
    };
    let mut studied = Vec::new();
    for name in crate::eval::expand(&args.policies)? {
        let mut source = PolicySource::parse(&name)?;
        source.set_play_rule(rule, true)?;
        let label = source.name();
        let Some(policy) = source.trained() else {
            bail!("`{name}` is a built-in bot: `yokai probe-end` reads a trained network's P(END)");
        };
        if policy.config().network.colours != yokai_train::ColourNames::Dealt {
            bail!(
                "{name}: its network reads its own colour names (network.colours = \"{}\"), \
                 which `yokai probe-end` does not support yet",
                policy.config().network.colours
            );
        }
        eprintln!("probing END of {label}: {} self-play games", args.games);
        studied.push((label, study(policy, args.games, args.seed)));
    }
    let text = report(&studied);
    print!("{text}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let write = |name: &str, body: &str| {
            let path = dir.join(name);
            std::fs::write(&path, body).with_context(|| format!("cannot write {}", path.display()))
        };
        write("probe-end.md", &text)?;
        let json: Vec<_> = studied
            .iter()
            .map(|(policy, s)| serde_json::json!({ "policy": policy, "summary": s }))
            .collect();
        write(
            "probe-end.json",
            &serde_json::to_string_pretty(&json).expect("json values serialise"),
        )?;
        eprintln!("wrote {}", dir.display());
    }
    Ok(())
}

/// The report: per policy, its ENDs, then its END chances by first-hand P(clustered).
fn report(studied: &[(String, EndSummary)]) -> String {
    let pct = |x: f64| format!("{:.1}", 100.0 * x);
    let mut t = String::from(
        "# Where trained policies END, against what the seat knows first-hand\n\n\
         An END chance is a state where the acting seat may END. Its first-hand outlook \
         averages over the colourings that agree with every card the seat observed itself \
         (and the colour counts): OBL level 1's belief, and a lower bound of what a seat \
         with conventions knows. P(clustered) is the outlook's share of clustered boards, \
         E[R] the reward END would pay on average over it.\n\n\
         | policy | games | ENDed % | ENDs: first-hand P(clustered) | ENDs: first-hand E[R] | ENDs: clustered % | games with a sure win % |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for (policy, s) in studied {
        let ends = |x: f64| {
            if s.games_ended > 0.0 {
                format!("{x:.3}")
            } else {
                "–".into()
            }
        };
        let _ = writeln!(
            t,
            "| {policy} | {} | {} | {} | {} | {} | {} |",
            s.games,
            pct(s.games_ended),
            ends(s.ends_first_hand_win),
            ends(s.ends_first_hand_reward),
            if s.games_ended > 0.0 {
                pct(s.ends_won)
            } else {
                "–".into()
            },
            pct(s.games_with_sure_win),
        );
    }
    for (policy, s) in studied {
        let _ = write!(
            t,
            "\n## {policy}\n\n{} END chances{}\n\n\
             | first-hand P(clustered) | chances % | mean P(END) | ENDed % | mean P(clustered) | E[R] of END | clustered % |\n\
             |---|---|---|---|---|---|---|\n",
            s.chances,
            if s.exact {
                ""
            } else {
                " (outlooks sampled, not exact)"
            },
        );
        for r in &s.rows {
            if r.chances == 0 {
                let _ = writeln!(t, "| {} | 0.0 | – | – | – | – | – |", r.bin);
                continue;
            }
            let _ = writeln!(
                t,
                "| {} | {} | {:.3} | {} | {:.3} | {:+.2} | {} |",
                r.bin,
                pct(r.share),
                r.p_end,
                pct(r.ended),
                r.first_hand_win,
                r.first_hand_reward,
                pct(r.won),
            );
        }
    }
    t
}
