//! `yokai compare`: several evaluation outputs in one table.

use crate::summary::{paper_rows, table_row, EvalSummary, TABLE_HEAD};
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
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut summaries = Vec::new();
    for dir in &args.evaluations {
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
        summaries.push(summary);
    }
    let mut games: Vec<&str> = summaries.iter().map(|s| s.game.as_str()).collect();
    games.dedup();
    let mut out = String::new();
    for game in &games {
        out += &format!("## {game}\n\n{TABLE_HEAD}");
        for s in summaries.iter().filter(|s| s.game == *game) {
            for g in &s.groups {
                out += &table_row(g);
            }
        }
        out += &paper_rows(game);
        out += "\n";
    }
    print!("{out}");
    if let Some(path) = args.out {
        std::fs::write(&path, &out).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
