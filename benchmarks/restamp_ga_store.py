"""Re-stamp the packaged onoff-tuning GA store after a change of its code or libraries.

Runs :func:`adcskit.studies.onoff_tuning.ga_store.restamp` on
``src/adcskit/studies/onoff_tuning/paper_scale_ga`` with the jobs of the study's default
paper-scale run (root seed 0): every stored run is re-evaluated exactly on its training
samples, the runs named by ``--recompute`` are re-run from scratch and compared bit for bit,
and only then are the files given the fingerprint of this installation (their provenance says
what was re-verified and recomputed) and the manifest renewed. Nothing is written on a failure.

Usage:
    PYTHONPATH=src python benchmarks/restamp_ga_store.py --recompute sweep_all_1 s4_all_mean [--note TEXT]
"""

from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))

import argparse  # noqa: E402
import json  # noqa: E402

from adcskit.studies.onoff_tuning.config import Config  # noqa: E402
from adcskit.studies.onoff_tuning.experiment import ga_jobs  # noqa: E402
from adcskit.studies.onoff_tuning.ga_store import PACKAGED, restamp  # noqa: E402


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--directory", default=str(PACKAGED))
    ap.add_argument("--seed", type=int, default=0, help="root seed of the study run the store belongs to")
    ap.add_argument("--recompute", nargs="+", required=True, help="labels of runs to recompute from scratch")
    ap.add_argument("--note", default="")
    args = ap.parse_args(argv)
    out = restamp(args.directory, ga_jobs(Config(paper_scale=True), args.seed), tuple(args.recompute), note=args.note)
    print(json.dumps(out, indent=1), file=sys.stderr)
    return out


if __name__ == "__main__":
    main()
