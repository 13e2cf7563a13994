"""Recurrent IPPO on Yōkai in JAX: the whole training run is one jitted function.

In the style of JaxMARL's IPPO baselines: the environment is ``yokai.jax.YokaiEnv`` (a
JaxMARL ``MultiAgentEnv``) behind JaxMARL's ``LogWrapper``; ``jax.vmap`` runs the games,
``jax.lax.scan`` the steps of a rollout and the updates of the run, and every env step is
one call into the Rust engine for the whole batch.

Phases of one update: (1) roll out ``--steps`` steps of ``--envs`` games with a GRU
policy shared by both seats, (2) generalised advantage estimates, (3) ``--epochs`` PPO
epochs over ``--minibatches`` minibatches of whole sequences.

    python python/examples/ippo_jax.py --updates 30
    python python/examples/ippo_jax.py --updates 30 --json curve.json

Needs ``pip install "yokai-learning-environment[jax]"`` (jax, jaxmarl, flax, optax).
"""

from __future__ import annotations

import argparse
import json
import time
from typing import NamedTuple

import flax.linen as nn
import jax
import jax.numpy as jnp
import numpy as np
import optax
from flax.training.train_state import TrainState
from jaxmarl.wrappers.baselines import LogWrapper

from yokai.jax import YokaiEnv


class GRU(nn.Module):
    """A GRU over time ``[T, B, F]``, its memory zeroed where a game started."""

    hidden: int

    @nn.compact
    def __call__(self, h, xs):
        cell = nn.scan(
            _ResetCell, variable_broadcast="params", split_rngs={"params": False}, in_axes=0, out_axes=0
        )(self.hidden)
        return cell(h, xs)


class _ResetCell(nn.Module):
    hidden: int

    @nn.compact
    def __call__(self, h, x):
        inputs, starts = x
        h = jnp.where(starts[:, None], jnp.zeros_like(h), h)
        h, y = nn.GRUCell(features=self.hidden)(h, inputs)
        return h, y


class ActorCritic(nn.Module):
    """Observation → dense → GRU → masked policy logits and a value."""

    num_actions: int
    hidden: int = 128

    @nn.compact
    def __call__(self, h, obs, starts, legal):
        x = nn.relu(nn.Dense(self.hidden)(obs))
        h, x = GRU(self.hidden)(h, (x, starts))
        logits = nn.Dense(self.num_actions, kernel_init=nn.initializers.orthogonal(0.01))(
            nn.relu(nn.Dense(self.hidden)(x))
        )
        # Illegal actions sit far below the legal ones (not at -inf: no NaN in softmax).
        logits = jnp.where(legal, logits, logits.min(-1, keepdims=True) - 60.0)
        value = nn.Dense(1)(nn.relu(nn.Dense(self.hidden)(x)))[..., 0]
        return h, jax.nn.log_softmax(logits), value


class Transition(NamedTuple):
    start: jax.Array  # the game started at this step (memory reset before it)
    done: jax.Array
    action: jax.Array
    value: jax.Array
    reward: jax.Array
    log_prob: jax.Array
    obs: jax.Array
    legal: jax.Array
    returns: jax.Array  # LogWrapper's finished-episode returns
    finished: jax.Array


def stack(x: dict, agents) -> jax.Array:
    """Per-agent ``[E, ...]`` arrays as one ``[P·E, ...]`` batch of actors."""
    return jnp.concatenate([x[a] for a in agents], axis=0)


def make_train(args):
    env = LogWrapper(YokaiEnv(args.config, shaping=args.shaping))
    agents = env._env.agents
    p, e = len(agents), args.envs
    actors = p * e
    net = ActorCritic(env.action_space(agents[0]).n, args.hidden)
    obs_len = env.observation_space(agents[0]).shape[0]

    def train(key):
        key, k_init, k_reset = jax.random.split(key, 3)
        h0 = jnp.zeros((actors, args.hidden))
        params = net.init(
            k_init,
            h0,
            jnp.zeros((1, actors, obs_len)),
            jnp.zeros((1, actors), bool),
            jnp.ones((1, actors, net.num_actions), bool),
        )
        tx = optax.chain(optax.clip_by_global_norm(0.5), optax.adam(args.lr, eps=1e-5))
        state = TrainState.create(apply_fn=net.apply, params=params, tx=tx)
        obs, env_state = jax.vmap(env.reset)(jax.random.split(k_reset, e))
        runner = (state, env_state, obs, jnp.ones((actors,), bool), h0, key)

        def update(runner, _):
            # (1) Roll out.
            def env_step(carry, _):
                state, env_state, obs, start, h, key = carry
                key, k_act, k_env = jax.random.split(key, 3)
                legal = stack(jax.vmap(env._env.get_avail_actions)(env_state.env_state), agents)
                obs_b = stack(obs, agents)
                h, logp, value = net.apply(state.params, h, obs_b[None], start[None], legal[None])
                logp, value = logp[0], value[0]
                action = jax.random.categorical(k_act, logp)
                acts = {a: action[i * e : (i + 1) * e] for i, a in enumerate(agents)}
                obs, env_state, reward, done, info = jax.vmap(env.step)(
                    jax.random.split(k_env, e), env_state, acts
                )
                d = jnp.tile(done["__all__"], p)
                t = Transition(
                    start,
                    d,
                    action,
                    value,
                    stack(reward, agents),
                    jnp.take_along_axis(logp, action[:, None], -1)[:, 0],
                    obs_b,
                    legal,
                    info["returned_episode_returns"][:, 0],
                    done["__all__"],
                )
                return (state, env_state, obs, d, h, key), t

            h_start = runner[4]
            runner, traj = jax.lax.scan(env_step, runner, None, args.steps)
            state, env_state, obs, start, h, key = runner

            # (2) Advantages.
            _, _, last_value = net.apply(
                state.params, h, stack(obs, agents)[None], start[None], jnp.ones((1, actors, net.num_actions), bool)
            )

            def gae(carry, t):
                adv, next_value = carry
                delta = t.reward + args.gamma * next_value * (1 - t.done) - t.value
                adv = delta + args.gamma * args.lam * (1 - t.done) * adv
                return (adv, t.value), adv

            _, advantages = jax.lax.scan(
                gae, (jnp.zeros(actors), last_value[0]), traj, reverse=True
            )
            targets = advantages + traj.value

            # (3) PPO epochs over minibatches of actors' whole sequences.
            def loss_fn(params, h0, t, adv, target):
                _, logp, value = net.apply(params, h0, t.obs, t.start, t.legal)
                new_logp = jnp.take_along_axis(logp, t.action[..., None], -1)[..., 0]
                ratio = jnp.exp(new_logp - t.log_prob)
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
                policy = -jnp.minimum(ratio * adv, jnp.clip(ratio, 0.8, 1.2) * adv).mean()
                value_loss = 0.5 * jnp.square(value - target).mean()
                probs = jnp.exp(logp)
                entropy = -(probs * jnp.where(t.legal, logp, 0.0)).sum(-1).mean()
                return policy + 0.5 * value_loss - args.ent * entropy, entropy

            def epoch(carry, _):
                state, key = carry
                key, k = jax.random.split(key)
                order = jax.random.permutation(k, actors).reshape(args.minibatches, -1)

                def minibatch(state, idx):
                    pick = lambda x: jnp.take(x, idx, axis=1)  # noqa: E731
                    grads, entropy = jax.grad(loss_fn, has_aux=True)(
                        state.params, h_start[idx], jax.tree.map(pick, traj), pick(advantages), pick(targets)
                    )
                    return state.apply_gradients(grads=grads), entropy

                state, entropy = jax.lax.scan(minibatch, state, order)
                return (state, key), entropy

            (state, key), entropy = jax.lax.scan(epoch, (state, key), None, args.epochs)
            finished = traj.finished.sum()
            metrics = {
                "episode_return": jnp.where(finished > 0, (traj.returns * traj.finished).sum() / finished, jnp.nan),
                "games_finished": finished,
                "entropy": entropy.mean(),
            }
            return (state, env_state, obs, start, h, key), metrics

        runner, metrics = jax.lax.scan(update, runner, None, args.updates)
        return runner[0], metrics

    return train


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default="9c-2p-perfect")
    ap.add_argument("--updates", type=int, default=30)
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--steps", type=int, default=64)
    ap.add_argument("--epochs", type=int, default=2)
    ap.add_argument("--minibatches", type=int, default=4)
    ap.add_argument("--hidden", type=int, default=128)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--gamma", type=float, default=0.99)
    ap.add_argument("--lam", type=float, default=0.95)
    ap.add_argument("--ent", type=float, default=0.01)
    ap.add_argument("--shaping", type=float, default=1.0, help="weight of the shaping reward (0: R alone)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", help="write the per-update metrics here")
    args = ap.parse_args(argv)
    start = time.time()
    _, metrics = jax.jit(make_train(args))(jax.random.PRNGKey(args.seed))
    metrics = jax.tree.map(np.asarray, metrics)
    wall = time.time() - start
    steps = args.updates * args.envs * args.steps
    for u in range(args.updates):
        print(
            f"update {u + 1:4d}  episode return {metrics['episode_return'][u]:7.2f}  "
            f"games {int(metrics['games_finished'][u]):5d}  entropy {metrics['entropy'][u]:.3f}"
        )
    print(f"{steps} env steps in {wall:.1f} s with compilation ({steps / wall:.0f} env steps/s)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({k: v.tolist() for k, v in metrics.items()} | {"wall_s": wall, "env_steps": steps}, f)
    return metrics


if __name__ == "__main__":
    main()
