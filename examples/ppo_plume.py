"""A learned policy in our worlds: stable-baselines3 PPO on a small ``Plume-v0``.

    pip install -e ".[gym]" stable-baselines3      # torch: see the README of this folder's repo
    python examples/ppo_plume.py --timesteps 200000 --out ppo_plume

The agent sees the posterior over the source as an image centred on itself
(``reciprocity.gym.BeliefImage(centred=True)``: otto's exact grid posterior on the 19 x 19
``otto-2d`` grid) and chooses one of otto's four moves. Every ``--eval-every`` steps it is evaluated
(deterministic actions) on the same ``--eval-seeds`` episodes as two references: infotaxis
(``StrategyPolicy("infotaxis")``) and a random walk. The figure ``learning_curve.png`` shows
its mean steps to the source falling toward infotaxis's; ``learning_curve.csv`` holds the
numbers. Not run in CI (it needs PyTorch); ``tests/test_examples.py`` checks the
environment and the evaluation, and trains a few hundred steps when stable-baselines3 is
installed.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

#: The budget of one episode (rounds): a failure scores it in full.
MAX_STEPS = 100


def make_env():
    """The training environment: ``otto-2d``, the belief centred on the searcher as the
    observation (37 x 37), and otto's four moves as the actions (no stay, no stop: a
    learner can neither park nor give up)."""
    import gymnasium
    import reciprocity.gym as rg

    class FourMoves(gymnasium.ActionWrapper):
        def __init__(self, env):
            super().__init__(env)
            self.action_space = gymnasium.spaces.Discrete(4)

        def action(self, action):
            return action                    # moves 0-3 of the face; a StrategyPolicy's own actions pass

    env = gymnasium.make("reciprocity/Plume-v0", scenario="otto-2d", max_steps=MAX_STEPS)
    return FourMoves(rg.BeliefImage(env, size=19, centred=True))


def evaluate(act, seeds, *, strategy: str | None = None) -> tuple[float, float]:
    """Mean steps (a failure counts as the whole budget) and success rate of a policy over
    `seeds`. `act(observation) -> action`, or `strategy` for a built-in one."""
    import reciprocity.gym as rg
    steps, wins = [], 0
    for seed in seeds:
        env = make_env()
        policy = rg.StrategyPolicy(strategy, env) if strategy else None
        obs, _ = env.reset(seed=int(seed))
        if policy:
            policy.reset(int(seed))
        done, info = False, {}
        while not done:
            obs, _, terminated, truncated, info = env.step(policy(obs) if policy else act(obs))
            done = terminated or truncated
        wins += bool(info["success"])
        steps.append(info["steps"] if info["success"] else MAX_STEPS)
    return float(np.mean(steps)), wins / len(seeds)


def random_walk(seed: int):
    """A random walk over otto's four moves (never stays, never stops)."""
    rng = np.random.default_rng(seed)
    return lambda obs: int(rng.integers(4))


def plot_curve(rows: list[dict], n_episodes: int, path: Path) -> None:
    """The learning curve: PPO's mean steps against training steps, beside infotaxis and
    the random walk."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4))
    t = [float(r["timesteps"]) for r in rows]
    ax.plot(t, [float(r["ppo_steps"]) for r in rows], "o-", label="PPO on the centred belief image")
    info, walk = float(rows[0]["infotaxis_steps"]), float(rows[0]["random_steps"])
    ax.axhline(info, color="k", ls="--", label=f"infotaxis ({info:.1f})")
    ax.axhline(walk, color="0.6", ls=":", label=f"random walk ({walk:.1f})")
    ax.set_xlabel("training steps")
    ax.set_ylabel("mean steps to the source")
    ax.set_title(f"otto-2d (19 x 19), {n_episodes} test episodes (a failure counts {MAX_STEPS})", fontsize=10)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timesteps", type=int, default=200_000)
    ap.add_argument("--eval-every", type=int, default=20_000)
    ap.add_argument("--eval-seeds", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=Path("ppo_plume"))
    args = ap.parse_args(argv)
    try:
        from stable_baselines3 import PPO
    except ImportError:
        sys.exit("error: this example needs stable-baselines3 (pip install stable-baselines3)")
    args.out.mkdir(parents=True, exist_ok=True)
    seeds = list(range(10_000, 10_000 + args.eval_seeds))       # never trained on: training seeds are drawn
    info_steps, info_rate = evaluate(None, seeds, strategy="infotaxis")
    rand_steps, rand_rate = evaluate(random_walk(args.seed), seeds)
    print(f"infotaxis {info_steps:.1f} steps ({info_rate:.0%}), random walk {rand_steps:.1f} ({rand_rate:.0%})")
    env = make_env()
    model = PPO("MlpPolicy", env, seed=args.seed, n_steps=1024, batch_size=256, gamma=0.995, verbose=0)
    rows = []
    done_steps, clock = 0, time.perf_counter()
    while True:
        mean, rate = evaluate(lambda o: int(model.predict(o, deterministic=True)[0]), seeds)
        rows.append(dict(timesteps=done_steps, ppo_steps=mean, ppo_success=rate, infotaxis_steps=info_steps,
                         random_steps=rand_steps, wall_s=time.perf_counter() - clock))
        print(f"{done_steps:>8} steps trained: PPO {mean:.1f} steps ({rate:.0%})", flush=True)
        if done_steps >= args.timesteps:
            break
        chunk = min(args.eval_every, args.timesteps - done_steps)
        model.learn(chunk, reset_num_timesteps=False)
        done_steps += chunk
    with open(args.out / "learning_curve.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    plot_curve(rows, len(seeds), args.out / "learning_curve.png")
    return rows


if __name__ == "__main__":
    main()
