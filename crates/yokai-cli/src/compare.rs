//! `yokai compare`: several evaluation outputs in one table, beside the paper's rows.

use crate::paper::PaperTable;
use crate::summary::{
    paper_rows, select_entropy, table_row, EvalSummary, GroupSummary, TABLE_HEAD,
};
use anyhow::{anyhow, Context};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Evaluation output directories (`yokai eval --out DIR`, or `runs/NAME/eval` of
    /// `yokai train`), each holding a summary.json.
    #[arg(required = true)]
    evaluations: Vec<PathBuf>,
    /// Write the table to this Markdown file as well.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// The paper's table whose rows to print beside ours, for each game: 2 (the main
    /// table), 3 (OP's entropy sweep), 4 (OP's symmetry groups), 5 (encoders), 6
    /// (imperfect memory).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=6))]
    paper_table: u8,
    /// HE's α selection (the paper's rule for more than 2 players): for each game, of the
    /// methods trained with different entropy coefficients (e.g. `sweeps/he-alpha.toml`),
    /// name the lowest α whose SP and XP returns differ by at most TOL (default 0.1).
    #[arg(long, value_name = "TOL", num_args = 0..=1, default_missing_value = "0.1")]
    select_entropy: Option<f64>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut summaries = Vec::new();
    for dir in &args.evaluations {
        summaries.push(read_summary(dir)?);
    }
    let paper = crate::paper::table(args.paper_table)
        .ok_or_else(|| anyhow!("the paper has no Table {}", args.paper_table))?;
    let mut out = table(&summaries, paper);
    if let Some(tolerance) = args.select_entropy {
        if tolerance.is_nan() || tolerance < 0.0 {
            return Err(anyhow!(
                "--select-entropy takes a tolerance ≥ 0, not {tolerance}"
            ));
        }
        for game in games(&summaries) {
            let groups: Vec<&GroupSummary> = summaries
                .iter()
                .filter(|s| s.game == game)
                .flat_map(|s| &s.groups)
                .collect();
            let selection = select_entropy(&groups, tolerance);
            out += &format!("## {game}: HE's α selection\n\n{}\n", selection.report());
        }
    }
    print!("{out}");
    if let Some(path) = args.out {
        std::fs::write(&path, &out).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

/// An evaluation's `summary.json`, with at least one trained method in it.
fn read_summary(dir: &std::path::Path) -> anyhow::Result<EvalSummary> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        anyhow!(
            "cannot read {}: {e} (is {} the --out of `yokai eval` with trained policies?)",
            path.display(),
            dir.display()
        )
    })?;
    let summary: EvalSummary = serde_json::from_str(&text)
        .with_context(|| format!("{} is not an evaluation summary", path.display()))?;
    if summary.groups.is_empty() {
        return Err(anyhow!(
            "{} has no trained methods to compare (only built-in policies were evaluated)",
            dir.display()
        ));
    }
    Ok(summary)
}

/// The games of the evaluations, each once, in the order they first appear.
fn games(summaries: &[EvalSummary]) -> Vec<&str> {
    let mut games: Vec<&str> = Vec::new();
    for s in summaries {
        if !games.contains(&s.game.as_str()) {
            games.push(&s.game);
        }
    }
    games
}

/// One section per game (in the order the evaluations first name it): our methods' rows,
/// then the paper's rows of `paper` for that game.
fn table(summaries: &[EvalSummary], paper: &PaperTable) -> String {
    let mut out = format!(
        "Beside the paper's Table {}: {}.\n\n",
        paper.number, paper.title
    );
    for game in games(summaries) {
        out += &format!("## {game}\n\n{TABLE_HEAD}");
        for s in summaries.iter().filter(|s| s.game == game) {
            for g in &s.groups {
                out += &table_row(g);
            }
        }
        out += &paper_rows(paper, game);
        out += "\n";
    }
    out
}
