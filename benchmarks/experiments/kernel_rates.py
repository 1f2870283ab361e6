"""Sample-steps per CPU-second of bench_basilisk.py's two scenarios and of profile variants.

Variants: full (the full chain), full_rec (with traces), full_nonees (no NEES), full_sunonly
(no magnetometer), truth_schmitt (truth estimator), truth_idle (truth, thrusters never
fire), same (same elements as Basilisk). Prints JSON: per variant [median, runs...]::

    PYTHONPATH=src python benchmarks/experiments/kernel_rates.py 3 full,same
"""

import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # benchmarks/
from adcskit.simulation import ControllerSpec, EstimatorSpec, simulate
from bench_basilisk import _speed_scenarios

same, full = _speed_scenarios(150.0)
V = {
    "full": (full, False),
    "full_rec": (full, True),
    "full_nonees": (full.replace(sim=full.sim.replace(nees_from_s=150.0)), False),
    "full_sunonly": (full.replace(sensors=full.sensors.replace(mag_rate_hz=0.0)), False),
    "truth_schmitt": (full.replace(estimator=EstimatorSpec(kind="truth")), False),
    "truth_idle": (
        full.replace(
            estimator=EstimatorSpec(kind="truth"),
            controller=ControllerSpec(kind="open-loop", on_times=((0.0,) * 6,)),
        ),
        False,
    ),
    "same": (same, False),
}
R = int(sys.argv[1])
names = sys.argv[2].split(",")
n = 512
for nm in names:
    sc, rec = V[nm]
    simulate(sc, 64, rng=0, record=rec)
res = {nm: [] for nm in names}
for r in range(R):
    for nm in names:
        sc, rec = V[nm]
        c0 = time.process_time()
        out = simulate(sc, n, rng=100 + r, record=rec)
        res[nm].append(n * out.n_steps / (time.process_time() - c0))
print(json.dumps({nm: [float(np.median(v))] + v for nm, v in res.items()}))
