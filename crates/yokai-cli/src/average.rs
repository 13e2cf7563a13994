//! `yokai average`: one policy whose weights are the mean of several policy files' —
//! a run's snapshots over its last stretch (`--last`), or files named one by one.

use anyhow::{bail, Context};
use std::path::{Path, PathBuf};
use yokai_train::average::{average_policies, last_stretch};

#[derive(clap::Args)]
pub struct Args {
    /// With --last: runs trained with `run.snapshot_every` (a seed's run directory, or a
    /// method directory of `seed-N` runs, or a quoted glob as `yokai eval` takes them).
    /// Without: the policy files, checkpoints or run directories to average into one.
    #[arg(required = true)]
    paths: Vec<String>,
    /// Average each run's snapshots taken after (1 − F) of its updates together with its
    /// final policy, F in (0, 1]: 0.2 averages the last fifth of the run. Each run's average
    /// goes to OUT/<its directory's name>/policy.ykp, so OUT reads like a method directory
    /// in `yokai eval`.
    #[arg(long, value_name = "F")]
    last: Option<f64>,
    /// Where to write: a directory with --last, else the averaged policy file.
    #[arg(short, long)]
    out: PathBuf,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let Some(fraction) = args.last else {
        let files: Vec<PathBuf> = args.paths.iter().map(PathBuf::from).collect();
        return write_average(&files, &args.out);
    };
    let runs = crate::eval::expand(&args.paths)?;
    for run in &runs {
        let run = Path::new(run);
        let Some(name) = run.file_name() else {
            bail!("`{}` names no run directory", run.display());
        };
        let files = last_stretch(run, fraction)?;
        write_average(&files, &args.out.join(name).join("policy.ykp"))?;
    }
    Ok(())
}

/// Average `files` into the policy file `out` (its folder made if need be), and say what
/// was averaged.
fn write_average(files: &[PathBuf], out: &Path) -> anyhow::Result<()> {
    let averaged = average_policies(files)?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    averaged
        .write_atomic(out)
        .with_context(|| format!("writing {}", out.display()))?;
    let shown = |f: Option<&PathBuf>| f.map(|f| f.display().to_string()).unwrap_or_default();
    eprintln!(
        "wrote {}: the mean of {} policies ({} … {})",
        out.display(),
        files.len(),
        shown(files.first()),
        shown(files.last()),
    );
    Ok(())
}
