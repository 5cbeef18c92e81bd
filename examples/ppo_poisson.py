"""A learned policy on the reciprocity arena: stable-baselines3 PPO, at its defaults, on
``reciprocity/Poisson-v0``.

    pip install -e ".[gym]" stable-baselines3
    python examples/ppo_poisson.py --timesteps 200000 --out ppo_poisson

stable-baselines3 installs PyTorch; this example needs no GPU, and the CPU-only wheel is
smaller: ``pip install torch --index-url https://download.pytorch.org/whl/cpu`` first.

Each episode draws a new source and start (``Poisson-v0``'s ``random_source``), and has
40 rounds; a failed stop costs the rounds left. The learner sees the reciprocity imaging
map as a 16 x 16 image and the belief's spread along its two axes
(``BeliefImage(features=True)``, the map on a 2 cm mesh), and acts in the belief's own frame
(``BeliefStop``: the next point as a multiple of the belief's standard deviations from its
mean, and a stop flag that declares the map's estimate). It must learn where to read and
when to stop; the map itself is not learned.

Every ``--eval-every`` steps the policy is evaluated on the same ``--eval-seeds`` held-out
episodes, with its deterministic actions and with actions sampled from it (torch seeded
by ``--seed``), beside two references on the same seeds: the reciprocity
strategy itself (``StrategyPolicy("reciprocity")``) and random actions in the same action
space. It prints the steps trained every ``--report-every`` steps and, after each
evaluation, rewrites ``learning_curve.csv`` and ``learning_curve.png``, so a run stopped
early keeps its curve so far. Training runs ``--envs`` environments in subprocesses
(SB3's ``SubprocVecEnv``). The time and the result are in ``benchmarks/adapters.md``.
Not run in CI (it needs PyTorch); ``tests/test_examples.py`` checks the environment and the
evaluation, and trains a few hundred steps when stable-baselines3 is installed.
"""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np

#: The budget of one episode (rounds): ``Poisson-v0``'s own.
MAX_STEPS = 40
#: Imaging mesh of the learner's belief (cm): coarser than the strategy's 1 cm, for speed.
BELIEF_H = 2.0


def make_env():
    """The training environment: ``Poisson-v0`` seen through its belief (the imaging map as
    a 16 x 16 image, its spread and the budget spent), acting in the belief's own frame."""
    import gymnasium
    import reciprocity.gym as rg
    env = gymnasium.make("reciprocity/Poisson-v0", max_steps=MAX_STEPS)
    return rg.BeliefStop(rg.BeliefImage(env, size=16, h=BELIEF_H, features=True))


def random_actions(seed: int):
    """Uniform actions in the learner's action space."""
    rng = np.random.default_rng(seed)
    return lambda obs: rng.uniform(-1.0, 1.0, 3)


def evaluate(act, seeds, *, strategy: str | None = None, desc: str = "evaluating") -> dict:
    """Success rate with its 95 % interval and mean rounds of a policy over `seeds`."""
    from reciprocity.gym.training import evaluate as run
    result = run(make_env, seeds, act, strategy=strategy, desc=desc)
    lo, hi = result.interval()
    return dict(success=result.rate, low=lo, high=hi, steps=result.mean_steps())


def plot_curve(rows: list[dict], n_episodes: int, path: Path) -> None:
    """Success rate (with its 95 % interval) against training steps, beside the references."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4))
    t = np.array([float(r["timesteps"]) for r in rows])
    rate = np.array([float(r["ppo_success"]) for r in rows])
    ax.fill_between(t, [float(r["ppo_low"]) for r in rows], [float(r["ppo_high"]) for r in rows],
                    color="tab:blue", alpha=0.2, lw=0)
    ax.plot(t, rate, "o-", color="tab:blue", label="PPO (SB3 defaults), deterministic actions")
    have = [k for k, r in enumerate(rows) if str(r.get("sampled_success", "")) != ""]
    if have:
        ts = t[have]
        ax.fill_between(ts, [float(rows[k]["sampled_low"]) for k in have],
                        [float(rows[k]["sampled_high"]) for k in have], color="tab:orange", alpha=0.2, lw=0)
        ax.plot(ts, [float(rows[k]["sampled_success"]) for k in have], "s-", color="tab:orange",
                label="PPO, actions sampled from its policy")
    ref, rnd = float(rows[0]["strategy_success"]), float(rows[0]["random_success"])
    ax.axhline(ref, color="k", ls="--", label=f"reciprocity strategy ({ref:.0%})")
    ax.axhline(rnd, color="0.6", ls=":", label=f"random actions ({rnd:.0%})")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("training steps")
    ax.set_ylabel("success rate")
    ax.set_title(f"Poisson-v0 (paper arena, new source and start each episode), {n_episodes} test episodes",
                 fontsize=9)
    ax.legend(loc="lower left", bbox_to_anchor=(0.01, 0.6), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def write_results(rows: list[dict], n_episodes: int, out: Path) -> None:
    """``learning_curve.csv`` and ``learning_curve.png`` in `out`, from the evaluations so far."""
    with open(out / "learning_curve.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[-1]), restval="")
        w.writeheader()
        w.writerows(rows)
    plot_curve(rows, n_episodes, out / "learning_curve.png")


def earlier_rows(path: Path, before: int) -> list[dict]:
    """The rows of an earlier run's curve in `path` up to `before` training steps (a
    continued run draws the whole curve)."""
    if not path.is_file():
        return []
    with open(path, newline="") as f:
        return [row for row in csv.DictReader(f) if float(row["timesteps"]) < before]


def main(argv=None) -> list[dict]:
    from reciprocity.gym.training import HELD_OUT, checked, training_parser
    ap = training_parser(__doc__.splitlines()[0], "ppo_poisson")
    ap.add_argument("--envs", type=int, default=2, help="training environments, one process each")
    ap.add_argument("--init", type=Path, help="go on training this saved model (its steps count toward --timesteps)")
    args = checked(ap, ap.parse_args(argv))
    if args.init is not None and not args.init.is_file():
        ap.error(f"--init must be a model saved by this example (ppo_poisson.zip); got {str(args.init)!r}")
    from reciprocity.gym.training import require_sb3, sb3_progress
    torch = require_sb3(args.threads)
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv
    args.out.mkdir(parents=True, exist_ok=True)
    seeds = list(range(HELD_OUT, HELD_OUT + args.eval_seeds))   # never trained on: training seeds are drawn
    print(f"references on {len(seeds)} episodes: the reciprocity strategy, then random actions", flush=True)
    ref = evaluate(None, seeds, strategy="reciprocity", desc="reciprocity")
    rnd = evaluate(random_actions(args.seed), seeds, desc="random")
    print(f"reciprocity {ref['success']:.0%} in {ref['steps']:.1f} rounds, random {rnd['success']:.0%} "
          f"in {rnd['steps']:.1f}", flush=True)
    venv = make_vec_env(make_env, n_envs=args.envs, seed=args.seed,
                        vec_env_cls=SubprocVecEnv if args.envs > 1 else None)
    if args.init is None:
        model = PPO("MultiInputPolicy", venv, seed=args.seed, device="cpu", verbose=0)    # SB3's defaults
    else:
        model = PPO.load(args.init, env=venv, device="cpu")
    done_steps, clock = int(model.num_timesteps), time.perf_counter()
    rows = earlier_rows(args.out / "learning_curve.csv", done_steps) if args.init is not None else []
    report = sb3_progress(args.timesteps, args.report_every)
    try:
        while True:
            ppo = evaluate(lambda o: model.predict(o, deterministic=True)[0], seeds, desc="PPO")
            torch.manual_seed(args.seed)                          # the sampled actions, reproducibly
            sampled = evaluate(lambda o: model.predict(o, deterministic=False)[0], seeds, desc="PPO sampled")
            rows.append(dict(timesteps=done_steps, ppo_success=ppo["success"], ppo_low=ppo["low"],
                             ppo_high=ppo["high"], ppo_steps=ppo["steps"], sampled_success=sampled["success"],
                             sampled_low=sampled["low"], sampled_high=sampled["high"], sampled_steps=sampled["steps"],
                             strategy_success=ref["success"], strategy_steps=ref["steps"],
                             random_success=rnd["success"], random_steps=rnd["steps"],
                             wall_s=round(time.perf_counter() - clock, 1)))
            write_results(rows, len(seeds), args.out)            # as it goes: a stopped run keeps its curve
            print(f"{done_steps:>8} steps trained: PPO {ppo['success']:.0%} [{ppo['low']:.0%}, {ppo['high']:.0%}] "
                  f"in {ppo['steps']:.1f} rounds, sampled {sampled['success']:.0%} [{sampled['low']:.0%}, "
                  f"{sampled['high']:.0%}] in {sampled['steps']:.1f}, {rows[-1]['wall_s'] / 60:.1f} min; "
                  f"results in {args.out}/", flush=True)
            if done_steps >= args.timesteps:
                break
            chunk = min(args.eval_every, args.timesteps - done_steps)
            model.learn(chunk, reset_num_timesteps=False, callback=report)
            done_steps = int(model.num_timesteps)      # whole rollouts: a little past the chunk
        model.save(args.out / "ppo_poisson")
    finally:
        venv.close()
    return rows


if __name__ == "__main__":
    main()
