"""Train PPO (Stable-Baselines3) on ``mjtether/TetherWinch-v0`` and compare it with the
hand-written controllers on the same evaluation seeds: the paper's payout rule (``FollowPayout``:
pay out at the walker's speed, the baseline), the slant-range rate (``SlantRangePayout``), the
tuned PI loop on the laid slack (``SlackPI``) and a stopped winch.

    python -m pip install -e ".[learning]"
    python scripts/train_ppo.py --timesteps 400000 --out results/ppo      # about 40 min on 2 cores
    python scripts/train_ppo.py --baselines-only --eval-seeds 10         # the controllers alone, no PPO

Writes to ``--out``: ``policy.zip`` and ``vecnormalize.pkl`` (the policy and its observation
normalisation), ``learning_curve.png`` (episode return against environment steps),
``evaluation.json`` (per-seed returns and early terminations of every controller, means and
standard deviations) and prints the table that ``docs/learning.md`` shows (``--baselines-only``:
``baselines.json`` and the table without the policy; Stable-Baselines3 is not needed).
``--timesteps 256 --eval-seeds 1`` is the smoke test CI runs.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import mjtether.envs  # noqa: F401 - registers the environments
from mjtether.envs import FollowPayout, SlackPI, SlantRangePayout

ENV_ID = "mjtether/TetherWinch-v0"
EVAL_SEED0 = 10_000  # evaluation seeds: EVAL_SEED0 .. EVAL_SEED0 + n - 1, never used in training


def episode(env, act, seed: int) -> tuple[float, bool]:
    """(return, terminated early) of one episode of ``act(obs, env) -> action`` from
    ``env.reset(seed=seed)``."""
    obs, _ = env.reset(seed=seed)
    total, done, term = 0.0, False, False
    while not done:
        obs, r, term, trunc, _ = env.step(act(obs, env))
        total += r
        done = term or trunc
    return total, bool(term)


def episode_return(env, act, seed: int) -> float:
    """Return of one episode of ``act(obs, env) -> action`` from ``env.reset(seed=seed)``."""
    return episode(env, act, seed)[0]


REFERENCES = {"baseline": FollowPayout(), "slant_range": SlantRangePayout(), "slack_pi": SlackPI(),
              "fixed": lambda e: np.zeros(1, dtype=np.float32)}
"""Hand-written controllers evaluated beside the policy: the required baseline (the paper's
Eq. 30), a geometric payout rule, the tuned PI loop on the laid slack, and a winch that never
moves."""

LABELS = {"policy": "PPO policy (deterministic)", "baseline": "payout = walker speed (Khan Eq. 30), the baseline",
          "slant_range": "payout = slant-range rate", "slack_pi": "PI on the laid slack + slant-range feed-forward "
          "(`SlackPI`, tuned)", "fixed": "winch stopped"}


def evaluate(model, vecnorm, seeds) -> dict:
    """Every controller (the policy too, unless ``model`` is None) on ``seeds``."""
    env = gym.make(ENV_ID)
    out = {"seeds": list(seeds)}
    controllers = {} if model is None else {
        "policy": lambda o, e: model.predict(vecnorm.normalize_obs(o), deterministic=True)[0]}
    controllers.update({name: (lambda o, e, c=ctrl: c(e)) for name, ctrl in REFERENCES.items()})
    try:
        for name, act in controllers.items():
            runs = [episode(env, act, s) for s in seeds]
            out[name] = [r for r, _ in runs]
            out[f"{name}_terminated"] = int(sum(t for _, t in runs))
    finally:
        env.close()
    for name in controllers:
        out[f"{name}_mean"] = float(np.mean(out[name]))
        out[f"{name}_std"] = float(np.std(out[name]))
    return out


def table(ev: dict) -> str:
    n = len(ev["seeds"])
    lines = [f"| controller (over {n} seeds, {ev['seeds'][0]}..{ev['seeds'][-1]}) | mean return | std | "
             "episodes ended early |", "|---|---:|---:|---:|"]
    lines += [f"| {label} | {ev[key + '_mean']:.1f} | {ev[key + '_std']:.1f} | {ev.get(key + '_terminated', '')} |"
              for key, label in LABELS.items() if key + "_mean" in ev]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timesteps", type=int, default=400_000)
    ap.add_argument("--envs", type=int, default=2, help="parallel environments (subprocesses), default 2")
    ap.add_argument("--eval-seeds", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="results/ppo")
    ap.add_argument("--evaluate-only", action="store_true", help="load --out's policy and evaluate it again")
    ap.add_argument("--baselines-only", action="store_true",
                    help="evaluate the hand-written controllers alone (no training, no Stable-Baselines3)")
    args = ap.parse_args(argv)
    if args.baselines_only:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        ev = evaluate(None, None, range(EVAL_SEED0, EVAL_SEED0 + args.eval_seeds))
        (out / "baselines.json").write_text(json.dumps(ev, indent=1))
        print(table(ev))
        return
    try:
        from stable_baselines3 import PPO
        from stable_baselines3.common.env_util import make_vec_env
        from stable_baselines3.common.vec_env import SubprocVecEnv, VecNormalize
    except ImportError:
        raise SystemExit("train_ppo.py needs Stable-Baselines3: python -m pip install -e \".[learning]\"")
    import torch

    torch.set_num_threads(1)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.evaluate_only:
        return _evaluate_only(out, args.eval_seeds)
    t0 = time.perf_counter()
    vec_cls = SubprocVecEnv if args.envs > 1 else None
    venv = make_vec_env(ENV_ID, n_envs=args.envs, seed=args.seed, vec_env_cls=vec_cls)
    venv = VecNormalize(venv, norm_obs=True, norm_reward=True, gamma=0.99)
    n_steps = max(16, min(1024, args.timesteps // args.envs))
    model = PPO("MlpPolicy", venv, n_steps=n_steps, batch_size=min(256, n_steps * args.envs), learning_rate=3e-4,
                gamma=0.99, gae_lambda=0.95, n_epochs=10, clip_range=0.2, ent_coef=0.0,
                policy_kwargs={"net_arch": [64, 64]}, seed=args.seed, verbose=0, device="cpu")
    curve = []  # (environment steps, episode return)

    from stable_baselines3.common.callbacks import BaseCallback

    class Curve(BaseCallback):
        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "episode" in info:
                    curve.append((self.num_timesteps, float(info["episode"]["r"])))
            return True

    model.learn(total_timesteps=args.timesteps, callback=Curve(), progress_bar=False)
    train_s = time.perf_counter() - t0
    model.save(out / "policy.zip")
    venv.save(out / "vecnormalize.pkl")
    venv.training = False
    venv.norm_reward = False
    ev = evaluate(model, venv, range(EVAL_SEED0, EVAL_SEED0 + args.eval_seeds))
    venv.close()
    ev.update({"timesteps": args.timesteps, "envs": args.envs, "train_wall_s": round(train_s, 1),
               "curve": curve})
    (out / "evaluation.json").write_text(json.dumps(ev, indent=1))
    _plot_curve(curve, ev, out / "learning_curve.png")
    print(f"trained {args.timesteps} steps in {train_s / 60:.1f} min on {args.envs} envs")
    print(table(ev))


def _evaluate_only(out: Path, n_seeds: int) -> None:
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    vecnorm = VecNormalize.load(str(out / "vecnormalize.pkl"), make_vec_env(ENV_ID, n_envs=1))
    vecnorm.training, vecnorm.norm_reward = False, False
    model = PPO.load(out / "policy.zip", device="cpu")
    old = json.loads((out / "evaluation.json").read_text()) if (out / "evaluation.json").exists() else {}
    ev = evaluate(model, vecnorm, range(EVAL_SEED0, EVAL_SEED0 + n_seeds))
    ev.update({k: old[k] for k in ("timesteps", "envs", "train_wall_s", "curve") if k in old})
    (out / "evaluation.json").write_text(json.dumps(ev, indent=1))
    _plot_curve(ev.get("curve", []), ev, out / "learning_curve.png")
    print(table(ev))


def _plot_curve(curve, ev, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    if curve:
        steps, ret = np.array(curve).T
        ax.plot(steps, ret, ".", alpha=0.3, color="C0", label="training episodes")
        k = max(1, len(ret) // 20)
        if len(ret) >= k:
            smooth = np.convolve(ret, np.ones(k) / k, mode="valid")
            ax.plot(steps[k - 1:], smooth, color="C0", label=f"moving mean of {k}")
    ax.axhline(ev["baseline_mean"], color="C3", ls="--", label="payout = walker speed (evaluation mean)")
    if "slant_range_mean" in ev:
        ax.axhline(ev["slant_range_mean"], color="C1", ls=":", label="payout = slant-range rate (evaluation mean)")
    if "slack_pi_mean" in ev:
        ax.axhline(ev["slack_pi_mean"], color="C4", ls="-.", label="SlackPI, tuned (evaluation mean)")
    ax.axhline(ev["policy_mean"], color="C2", ls="-", label="PPO policy (evaluation mean)")
    ax.set_xlabel("environment steps")
    ax.set_ylabel("episode return")
    ax.set_title("PPO on mjtether/TetherWinch-v0")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
