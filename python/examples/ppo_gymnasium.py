"""A CleanRL-style PPO on `yokai.gymnasium.YokaiVectorEnv`: one policy plays every seat
(self-play), an MLP over the acting seat's image, illegal moves masked out of the logits.

    pip install "./python[pettingzoo]" torch
    python python/examples/ppo_gymnasium.py --updates 200

It shows the Gymnasium interface, not how to reach the paper's scores: a plain MLP learns
the shaped objective (the clustering shaping it is paid) within tens of updates, but
its game reward R stays near random play's -4.0 for far longer than the `yokai train`
presets, whose pointer head and END levers are what make agents END (docs/training.md).
Each update prints the mean game reward R of the games that ended and the shaped return per
game slot of the rollout.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import torch
import torch.nn as nn

from yokai.gymnasium import YokaiVectorEnv


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--config", default="9c-2p-perfect")
    p.add_argument("--updates", type=int, default=200)
    p.add_argument("--num-envs", type=int, default=64)
    p.add_argument("--rollout-steps", type=int, default=32)
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--entropy-coef", type=float, default=0.0)
    p.add_argument("--shaping", type=float, default=1.0, help="weight of the clustering shaping in the reward")
    p.add_argument("--epochs", type=int, default=2)
    p.add_argument("--minibatches", type=int, default=4)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--threads", type=int, default=1, help="PyTorch threads (the games step on all cores)")
    return p.parse_args(argv)


class Agent(nn.Module):
    def __init__(self, obs_dim: int, n_actions: int, hidden: int = 128):
        super().__init__()
        self.body = nn.Sequential(nn.Linear(obs_dim, hidden), nn.Tanh(), nn.Linear(hidden, hidden), nn.Tanh())
        self.actor, self.critic = nn.Linear(hidden, n_actions), nn.Linear(hidden, 1)

    def forward(self, obs, mask):
        h = self.body(obs.flatten(1))
        dist = torch.distributions.Categorical(logits=self.actor(h).masked_fill(~mask, -1e9))
        return dist, self.critic(h).squeeze(-1)


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    torch.manual_seed(args.seed)
    torch.set_num_threads(args.threads)
    env = YokaiVectorEnv(args.config, num_envs=args.num_envs, seed=args.seed, shaping=args.shaping)
    n, t_n = env.num_envs, args.rollout_steps
    agent = Agent(int(np.prod(env.single_observation_space.shape)), env.single_action_space.n)
    optim = torch.optim.Adam(agent.parameters(), lr=args.lr, eps=1e-5)
    obs, info = env.reset(seed=args.seed)
    log = []
    for update in range(1, args.updates + 1):
        start = time.perf_counter()
        # Rollout: the acting seat of every game chooses; the shared reward comes back.
        buf = {k: [] for k in ("obs", "mask", "action", "logp", "value", "reward", "done")}
        ended = []
        for _ in range(t_n):
            o, m = torch.as_tensor(obs), torch.as_tensor(info["action_mask"])
            with torch.no_grad():
                dist, value = agent(o, m)
                action = dist.sample()
            for k, x in (("obs", o), ("mask", m), ("action", action), ("logp", dist.log_prob(action)),
                         ("value", value)):
                buf[k].append(x)
            obs, reward, term, trunc, info = env.step(action.numpy())
            buf["reward"].append(torch.as_tensor(reward))
            buf["done"].append(torch.as_tensor(term | trunc, dtype=torch.float32))
            if "final_info" in info:
                ended.extend(info["final_info"]["reward"][info["_final_info"]].tolist())
        # Advantages: GAE over the rollout, bootstrapped from the last state's value.
        with torch.no_grad():
            _, next_value = agent(torch.as_tensor(obs), torch.as_tensor(info["action_mask"]))
        values, rewards, dones = (torch.stack(buf[k]) for k in ("value", "reward", "done"))
        adv, last = torch.zeros_like(rewards), torch.zeros(n)
        for t in reversed(range(t_n)):
            nxt = next_value if t == t_n - 1 else values[t + 1]
            delta = rewards[t] + 0.99 * nxt * (1 - dones[t]) - values[t]
            last = delta + 0.99 * 0.95 * (1 - dones[t]) * last
            adv[t] = last
        returns = (adv + values).flatten()
        flat = {k: torch.cat(buf[k]) for k in ("obs", "mask", "action", "logp")}
        adv = adv.flatten()
        adv = (adv - adv.mean()) / (adv.std() + 1e-8)
        # Learning: clipped PPO over shuffled minibatches.
        for _ in range(args.epochs):
            for mb in torch.randperm(n * t_n).chunk(args.minibatches):
                dist, value = agent(flat["obs"][mb], flat["mask"][mb])
                ratio = (dist.log_prob(flat["action"][mb]) - flat["logp"][mb]).exp()
                pg = torch.max(-adv[mb] * ratio, -adv[mb] * ratio.clamp(0.8, 1.2)).mean()
                loss = pg + 0.25 * ((value - returns[mb]) ** 2).mean() - args.entropy_coef * dist.entropy().mean()
                optim.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), 0.5)
                optim.step()
        line = {"update": update, "env_steps": update * n * t_n, "games": len(ended),
                "reward": float(np.mean(ended)) if ended else None,
                "shaped_return": float(rewards.sum() / n), "seconds": time.perf_counter() - start}
        log.append(line)
        print(line, flush=True)
    env.close()
    return log


if __name__ == "__main__":
    main()
