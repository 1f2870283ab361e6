"""The kernels' declared array tables (issue 41: "one declared table per kernel").

Each closed-loop kernel lists its arrays once (``ARGS``); the argument tuple, the allocations,
the CUDA signature and the GPU transfers are made from it. Checked here without compiling a
kernel: the tuple's fields are the table's names in order, every array ``allocate_arrays``
makes (with the inputs of the real set-up, ``_prepare``) has the declared rank and dtype and
one row per sample where declared, every ``"in"`` array is an input that ``_prepare`` fills,
and the CUDA signature has one C-contiguous array type per entry.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import types as t

from adcskit._validation import as_rng
from adcskit.simulation import EstimatorSpec, Scenario, SimSpec, WheelScenario, core
from adcskit.simulation import _kernels as K
from adcskit.simulation import _wheel_kernels as WK
from adcskit.simulation import wheels as W

_DT = {"f8": np.float64, "u8": np.uint64}


def _thruster_arrays(record):
    sc = Scenario(sim=SimSpec(dt=0.05, t_final=1.0, metrics_from_s=0.5), estimator=EstimatorSpec(kind="mekf"))
    prep, _ = core._prepare(sc, 3, as_rng(1))
    sh, ps = prep["shared"], prep["per_sample"]
    n_rec = sh["n_steps"] // int(sh["C"][K.REC_EVERY]) + 1 if record else 0
    dims = K.Dims(n=3, nt=sh["POS"].shape[0], buf_len=sh["buf_len"], n_rec=n_rec)
    seeds = np.arange(3, dtype=np.uint64)
    return K.allocate_arrays({**sh, **ps, "SEEDS": seeds}, dims)


def _wheel_arrays(record):
    sc = WheelScenario(sim=SimSpec(dt=0.2, t_final=4.0, metrics_from_s=2.0), estimator=EstimatorSpec(kind="mekf"))
    prep, _ = W._prepare(sc, 3, as_rng(1))
    sh = prep["shared"]
    n_rec = sh["n_steps"] // int(sh["C"][WK.REC_EVERY]) + 1 if record else 0
    dims = WK.Dims(n=3, nw=sh["JW"].shape[0], nt=sh["THR"].shape[1], n_rec=n_rec, filt=True)
    seeds = np.arange(3, dtype=np.uint64)
    return WK.allocate_arrays({**sh, "P": prep["P"], "AX": prep["AX"], "SEEDS": seeds}, dims)


@pytest.mark.parametrize("record", [True, False])
@pytest.mark.parametrize(("mod", "make"), [(K, _thruster_arrays), (WK, _wheel_arrays)])
def test_allocated_arrays_follow_the_table(mod, make, record):
    A = make(record)
    assert A._fields == tuple(a.name for a in mod.ARGS)
    for a, x in zip(mod.ARGS, A):
        assert x.ndim == a.ndim and x.dtype == _DT[a.dtype], a.name
        assert x.flags.c_contiguous, a.name
        if a.rows:
            # the thruster kernel's REC has no rows when not recording (its "record" flag)
            empty = mod is K and a.name == "REC" and not record
            assert x.shape[0] == (0 if empty else 3), a.name
    assert (A.REC.size > 0) == record


@pytest.mark.parametrize("mod", [K, WK])
def test_cuda_signature_follows_the_table(mod):
    (sig,) = mod._cuda_signature()
    assert isinstance(sig, t.NamedTuple) and sig.instance_class is mod.Arrays
    assert len(sig.types) == len(mod.ARGS)
    for a, ty in zip(mod.ARGS, sig.types):
        assert ty.ndim == a.ndim and ty.layout == "C" and str(ty.dtype) == {"f8": "float64", "u8": "uint64"}[a.dtype]


def test_table_entries_are_unique_and_roles_known():
    for mod in (K, WK):
        names = [a.name for a in mod.ARGS]
        assert len(set(names)) == len(names)
        assert {a.role for a in mod.ARGS} <= {"in", "scratch", "out"}
        assert all(a.shape is not None for a in mod.ARGS if a.role != "in")
