"""A learned policy in our worlds: stable-baselines3 PPO on a small ``Plume-v0``.

    pip install -e ".[gym]" stable-baselines3
    python examples/ppo_plume.py --timesteps 200000 --out ppo_plume

stable-baselines3 installs PyTorch, a download of several hundred MB (with CUDA
libraries on Linux); this example needs no GPU, and the CPU-only wheel is smaller:
``pip install torch --index-url https://download.pytorch.org/whl/cpu`` first.

It takes about 9 minutes on one idle core (``benchmarks/adapters.md``: 200 000 steps,
ten evaluations of 100 episodes each), torch held to one thread (``--threads 1``, the
default: the policy is small, and more threads only contend on a shared machine); on a
busy two-core machine with torch's default threads it took 35-40 minutes. It prints the
training steps as it goes (every ``--report-every`` steps) and, after each evaluation,
rewrites ``learning_curve.csv`` and ``learning_curve.png``, so a run stopped early keeps
its curve so far.

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

import csv
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


def evaluate(act, seeds, *, strategy: str | None = None, desc: str = "evaluating") -> tuple[float, float]:
    """Mean steps (a failure counts as the whole budget) and success rate of a policy over
    `seeds`. `act(observation) -> action`, or `strategy` for a built-in one. A progress bar
    over the episodes shows on a terminal."""
    from reciprocity.gym.training import evaluate as run
    result = run(make_env, seeds, act, strategy=strategy, desc=desc)
    return result.mean_steps(MAX_STEPS), result.rate


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


def write_results(rows: list[dict], n_episodes: int, out: Path) -> None:
    """``learning_curve.csv`` and ``learning_curve.png`` in `out`, from the evaluations so far."""
    with open(out / "learning_curve.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    plot_curve(rows, n_episodes, out / "learning_curve.png")


def main(argv=None) -> list[dict]:
    from reciprocity.gym.training import HELD_OUT, checked, training_parser
    ap = training_parser(__doc__.splitlines()[0], "ppo_plume")
    args = checked(ap, ap.parse_args(argv))
    from reciprocity.gym.training import require_sb3
    require_sb3(args.threads)
    from stable_baselines3 import PPO
    args.out.mkdir(parents=True, exist_ok=True)
    seeds = list(range(HELD_OUT, HELD_OUT + args.eval_seeds))   # never trained on: training seeds are drawn
    print(f"references on {len(seeds)} episodes: infotaxis, then a random walk", flush=True)
    info_steps, info_rate = evaluate(None, seeds, strategy="infotaxis", desc="infotaxis")
    rand_steps, rand_rate = evaluate(random_walk(args.seed), seeds, desc="random walk")
    print(f"infotaxis {info_steps:.1f} steps ({info_rate:.0%}), random walk {rand_steps:.1f} ({rand_rate:.0%})",
          flush=True)
    env = make_env()
    model = PPO("MlpPolicy", env, seed=args.seed, n_steps=1024, batch_size=256, gamma=0.995, verbose=0)
    rows = []
    done_steps, clock = 0, time.perf_counter()
    from reciprocity.gym.training import sb3_progress
    report = sb3_progress(args.timesteps, args.report_every)
    while True:
        mean, rate = evaluate(lambda o: int(model.predict(o, deterministic=True)[0]), seeds, desc="PPO")
        rows.append(dict(timesteps=done_steps, ppo_steps=mean, ppo_success=rate, infotaxis_steps=info_steps,
                         random_steps=rand_steps, wall_s=time.perf_counter() - clock))
        write_results(rows, len(seeds), args.out)               # as it goes: a stopped run keeps its curve
        print(f"{done_steps:>8} steps trained: PPO {mean:.1f} steps ({rate:.0%}), "
              f"{rows[-1]['wall_s'] / 60:.1f} min; results in {args.out}/", flush=True)
        if done_steps >= args.timesteps:
            break
        chunk = min(args.eval_every, args.timesteps - done_steps)
        model.learn(chunk, reset_num_timesteps=False, callback=report)
        done_steps = int(model.num_timesteps)          # whole rollouts: a little past the chunk
    return rows


if __name__ == "__main__":
    main()
