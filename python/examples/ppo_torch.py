"""Recurrent IPPO on Yōkai in PyTorch: one file, CleanRL style, GPU if present.

The starting point for researchers who train in PyTorch. It trains the paper's network
(4 × Conv2d(64, 3×3) → Linear 256 → GRU 256 → actor and critic heads) with shared
parameters across seats on `yokai.VecEnv`, as the Rust trainer (`yokai train`) does:

- every seat of every game is one row; the acting seat samples, the others take NOOP
  (their only legal action) but still step their GRU, so a seat's memory follows what its
  partners do;
- illegal logits are masked; the GRU state is zeroed where an episode starts;
- GAE over the team reward plus the shaping reward (annealed linearly to 0), no
  bootstrap across an episode end;
- minibatches are sets of whole rows, replayed from the state stored at the rollout's start
  (BPTT over the full rollout); clipped policy and value losses, entropy bonus, global
  gradient-norm clip, Adam with linear learning-rate annealing.

Run (defaults are the paper's IPPO hyper-parameters, docs/spec/training.md):

    pip install ./python torch
    python python/examples/ppo_torch.py --config 9c-2p-perfect --total-steps 10000000

The environment steps on the CPU (`--threads`, default all cores) and the network on
`--device` (default: cuda if available). `--log` writes one JSON line per update,
`--tensorboard DIR` TensorBoard event files (PyTorch's SummaryWriter), `--wandb-project NAME`
logs to Weights & Biases where `wandb` is installed.
`--checkpoint PATH` saves the network, optimiser and update count after every update;
`--resume` continues from it (with freshly dealt games), so a run longer than a job's time
limit goes on across jobs with `--max-updates` per job.
"""

from __future__ import annotations

import argparse
import json
import os
import time
import warnings
from dataclasses import dataclass

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

import yokai

# VecEnv returns read-only views of its buffers; every view is copied (to the device, or
# into the rollout storage) before the next step overwrites it, never written to.
warnings.filterwarnings("ignore", message="The given NumPy array is not writable")


@dataclass
class Args:
    config: str = "9c-2p-perfect"
    seed: int = 0
    num_envs: int = 1024
    rollout_steps: int = 128
    total_steps: int = 1_000_000_000
    lr: float = 3e-4
    anneal_lr: bool = True
    gamma: float = 0.99
    gae_lambda: float = 0.95
    epochs: int = 4
    minibatches: int = 4
    clip: float = 0.2
    value_clip: float = 0.2
    value_coef: float = 0.5
    entropy_coef: float = 0.05
    max_grad_norm: float = 0.5
    shaping: float = 1.0
    hidden: int = 256
    filters: int = 64
    device: str = "auto"
    bf16: bool = False  # autocast the network to bfloat16 on a GPU (TF32 is on regardless)
    threads: int = 0
    max_updates: int = 0  # stop this call after so many updates (0: run to total_steps)
    log: str = ""
    tensorboard: str = ""  # write TensorBoard event files into this directory (SummaryWriter)
    wandb_project: str = ""  # also log to Weights & Biases under this project (needs wandb)
    checkpoint: str = ""  # save network, optimiser and update count here after every update
    resume: bool = False  # continue from --checkpoint (new games are dealt)


def parse_args(argv=None) -> Args:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for name, default in Args().__dict__.items():
        flag = "--" + name.replace("_", "-")
        if isinstance(default, bool):
            parser.add_argument(flag, type=lambda s: s.lower() in ("1", "true", "yes"), default=default)
        else:
            parser.add_argument(flag, type=type(default), default=default)
    return Args(**vars(parser.parse_args(argv)))


def run_logger(args: Args):
    """A function that logs an update's numbers (x axis: env steps) to TensorBoard with
    PyTorch's `SummaryWriter` (`--tensorboard DIR`) and to W&B (`--wandb-project NAME`);
    it does nothing when neither is asked for."""
    sinks = []
    if args.tensorboard:
        from torch.utils.tensorboard import SummaryWriter  # needs the `tensorboard` package

        tb = SummaryWriter(args.tensorboard)

        def to_tensorboard(scalars, step):
            for tag, value in scalars.items():
                tb.add_scalar(tag, value, step)
            tb.flush()

        sinks.append(to_tensorboard)
    if args.wandb_project:
        try:
            import wandb
        except ImportError:
            raise SystemExit("--wandb-project needs Weights & Biases: pip install wandb") from None
        wandb.init(project=args.wandb_project, config=dict(args.__dict__))
        sinks.append(lambda scalars, step: wandb.log(scalars, step=step))

    def log(line: dict):
        group = {"games": "games", "reward": "games", "early_end": "games"}
        scalars = {
            f"{group.get(k, 'train')}/{k}": float(v)
            for k, v in line.items()
            if k not in ("update", "env_steps") and isinstance(v, (int, float))
        }
        for sink in sinks:
            sink(scalars, line["env_steps"])

    return log


def orthogonal(layer: nn.Module, gain: float = 2**0.5) -> nn.Module:
    nn.init.orthogonal_(layer.weight, gain)
    nn.init.zeros_(layer.bias)
    return layer


class ActorCritic(nn.Module):
    """The paper's CNN-GRU on the channels-first image `[F, g, g+1]`."""

    def __init__(self, obs_shape: list[int], n_actions: int, hidden: int, filters: int):
        super().__init__()
        f, h, w = obs_shape
        layers, c = [], f
        for _ in range(4):
            layers += [orthogonal(nn.Conv2d(c, filters, 3)), nn.ReLU()]
            c, h, w = filters, h - 2, w - 2
        self.conv = nn.Sequential(*layers, nn.Flatten())
        self.embed = orthogonal(nn.Linear(filters * h * w, hidden))
        self.gru = nn.GRUCell(hidden, hidden)
        self.actor = orthogonal(nn.Linear(hidden, n_actions), 0.01)
        self.critic = orthogonal(nn.Linear(hidden, 1), 1.0)

    def project(self, obs: torch.Tensor) -> torch.Tensor:
        """Observations `[B, F, g, g+1]` → GRU inputs `[B, H]` (no state: batch freely)."""
        return F.relu(self.embed(self.conv(obs)))

    def heads(self, h: torch.Tensor, mask: torch.Tensor):
        logits = self.actor(h).masked_fill(~mask, -1e9)
        return torch.log_softmax(logits, -1), self.critic(h).squeeze(-1)


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    device = torch.device(
        ("cuda" if torch.cuda.is_available() else "cpu") if args.device == "auto" else args.device
    )
    torch.manual_seed(args.seed)
    torch.backends.cuda.matmul.allow_tf32 = True
    torch.backends.cudnn.allow_tf32 = True
    torch.backends.cudnn.benchmark = True
    autocast = torch.autocast(device.type, dtype=torch.bfloat16, enabled=args.bf16 and device.type == "cuda")
    env = yokai.VecEnv(
        args.config,
        num_envs=args.num_envs,
        seed=args.seed,
        obs="image-chw",
        dtype="float32",
        threads=args.threads or None,
    )
    n, p, a_n, t_n = env.num_envs, env.num_players, env.num_actions, args.rollout_steps
    rows = n * p
    obs_shape = env.observation_shape
    net = ActorCritic(obs_shape, a_n, args.hidden, args.filters).to(device)
    optim = torch.optim.Adam(net.parameters(), lr=args.lr, eps=1e-5)
    updates = max(1, args.total_steps // (n * t_n))  # the whole run: annealing spans it
    first = 1
    if args.resume:
        if not args.checkpoint:
            raise SystemExit("--resume needs --checkpoint PATH")
        state = torch.load(args.checkpoint, map_location=device)
        net.load_state_dict(state["net"])
        optim.load_state_dict(state["optim"])
        first = state["update"] + 1
        # The games restart: deal a fresh stream, a function of (seed, update).
        env = yokai.VecEnv(args.config, num_envs=n, seed=yokai.episode_seed(args.seed, 0, first),
                           obs="image-chw", dtype="float32", threads=args.threads or None)
    last = updates if not args.max_updates else min(updates, first - 1 + args.max_updates)
    writer = run_logger(args)

    # Rollout storage, on the device: `[T, rows, ...]`.
    obs_buf = torch.zeros((t_n, rows, *obs_shape), device=device)
    mask_buf = torch.zeros((t_n, rows, a_n), dtype=torch.bool, device=device)
    act_buf = torch.zeros((t_n, rows), dtype=torch.long, device=device)
    logp_buf = torch.zeros((t_n, rows), device=device)
    val_buf = torch.zeros((t_n, rows), device=device)
    rew_buf = torch.zeros((t_n, rows), device=device)
    start_buf = torch.zeros((t_n, rows), device=device)  # 1 where an episode starts
    done_buf = torch.zeros((t_n, rows), device=device)

    out = env.reset()
    hidden = torch.zeros((rows, args.hidden), device=device)
    starts = torch.ones(rows, device=device)
    seat_ids = torch.arange(p, device=device).repeat(n)

    def forward(out, hidden, starts):
        """The network on the views in `out` (states zeroed where episodes start):
        observations, masks, the new states, log-probabilities and values."""
        obs = torch.from_numpy(out["obs"]).to(device, non_blocking=True).view(rows, *obs_shape)
        mask = torch.from_numpy(out["legal_mask"]).to(device).view(rows, a_n).bool()
        hidden = net.gru(net.project(obs), hidden * (1.0 - starts[:, None])).float()
        logp, value = net.heads(hidden, mask)
        return obs, mask, hidden, logp.float(), value.float()

    log, steps = [], (first - 1) * n * t_n
    for update in range(first, last + 1):
        t0 = time.perf_counter()
        frac = 1.0 - (update - 1) / updates
        if args.anneal_lr:
            optim.param_groups[0]["lr"] = args.lr * frac
        shaping_w = args.shaping * frac
        h0 = hidden.clone()
        ended = []
        with torch.no_grad(), autocast:
            for t in range(t_n):
                acting = torch.from_numpy(out["acting_seat"]).to(device).long().repeat_interleave(p)
                obs, mask, hidden, logp, value = forward(out, hidden, starts)
                action = torch.distributions.Categorical(logits=logp).sample()
                action = torch.where(seat_ids == acting, action, torch.zeros_like(action))
                obs_buf[t], mask_buf[t], act_buf[t], val_buf[t] = obs, mask, action, value
                logp_buf[t] = logp.gather(1, action[:, None]).squeeze(1)
                start_buf[t] = starts
                out = env.step(action.view(n, p).cpu().numpy().astype(np.uint32))
                r = torch.from_numpy(out["reward"] + shaping_w * out["shaping"]).to(device)
                d = torch.from_numpy(out["done"].astype(np.float32)).to(device)
                rew_buf[t], done_buf[t] = r.repeat_interleave(p), d.repeat_interleave(p)
                starts = done_buf[t]
                if out["done"].any():
                    ended.append({k: v[out["done"]].copy() for k, v in out["final"].items()})
            # The state reached here is not kept: the next rollout starts from these views.
            next_value = forward(out, hidden, starts)[4]
            adv = torch.zeros_like(rew_buf)
            last = torch.zeros(rows, device=device)
            for t in reversed(range(t_n)):
                nv = next_value if t == t_n - 1 else val_buf[t + 1]
                live = 1.0 - done_buf[t]
                delta = rew_buf[t] + args.gamma * nv * live - val_buf[t]
                last = delta + args.gamma * args.gae_lambda * live * last
                adv[t] = last
            ret = adv + val_buf
        t1 = time.perf_counter()

        # Learning: minibatches of whole rows, replayed from the rollout's start state.
        # Only acting rows (more than one legal action) carry a policy loss.
        choice = mask_buf.sum(-1) > 1

        def minibatch_loss(mb: torch.Tensor):
            b = len(mb)
            x = net.project(obs_buf[:, mb].reshape(t_n * b, *obs_shape)).view(t_n, b, -1)
            h, hs = h0[mb], []
            for t in range(t_n):
                h = net.gru(x[t], h * (1.0 - start_buf[t, mb, None]))
                hs.append(h)
            logp_all, value = net.heads(torch.stack(hs), mask_buf[:, mb])
            logp_all, value = logp_all.float(), value.float()
            logp = logp_all.gather(2, act_buf[:, mb, None]).squeeze(2)
            sel = choice[:, mb]
            a = adv[:, mb][sel]
            a = (a - a.mean()) / (a.std() + 1e-8)
            ratio = (logp[sel] - logp_buf[:, mb][sel]).exp()
            pg = torch.max(-a * ratio, -a * ratio.clamp(1 - args.clip, 1 + args.clip)).mean()
            v_old, r = val_buf[:, mb], ret[:, mb]
            v_clip = v_old + (value - v_old).clamp(-args.value_clip, args.value_clip)
            v_loss = 0.5 * torch.max((value - r) ** 2, (v_clip - r) ** 2).mean()
            ent = -(logp_all.exp() * logp_all).sum(-1)[sel].mean()
            return pg + args.value_coef * v_loss - args.entropy_coef * ent, pg, v_loss, ent

        for _ in range(args.epochs):
            for mb in torch.randperm(rows, device=device).chunk(args.minibatches):
                with autocast:
                    loss, pg, v_loss, ent = minibatch_loss(mb)
                optim.zero_grad(set_to_none=True)
                loss.backward()
                nn.utils.clip_grad_norm_(net.parameters(), args.max_grad_norm)
                optim.step()
        hidden = hidden.detach()
        if device.type == "cuda":
            torch.cuda.synchronize()
        t2 = time.perf_counter()
        steps += n * t_n
        games = {k: np.concatenate([e[k] for e in ended]) for k in ended[0]} if ended else {}
        line = {
            "update": update,
            "env_steps": steps,
            "sps": n * t_n / (t2 - t0),
            "rollout_seconds": t1 - t0,
            "learn_seconds": t2 - t1,
            "games": len(games.get("reward", [])),
            "reward": float(games["reward"].mean()) if games else None,
            "early_end": float(games["early_end"].mean()) if games else None,
            "policy_loss": pg.item(),
            "value_loss": v_loss.item(),
            "entropy": ent.item(),
            "lr": optim.param_groups[0]["lr"],
        }
        log.append(line)
        print(json.dumps(line), flush=True)
        if args.log:
            with open(args.log, "a") as f:
                f.write(json.dumps(line) + "\n")
        writer(line)
        if args.checkpoint:
            state = {"net": net.state_dict(), "optim": optim.state_dict(), "update": update}
            torch.save(state, args.checkpoint + ".tmp")
            os.replace(args.checkpoint + ".tmp", args.checkpoint)  # a crash keeps the last one
    return log


if __name__ == "__main__":
    main()
