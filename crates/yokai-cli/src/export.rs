//! `yokai export`: a trained network's weights as a SafeTensors file, for PyTorch, NumPy or
//! JAX (`safetensors.numpy.load_file`); `yokai` itself keeps reading its own policy files.

use anyhow::Context;
use std::path::PathBuf;
use yokai_train::TrainedPolicy;

#[derive(clap::Args)]
pub struct Args {
    /// The trained policy: a policy file, checkpoint or run directory.
    policy: PathBuf,
    /// Where to write. Default: `policy.safetensors` beside the policy file (in the run
    /// directory).
    #[arg(short, long)]
    out: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let policy = TrainedPolicy::load(&args.policy)?;
    let out = args.out.unwrap_or_else(|| {
        policy
            .path()
            .with_file_name("policy")
            .with_extension("safetensors")
    });
    policy
        .write_safetensors(&out)
        .with_context(|| format!("exporting {}", args.policy.display()))?;
    eprintln!(
        "wrote {} ({} parameters; tensors named by their path in the network, metadata \
         yokai.train_config, yokai.game, yokai.encoding, yokai.observation_shape, \
         yokai.hidden_size)",
        out.display(),
        policy.parameters().len()
    );
    Ok(())
}
