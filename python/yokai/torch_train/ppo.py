"""Recurrent PPO on ``yokai.TrainEnv`` in PyTorch, the algorithm of ``yokai train``
(``crates/yokai-train/src/trainer``) with its add-ons, in named phases:

1. schedules: the learning rate falls linearly to 0 (``ppo.anneal_lr``), the shaping
   weight over the first ``ppo.shaping_fraction`` of the run;
2. rollout: every row (a seat of a game) steps its GRU on its own view; the rows with more
   than one legal action draw from the masked policy, the others play their only action;
3. value targets: GAE over the game reward plus the weighted shaping, bootstrapped from
   the values after the last step;
4. learning: ``ppo.epochs`` passes over ``ppo.minibatches`` sets of whole row sequences,
   replayed from the states stored at the rollout's start: the clipped policy and value
   losses, the entropy bonus (per row divided by ln(legal actions) with
   ``ppo.entropy_normalized``), the END term (``ppo.end_lookahead``: P(END) pulled towards
   σ((R_END − V) / ¼) wherever END is legal, or its expected form), the END entropy bonus,
   the belief loss (``ppo.belief_aux``), the global gradient-norm clip and Adam.

Other-Play needs nothing here: ``TrainEnv`` shows each row its game through the row's
symmetry and maps its action back, as the Rust actor does.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import torch
import torch.nn.functional as F

import yokai

from .network import ActorCritic, Shapes, supported

#: Illegal logits sit this far below the row's best legal one (as ``distribution.rs``).
ILLEGAL_GAP = 60.0
#: Temperature of the END term's target form, in points of reward.
END_TARGET_TEMPERATURE = 0.25


def masked_log_softmax(logits: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """Log-probabilities over each row's legal actions (``mask`` 1/0)."""
    best = (logits + (mask - 1.0) * 1e9).amax(1, keepdim=True).detach()
    return F.log_softmax(logits * mask + (1.0 - mask) * (best - ILLEGAL_GAP), 1)


def draw(probs: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """One action per row of ``probs`` ``[B, A]``, drawn by inverse CDF: the first action
    whose cumulative probability passes a uniform number from ``generator`` (a CPU
    generator, so a seed gives the same uniforms on every device).

    Why not ``torch.multinomial``: with a CPU generator the probabilities must come back
    to the CPU, and there its draw of 1,024 rows × 777 actions took 29–44 ms on one thread
    (measured 2026-11-27 on a 2-core machine, docs/results/torch-draw.md): likely most of
    the 35 ms per rollout step the H200 run spent (docs/results/gpu-h200.md), not yet
    measured there. A cumulative sum and a sorted search are two kernels on the device; an
    action of probability 0 is never drawn (its interval is empty)."""
    u = torch.rand(probs.shape[0], 1, generator=generator).to(probs.device)
    cdf = probs.cumsum(1)
    drawn = torch.searchsorted(cdf, u * cdf[:, -1:], right=True)
    return drawn.clamp_max(probs.shape[1] - 1).squeeze(1)


def gae(rewards, values, dones, last_values, gamma: float, lam: float):
    """Advantages and returns of ``[T, R]`` steps (no bootstrap across an episode end)."""
    t_len = rewards.shape[0]
    adv = torch.zeros_like(rewards)
    next_adv = torch.zeros_like(last_values)
    next_value = last_values
    for t in reversed(range(t_len)):
        live = 1.0 - dones[t]
        delta = rewards[t] + gamma * next_value * live - values[t]
        next_adv = delta + gamma * lam * live * next_adv
        adv[t] = next_adv
        next_value = values[t]
    return adv, adv + values


@dataclass
class Games:
    """The paper's metrics of the games that ended during an update."""

    reward: list = field(default_factory=list)
    won: list = field(default_factory=list)
    early_end: list = field(default_factory=list)
    length: list = field(default_factory=list)
    correct_hints: list = field(default_factory=list)
    wrong_hints: list = field(default_factory=list)

    def add(self, final: dict, done: np.ndarray) -> None:
        for key in ("reward", "won", "early_end", "length", "correct_hints", "wrong_hints"):
            getattr(self, key).extend(final[key][done].tolist())

    def metrics(self) -> dict | None:
        n = len(self.reward)
        if n == 0:
            return None
        r = np.asarray(self.reward, dtype=np.float64)
        won, early = np.asarray(self.won), np.asarray(self.early_end)
        return {
            "games": n,
            "reward": float(r.mean()),
            "reward_se": float(r.std(ddof=1) / math.sqrt(n)) if n > 1 else 0.0,
            "win_rate": float(won.mean()),
            "early_end": float(early.mean()),
            "successful_early_end": float((won & early).mean()),
            "win_given_early_end": float(won[early].mean()) if early.any() else None,
            "length": float(np.mean(self.length)),
            "correct_hints": float(np.mean(self.correct_hints)),
            "wrong_hints": float(np.mean(self.wrong_hints)),
        }


class Trainer:
    """One seed's run of a training config (a preset name or a TOML path, with
    ``FIELD=VALUE`` overrides as ``yokai train --set``) on ``device``."""

    def __init__(self, config: str, seed: int = 0, overrides=(), device: str = "cpu"):
        self.env = yokai.TrainEnv(config, seed=seed, set=list(overrides))
        self.config = _toml(self.env.train_config)
        supported(self.config)
        self.seed, self.device = seed, torch.device(device)
        self.c = self.config["ppo"]
        torch.manual_seed(yokai.derive_seed(seed, 0xC0FFEE))
        self.shapes = Shapes.of(self.env)
        self.model = ActorCritic(self.config["network"], self.c, self.shapes).to(self.device)
        self.optim = torch.optim.Adam(self.model.parameters(), lr=self.c["lr"], eps=self.c["adam_eps"])
        self.generator = torch.Generator().manual_seed(yokai.derive_seed(seed, 0xD2A3))
        self.rows, self.players = self.env.num_rows, self.env.num_players
        self.state = torch.zeros(self.rows, self.model.hidden_size, device=self.device)
        self.view = self.env.observe()
        self.update = 0
        #: Env steps per update (one step of every game per rollout step).
        self.per_update = self.c["num_envs"] * self.c["rollout_steps"]
        self.updates = max(1, -(-self.c["total_steps"] // self.per_update))

    # -- phases -------------------------------------------------------------------------

    def schedules(self) -> tuple[float, float]:
        progress = self.update / self.updates
        lr = self.c["lr"] * (1.0 - progress) if self.c["anneal_lr"] else self.c["lr"]
        shaping = self.c["shaping"] * max(0.0, 1.0 - progress / self.c["shaping_fraction"])
        return lr, shaping

    def _tensors(self, view: dict):
        d = self.device
        obs = torch.from_numpy(view["obs"]).reshape(self.rows, -1).to(d)
        mask = torch.from_numpy(view["legal_mask"]).to(d)
        keep = torch.from_numpy(view["keep"]).to(d)
        return obs, mask, keep

    def _one_hot(self, truth: torch.Tensor) -> torch.Tensor:
        """Every row's true colours ``[rows, Y·C]`` one-hot (what a central critic reads)."""
        return F.one_hot(truth, self.shapes.colours).reshape(truth.shape[0], -1).float().to(self.device)

    @torch.no_grad()
    def rollout(self, shaping: float) -> dict:
        c, m, s = self.c, self.model, self.shapes
        t_len, rows, p = c["rollout_steps"], self.rows, self.players
        central = m.central is not None
        ro = {k: [] for k in ("obs", "mask", "keep", "actions", "logp", "values", "truth", "end_paid", "rewards", "dones")}
        h0 = self.state.clone()
        games, acting_rows = Games(), 0
        # Summed on the device and read once: a read per step would wait for the GPU.
        entropy_sum = torch.zeros((), device=self.device)
        for _ in range(t_len):
            view = self.view
            obs, mask, keep = self._tensors(view)
            h = m.recur(obs, self.state, keep)
            truth = torch.from_numpy(view["truth"].astype(np.int64))
            values = m.values(h, self._one_hot(truth) if central else None)
            legal = mask.sum(1)
            actions = mask.argmax(1)
            logp = torch.zeros(rows, device=self.device)
            choosing = (legal > 1).nonzero().squeeze(1)
            if len(choosing):
                logits, _ = m.heads(obs[choosing], h[choosing])
                mask_c = mask[choosing]
                lp = masked_log_softmax(logits, mask_c)
                probs = lp.exp()
                drawn = draw(probs, self.generator)
                actions[choosing] = drawn
                logp[choosing] = lp.gather(1, drawn.unsqueeze(1)).squeeze(1)
                entropy_sum += -(probs * lp * mask_c).sum()
            acting_rows += self.env.num_envs
            # What END pays, on the acting rows (TrainEnv gives 0 where END is illegal).
            acting = torch.from_numpy(view["acting_seat"].astype(np.int64)) + torch.arange(0, rows, p)
            end_paid = torch.zeros(rows)
            end_paid[acting] = torch.from_numpy(view["end_reward"])
            step = self.env.step(actions.cpu().numpy())
            reward = torch.from_numpy(step["reward"] + shaping * step["shaping"]).repeat_interleave(p)
            done = step["done"]
            games.add(step["final"], done)
            for k, v in (("obs", obs), ("mask", mask), ("keep", keep), ("actions", actions), ("logp", logp), ("values", values),
                         ("truth", truth), ("end_paid", end_paid), ("rewards", reward),
                         ("dones", torch.from_numpy(done.astype(np.float32)).repeat_interleave(p))):
                ro[k].append(v.to(self.device))
            self.state = h
            self.view = self.env.observe()
        ro = {k: torch.stack(v) for k, v in ro.items()}
        # Value targets: GAE, bootstrapped from the values after the last step.
        obs, _, keep = self._tensors(self.view)
        h_last = m.recur(obs, self.state, keep)
        last_truth = torch.from_numpy(self.view["truth"].astype(np.int64))
        last = m.values(h_last, self._one_hot(last_truth) if central else None)
        ro["adv"], ro["returns"] = gae(ro["rewards"], ro["values"], ro["dones"], last, c["gamma"], c["gae_lambda"])
        ro["h0"] = h0
        ro["games"] = games.metrics()
        ro["entropy"] = float(entropy_sum) / max(acting_rows, 1)
        return ro

    def learn(self, ro: dict, lr: float) -> dict:
        c = self.c
        for group in self.optim.param_groups:
            group["lr"] = lr
        sums = {"policy_loss": 0.0, "value_loss": 0.0, "approx_kl": 0.0, "clip_fraction": 0.0, "grad_norm": 0.0,
                "belief_loss": 0.0, "belief_accuracy": 0.0}
        count, replay_error = 0, 0.0
        mb = self.rows // c["minibatches"]
        for _ in range(c["epochs"]):
            order = torch.randperm(self.rows, generator=self.generator).to(self.device)
            for k in range(c["minibatches"]):
                batch = order[k * mb : self.rows if k + 1 == c["minibatches"] else (k + 1) * mb]
                out = self.learn_minibatch(ro, batch)
                if count == 0:
                    replay_error = out["abs_delta"]
                for key in sums:
                    sums[key] += out[key]
                count += 1
        means = {k: v / count for k, v in sums.items()}
        if self.c["belief_aux"] <= 0:
            del means["belief_loss"], means["belief_accuracy"]
        return {**means, "replay_error": replay_error, "explained_variance": explained_variance(ro)}

    def learn_minibatch(self, ro: dict, batch: torch.Tensor) -> dict:
        c, m, s = self.c, self.model, self.shapes
        t_len = c["rollout_steps"]

        def rows_of(x):  # [T, R, ...] → [B·T, ...] in (b, t) order
            x = x[:, batch].transpose(0, 1)
            return x.reshape(x.shape[0] * t_len, *x.shape[2:])

        obs = rows_of(ro["obs"])
        b = len(batch)
        states = m.unroll(obs.reshape(b, t_len, -1), ro["h0"][batch], ro["keep"][:, batch].t())
        truth = rows_of(ro["truth"])
        one_hot = F.one_hot(truth, s.colours).float()
        values = m.values(states, one_hot.reshape(b * t_len, -1) if m.central is not None else None)
        old_v, ret = rows_of(ro["values"]), rows_of(ro["returns"])
        v_clipped = old_v + (values - old_v).clamp(-c["value_clip"], c["value_clip"])
        value_loss = 0.5 * torch.maximum((values - ret) ** 2, (v_clipped - ret) ** 2).mean()

        mask = rows_of(ro["mask"])
        legal = mask.sum(1)
        idx = (legal > 1).nonzero().squeeze(1)
        n = len(idx)
        zero = torch.zeros((), device=self.device)
        policy_loss = entropy = end_bonus = belief = zero
        kl = clip_fraction = abs_delta = hits = 0.0
        if n:
            logits, colour_logits = m.heads(obs[idx], states[idx])
            mask_c = mask[idx]
            lp = masked_log_softmax(logits, mask_c)
            logp = lp.gather(1, rows_of(ro["actions"])[idx].unsqueeze(1)).squeeze(1)
            adv = rows_of(ro["adv"])[idx]
            if c["normalize_advantages"] and n > 1:
                adv = (adv - adv.mean()) / (adv.std(unbiased=False) + 1e-8)
            delta = logp - rows_of(ro["logp"])[idx]
            ratio = delta.exp()
            clipped = ratio.clamp(1 - c["clip"], 1 + c["clip"])
            policy_loss = -torch.minimum(ratio * adv, clipped * adv).sum() / n
            row_entropy = -(lp.exp() * lp * mask_c).sum(1)
            if c["entropy_normalized"]:
                row_entropy = row_entropy / legal[idx].log()
            entropy = row_entropy.sum() / n
            end_bonus = self.end_terms(lp, mask_c, rows_of(ro["end_paid"])[idx], old_v[idx])
            if colour_logits is not None and c["belief_aux"] > 0:
                log_p = F.log_softmax(colour_logits, 2)
                belief = -(log_p * one_hot[idx]).sum() / (n * s.cards)
                hits = float((log_p.argmax(2) == truth[idx]).float().mean())
            with torch.no_grad():
                kl = float((ratio - 1 - delta).mean())
                clip_fraction = float(((ratio - 1).abs() > c["clip"]).float().mean())
                abs_delta = float(delta.abs().mean())
        loss = policy_loss + c["value_coef"] * value_loss - c["entropy_coef"] * entropy - end_bonus + c["belief_aux"] * belief
        self.optim.zero_grad(set_to_none=True)
        loss.backward()
        grad_norm = torch.nn.utils.clip_grad_norm_(m.parameters(), c["max_grad_norm"])
        self.optim.step()
        return {"policy_loss": float(policy_loss.detach()), "value_loss": float(value_loss.detach()), "approx_kl": kl,
                "clip_fraction": clip_fraction, "grad_norm": float(grad_norm), "abs_delta": abs_delta,
                "belief_loss": float(belief.detach()), "belief_accuracy": hits}

    def end_terms(self, lp, mask, paid, old_v) -> torch.Tensor:
        """The END entropy bonus and the END term, averaged over the rows where END is
        legal (``trainer/addons/end.rs``)."""
        c = self.c
        end = self.env.end_action
        legal = mask[:, end]
        rows_with_end = legal.sum().clamp_min(1.0)
        log_p = lp[:, end]
        bonus = torch.zeros((), device=lp.device)
        if c["end_entropy_coef"] > 0:
            p = log_p.exp()
            rest = (1 - p).clamp_min(1e-7)
            h = -(p * log_p + rest * rest.log()) * legal
            bonus = bonus + c["end_entropy_coef"] * h.sum() / rows_with_end
        if c["end_lookahead"] > 0:
            adv = (paid - old_v) * legal
            if c["end_lookahead_form"] == "target":
                target = torch.sigmoid(adv / END_TARGET_TEMPERATURE)
                log_rest = torch.log1p(-log_p.exp().clamp_max(1 - 1e-6))
                gain = (target * log_p + (1 - target) * log_rest) * legal
            else:
                gain = log_p.exp() * adv
            bonus = bonus + c["end_lookahead"] * gain.sum() / rows_with_end
        return bonus

    def step(self) -> dict:
        """One update: schedules, rollout with its value targets, learning; its stats."""
        start = time.perf_counter()
        lr, shaping = self.schedules()
        ro = self.rollout(shaping)
        rollout_seconds = time.perf_counter() - start
        losses = self.learn(ro, lr)
        self.update += 1
        seconds = time.perf_counter() - start
        per = self.per_update
        return {"update": self.update, "env_steps": self.update * per, "sps": per / seconds, "games": ro["games"],
                "entropy": ro["entropy"], "lr": lr, "shaping": shaping, "rollout_seconds": rollout_seconds,
                "learn_seconds": seconds - rollout_seconds, **losses}

    def metadata(self) -> dict[str, str]:
        """What a policy file says of itself (``artifact/safetensors.rs``'s keys)."""
        return {
            "yokai.train_config": self.env.train_config,
            "yokai.game": self.env.game_config,
            "yokai.hidden_size": str(self.model.hidden_size),
            "yokai.observation_shape": str(list(self.env.observation_shape)),
            "yokai.seed": str(self.seed),
            "yokai.update": str(self.update),
            "yokai.env_steps": str(self.update * self.per_update),
            "yokai.trainer": "yokai.torch_train",
        }


def explained_variance(ro: dict) -> float | None:
    """1 − Var(return − V) / Var(return) over the rollout (``None`` where returns are
    constant), as the Rust trainer reports it."""
    ret, v = ro["returns"].flatten().double(), ro["values"].flatten().double()
    var = float(ret.var(unbiased=False))
    return None if var == 0 else 1.0 - float((ret - v).var(unbiased=False)) / var


def _toml(text: str) -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    return tomllib.loads(text)
