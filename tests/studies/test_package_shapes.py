"""Issue 20, item 1 ("done when"): every study is a package of paper / config / experiment /
claims / figures / report modules whose ``run`` is orchestration (<= 80 lines), with no function
longer than 120 lines anywhere under ``adcskit.studies``, figures and tables that are pure
functions of the measurement records (no random numbers, no solving, no simulation), and frozen
records."""

from __future__ import annotations

import ast
import dataclasses
import importlib
from pathlib import Path

import pytest

import adcskit.studies

STUDIES_DIR = Path(adcskit.studies.__file__).parent
MODULES = {"__init__", "paper", "config", "experiment", "claims", "figures", "report"}
#: modules a study adds to the six, and why: onoff-tuning keeps its stored paper-scale GA runs
#: (issue 24 item 4; docs/decisions/paper-scale-ga-store.md)
EXTRA_MODULES = {"onoff_tuning": {"ga_store"},
                 "wahba_table1": {"timing", "draws"}}  # speed-600x timing (issue 45); epoch draws shared by both
#: what a pure module must not name: random numbers, and each study's own solvers / simulators
NOT_PURE = {"rng", "default_rng", "random", "measure"}
FORBIDDEN = {
    "wahba_table1": {"solve_wahba", "robust_wahba", "trial", "perturb"},
    "wahba_orbit": {"solve_wahba", "robust_wahba", "propagate_attitude", "simulate_truth", "run_case"},
    "model_estimation": {"joint_estimate", "augmented_ekf", "identify_model", "simulate_linear", "build_case"},
    "rendezvous": {"solve", "solve_adaptive", "solve_multiphase", "run_experiment", "resimulate"},
    "thruster_layout": {"allocate", "design_layout", "score_layout"},
    "onoff_schmitt": {"simulate_batch", "simulate_trace"},
    "onoff_tuning": {"simulate_batch", "simulate_trace", "monte_carlo", "tune_robust", "latin_hypercube"},
    "closed_loop": {"simulate", "simulate_wheels", "sim", "optimal_slew_table", "design_layout"},
}
#: modules that must be pure functions of the records (model-estimation's claims are too)
PURE = {"model_estimation": ("figures", "report", "claims")}


def _function_lengths(path: Path) -> dict[str, int]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {f"{path.stem}.{n.name}": n.end_lineno - n.lineno + 1 for n in ast.walk(tree)
            if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)}


@pytest.mark.parametrize("study", sorted(FORBIDDEN))
def test_study_package_shape(study):
    root = STUDIES_DIR / study
    assert {p.stem for p in root.glob("*.py")} == MODULES | EXTRA_MODULES.get(study, set())
    lengths = {}
    for path in root.glob("*.py"):
        lengths.update(_function_lengths(path))
        if path.stem in PURE.get(study, ("figures", "report")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
            names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
            assert not names & (NOT_PURE | FORBIDDEN[study]), (path.stem, names & (NOT_PURE | FORBIDDEN[study]))
    assert lengths["__init__.run"] <= 80
    assert max(lengths.values()) <= 120, max(lengths.items(), key=lambda kv: kv[1])
    experiment = importlib.import_module(f"adcskit.studies.{study}.experiment")
    for name in experiment.__all__:
        obj = getattr(experiment, name)
        if isinstance(obj, type):
            assert dataclasses.is_dataclass(obj) and obj.__dataclass_params__.frozen, name


def test_every_study_is_a_package():
    modules = {p.stem for p in STUDIES_DIR.glob("*.py") if not p.stem.startswith("_")}
    assert modules == set(), modules  # no study left as a single module
    assert {p.name for p in STUDIES_DIR.iterdir() if (p / "__init__.py").is_file()} == set(FORBIDDEN)


def test_no_long_function_in_the_framework():
    lengths = {}
    for path in STUDIES_DIR.glob("*.py"):
        lengths.update(_function_lengths(path))
    long = {k: v for k, v in lengths.items() if v > 120}
    assert not long, long
