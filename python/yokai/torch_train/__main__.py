"""Command line of ``python -m yokai.torch_train`` (see the package's docs)."""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import torch

from .ppo import Trainer
from .weights import save

CHECKPOINT, POLICY, METRICS = "checkpoint.pt", "policy.safetensors", "metrics.jsonl"


def parse(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        prog="python -m yokai.torch_train",
        description="Train a `yokai train` preset in PyTorch: same configs, same algorithm and levers, "
        "and a policy file every yokai front end plays (yokai eval, serve, play, yokai.Agent).",
    )
    p.add_argument("config", help="a preset of configs/ (quick, cpu-fast, cpu, cpu-op, ...) or a TOML file")
    p.add_argument("--out", required=True, help="run directory (created; with --resume, continued)")
    p.add_argument("--seed", type=int, default=0, help="run seed: weights, deals, draws (default 0)")
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                   help="override a config field, as `yokai train --set` (repeatable)")
    p.add_argument("--max-updates", type=int, default=0,
                   help="stop after so many updates in this call (0: run to ppo.total_steps)")
    p.add_argument("--device", default="cpu", help="torch device: cpu (default), cuda, cuda:1, or auto")
    p.add_argument("--threads", type=int, default=0, help="torch CPU threads (default: torch's choice)")
    p.add_argument("--resume", action="store_true", help="continue the run in --out from its checkpoint")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    return p.parse_args(argv)


def main(argv=None) -> int:
    args = parse(argv)
    if args.threads > 0:
        torch.set_num_threads(args.threads)
    device = ("cuda" if torch.cuda.is_available() else "cpu") if args.device == "auto" else args.device
    os.makedirs(args.out, exist_ok=True)
    checkpoint = os.path.join(args.out, CHECKPOINT)
    if os.path.exists(checkpoint) and not args.resume:
        print(f"error: {args.out} already holds a run; pass --resume to continue it", file=sys.stderr)
        return 2
    try:
        trainer = Trainer(args.config, seed=args.seed, overrides=args.set, device=device)
    except ValueError as e:  # a bad config, override or unsupported field: say which
        print(f"error: {e}", file=sys.stderr)
        return 2
    if args.resume and os.path.exists(checkpoint):
        saved = torch.load(checkpoint, map_location=device)
        trainer.model.load_state_dict(saved["model"])
        trainer.optim.load_state_dict(saved["optim"])
        trainer.update = saved["update"]
    with open(os.path.join(args.out, "config.toml"), "w") as f:
        f.write(trainer.env.train_config)
    every = trainer.config["run"]["checkpoint_every"]
    done_here, start = 0, time.perf_counter()
    with open(os.path.join(args.out, METRICS), "a") as log:
        while trainer.update < trainer.updates and (args.max_updates == 0 or done_here < args.max_updates):
            stats = trainer.step()
            done_here += 1
            log.write(json.dumps(stats) + "\n")
            log.flush()
            last = trainer.update == trainer.updates or done_here == args.max_updates
            if last or (every > 0 and trainer.update % every == 0):
                write_run(trainer, args.out)
            if not args.quiet and (last or trainer.update % 10 == 0):
                g = stats["games"] or {}
                print(f"update {trainer.update}/{trainer.updates}  steps {stats['env_steps']:,}  "
                      f"R {g.get('reward', float('nan')):.2f}  EE {g.get('early_end', float('nan')):.2f}  "
                      f"{stats['sps']:,.0f} steps/s  {time.perf_counter() - start:.0f} s", file=sys.stderr)
    return 0


def write_run(trainer: Trainer, out: str) -> None:
    """The policy file and the checkpoint, each replaced atomically."""
    save(trainer.model, os.path.join(out, POLICY), trainer.metadata())
    tmp = os.path.join(out, CHECKPOINT + ".tmp")
    torch.save({"model": trainer.model.state_dict(), "optim": trainer.optim.state_dict(), "update": trainer.update}, tmp)
    os.replace(tmp, os.path.join(out, CHECKPOINT))


if __name__ == "__main__":
    sys.exit(main())
