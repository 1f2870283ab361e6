"""S4's robust tuning at the paper's full settings, next to the capped setting of the study.

For each uncertainty case of S4 Table 6 (inertia, thrust, disturbance, delay, all four; the
printed weight ratios w2/w1 = 25, 22, 15, 10, 180) this runs the robust GA twice on the
same machine and backend:

* paper scale (:data:`adcskit.control.tuning.PAPER_SCALE`): population 70, the S4
  stopping rule with the 1000-generation cap, 1000 LHS samples per candidate;
* capped (the onoff-tuning study's 2-core GA): population 70, ``--capped-gen`` generations
  (default 30, the study's ``ga_max_gen``), ``--capped-samples`` LHS samples (default 40,
  its ``n_lhs``);

then evaluates both gain triples and S4's deterministic minimum-error gains (Table 4, read
as (K_p, K_i, K_d) = (56.24, 0.02, 49.99)) with the same 10 000-run LHS Monte-Carlo, and
reports whether the capped run's verdict -- "the robust gains have a smaller spread
(std of the per-run error) than the deterministic gains" (S4 Figs. 15-19) -- holds at
paper scale. A time estimate from a short calibration run is printed first, and the GA
shows a progress bar.

Usage:
    python benchmarks/paper_scale_tuning.py [--backend auto|cpu|cuda] [--cases all,delay,...]
        [--out DIR] [--capped-gen 30] [--capped-samples 40] [--smoke]

``--smoke`` shrinks every size (seconds on 2 cores) to check the script itself. Without a
GPU the paper-scale run is runnable but long (the estimate says how long).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

from adcskit._progress import progress_session, status  # noqa: E402
from adcskit._targets import resolve_backend  # noqa: E402
from adcskit.control import LoopSettings  # noqa: E402
from adcskit.control.tuning import (  # noqa: E402
    PAPER_SCALE,
    RobustTuningScale,
    estimate_tuning_time,
    monte_carlo,
    tune_robust,
)
from adcskit.uncertainty import Gaussian, TruncatedGaussian  # noqa: E402

# S4 Table 5 standard deviations around the Table 3 means; inertia, thrust level and delay
# truncated to stay positive (as in the onoff-tuning study)
TABLE5 = {
    "inertia": TruncatedGaussian(mean=10.0, std=2.0, low=0.5),
    "torque": TruncatedGaussian(mean=1.0, std=0.2, low=0.05),
    "disturbance": Gaussian(mean=0.05, std=0.05),
    "delay": TruncatedGaussian(mean=0.02, std=0.01, low=0.0),
}
CASES = {  # S4 Table 6: uncertain parameters and printed weight ratio w2/w1
    "inertia": (("inertia",), 25.0),
    "thrust": (("torque",), 22.0),
    "disturbance": (("disturbance",), 15.0),
    "delay": (("delay",), 10.0),
    "all": (("inertia", "torque", "disturbance", "delay"), 180.0),
}
DETERMINISTIC = (56.24, 0.02, 49.99)  # S4 Table 4 minimum-error point, (K_p, K_i, K_d)


def _run_case(case, scale, settings, backend, seed):
    names, ratio = CASES[case]
    dists = {k: TABLE5[k] for k in names}
    t0 = time.perf_counter()
    r = tune_robust(dists, ratio=ratio, settings=settings, backend=backend, rng=seed,
                    **scale.tune_kwargs())
    t_tune = time.perf_counter() - t0
    return r, t_tune, dists


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backend", default="auto", choices=("auto", "cpu", "cuda"))
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated subset of " + ",".join(CASES))
    ap.add_argument("--out", default=None, help="folder for paper_scale_tuning.json")
    ap.add_argument("--seed", type=int, default=2017)
    ap.add_argument("--capped-gen", type=int, default=30, help="generation cap of the capped GA")
    ap.add_argument("--capped-samples", type=int, default=40, help="LHS samples of the capped GA")
    ap.add_argument("--smoke", action="store_true", help="tiny sizes: checks the script only")
    args = ap.parse_args(argv)
    cases = [c.strip() for c in args.cases.split(",") if c.strip()]
    unknown = set(cases) - set(CASES)
    if unknown:
        ap.error(f"unknown cases {sorted(unknown)}; choose from {', '.join(CASES)}")
    backend = resolve_backend(args.backend)
    if args.smoke:
        paper = RobustTuningScale(pop_size=6, max_gen=3, n_samples=6, n_eval=60)
        capped = RobustTuningScale(pop_size=6, max_gen=2, n_samples=3, n_eval=60)
        settings = LoopSettings(t_final=2.0, t_window=1.0)
    else:
        capped = RobustTuningScale(pop_size=PAPER_SCALE.pop_size, max_gen=args.capped_gen,
                                   n_samples=args.capped_samples, n_eval=PAPER_SCALE.n_eval)
        paper, settings = PAPER_SCALE, LoopSettings()
    out: dict = {"backend": backend, "paper_scale": paper.to_dict(), "capped": capped.to_dict(),
                 "settings": settings.to_dict(), "cases": {}}
    with progress_session():
        est = estimate_tuning_time(paper, settings=settings, backend=backend)
        status(f"per case: {est.message}")
        status(f"all {len(cases)} cases: worst case ~ {est.total_max_s * len(cases) / 3600:.2f} h")
        out["estimate_per_case"] = est.to_dict()
        for i, case in enumerate(cases):
            row: dict = {"ratio": CASES[case][1]}
            for label, scale in (("capped", capped), ("paper", paper)):
                r, t_tune, dists = _run_case(case, scale, settings, backend, args.seed + i)
                row[label] = {"x": r.x.tolist(), "fun": r.fun, "nit": r.nit, "success": r.success,
                              "message": r.message, "tune_s": t_tune}
            t0 = time.perf_counter()
            for label, gains in (("capped", row["capped"]["x"]), ("paper", row["paper"]["x"]),
                                 ("deterministic", list(DETERMINISTIC))):
                mc = monte_carlo(gains, dists, paper.n_eval, settings=settings, backend=backend,
                                 rng=args.seed + 100 + i)
                row.setdefault("mc", {})[label] = {"mean_abs_err_deg": mc.mean_abs_err_deg,
                                                   "std_abs_err_deg": mc.std_abs_err_deg}
            row["mc_s"] = time.perf_counter() - t0
            mc = row["mc"]
            v_cap = mc["capped"]["std_abs_err_deg"] < mc["deterministic"]["std_abs_err_deg"]
            v_pap = mc["paper"]["std_abs_err_deg"] < mc["deterministic"]["std_abs_err_deg"]
            row["verdict_robust_spread_smaller"] = {"capped": v_cap, "paper": v_pap,
                                                    "holds_at_paper_scale": v_cap == v_pap}
            out["cases"][case] = row
            _write(args.out, out)  # after every case: a run cut short keeps what it finished
            status(f"{case}: capped x={np.round(row['capped']['x'], 3).tolist()} "
                   f"paper x={np.round(row['paper']['x'], 3).tolist()} "
                   f"(nit {row['paper']['nit']}, {row['paper']['message']}); std |e| (deg) "
                   f"det {mc['deterministic']['std_abs_err_deg']:.4g}, capped "
                   f"{mc['capped']['std_abs_err_deg']:.4g}, paper {mc['paper']['std_abs_err_deg']:.4g}; "
                   f"verdict holds: {v_cap == v_pap}")
    for case, row in out["cases"].items():
        print(f"{case:>12}: tune {row['paper']['tune_s']:.1f} s (paper) / {row['capped']['tune_s']:.1f} s "
              f"(capped); verdict 'robust spread < deterministic' capped={row['verdict_robust_spread_smaller']['capped']} "
              f"paper={row['verdict_robust_spread_smaller']['paper']}")
    _write(args.out, out)
    return out


def _write(folder: str | None, out: dict) -> None:
    if folder:
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "paper_scale_tuning.json"), "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2)
            fh.write("\n")


if __name__ == "__main__":
    main()
