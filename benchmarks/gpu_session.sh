#!/usr/bin/env bash
# Every GPU figure of issue 14 in one go, on a machine with an NVIDIA GPU (e.g. an H100 with
# 16 cores beside it). Writes everything to one folder (default: $OUT if set, else
# gpu_results/):
#   env.txt                 nvidia-smi, numba / numba-cuda versions, the device adcskit sees
#   tests.txt               the CUDA tests with the real device: the on-off kernel
#                           (tests/control/test_onoff_cuda.py, incl. slow: GPU == CPU kernel,
#                           1e7 samples in chunks) and both simulators
#                           (tests/simulation/test_{wheels,simulate}_cuda.py -k real_gpu: GPU vs
#                           CPU; their CUDA-simulator tests run in CI)
#   bench_onoff_cuda.{txt,json}  CPU (all cores) vs GPU sample-steps/s and ratio, registers
#                           and local memory per thread, CPU/GPU agreement
#   paper_scale_tuning.{txt,json}  S4 robust GA at paper scale vs capped, per Table 6 case,
#                           10 000-run evaluations, whether the capped verdicts hold
#   bench_simulators_gpu.{txt,json}  thruster closed loop and wheel loop: CPU (all cores)
#                           vs GPU sample-steps/s and ratio, CPU/GPU agreement
#
# The CPU kernels of the two simulators compile (not cached on a fresh machine: minutes for
# the closed loop) on one core in the background during the paper-scale tuning.
#
# Needs: numba-cuda (pip install 'adcskit[gpu]'), pymoo. A machine without a package index
# (the workplace's GPU machines) gets pymoo as wheels: run benchmarks/gpu_wheels.sh where pip
# works, carry .whl/, and this script installs them to /tmp/site first.
#
# Usage: bash benchmarks/gpu_session.sh [OUTDIR]      (at most ~9.5 minutes)
#   PAPER_CASES=all,delay,...  subset of the S4 cases (default: all five, "all" first)
#   TEST_TIMEOUT, SIM_TEST_TIMEOUT, BENCH_TIMEOUT, PAPER_TIMEOUT, SIM_TIMEOUT  limits in
#   seconds (75, 100, 75, 200, 110; with the background compile's 215 s that overlaps the
#   paper-scale tuning, at most 585 s: under the 10-minute limit of one device command). The
#   simulator tests and benchmark each compile the CUDA kernels (one to two minutes for the
#   closed loop, NVVM); the benchmark comes last and writes its JSON after each part.
set -uo pipefail
cd "$(dirname "$0")/.."
OUTDIR="${1:-${OUT:-gpu_results}}"
mkdir -p "$OUTDIR"
export PYTHONUNBUFFERED=1
export PYTHONPATH="$PWD/src${PYTHONPATH:+:$PYTHONPATH}"
PY="${PYTHON:-python3}"
if [ -d .whl ] && ls .whl/*.whl >/dev/null 2>&1; then
  "$PY" -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
    --target /tmp/site .whl/*.whl && export PYTHONPATH="$PYTHONPATH:/tmp/site"
fi
{
  date -u
  nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv 2>&1
  nproc
  "$PY" -c "import numba; print('numba', numba.__version__)"
  "$PY" -c "import numba_cuda; print('numba-cuda', numba_cuda.__version__)" 2>&1
  "$PY" -c "from adcskit import _targets; print('adcskit sees:', _targets.cuda_status())"
} 2>&1 | tee "$OUTDIR/env.txt"


echo "== tests (real device) =="
timeout "${TEST_TIMEOUT:-75}" "$PY" -m pytest -q -p no:cacheprovider tests/control/test_onoff_cuda.py \
  -m "slow or not slow" 2>&1 | tee "$OUTDIR/tests.txt"

echo "== benchmark: CPU all cores vs GPU =="
timeout "${BENCH_TIMEOUT:-75}" "$PY" benchmarks/bench_onoff.py --backend cuda --json "$OUTDIR/bench_onoff_cuda.json" \
  2>&1 | tee "$OUTDIR/bench_onoff_cuda.txt"

# the simulators' CPU kernels compile into numba's disk cache on one core while the GPU
# runs the paper-scale tuning (after the on-off CPU benchmark, which wants every core)
NUMBA_NUM_THREADS=1 timeout 215 "$PY" -c "
from adcskit.simulation import ModeSpec, Scenario, SimSpec, WheelScenario, simulate, simulate_wheels
simulate(Scenario(sim=SimSpec(dt=0.02, t_final=0.2, metrics_from_s=0.1)), 2, rng=0)
simulate_wheels(WheelScenario(modes=ModeSpec(initial='point', sequence=False),
                              sim=SimSpec(dt=0.2, t_final=2.0, metrics_from_s=1.0)), 2, rng=0)
print('CPU kernels of the simulators compiled')" > "$OUTDIR/warm_cpu_kernels.txt" 2>&1 &
WARM=$!

echo "== paper-scale robust tuning (S4) =="
timeout "${PAPER_TIMEOUT:-200}" "$PY" benchmarks/paper_scale_tuning.py --backend cuda \
  --cases "${PAPER_CASES:-all,inertia,thrust,disturbance,delay}" --out "$OUTDIR" \
  2>&1 | tee "$OUTDIR/paper_scale_tuning.txt"

echo "== tests of the simulators (real device) =="
wait "$WARM"; cat "$OUTDIR/warm_cpu_kernels.txt"
timeout "${SIM_TEST_TIMEOUT:-100}" "$PY" -m pytest -q -p no:cacheprovider tests/simulation/test_wheels_cuda.py \
  tests/simulation/test_simulate_cuda.py -k real_gpu 2>&1 | tee -a "$OUTDIR/tests.txt"

echo "== benchmark: simulators, CPU all cores vs GPU =="
timeout "${SIM_TIMEOUT:-110}" "$PY" benchmarks/bench_simulators_gpu.py --json "$OUTDIR/bench_simulators_gpu.json" \
  2>&1 | tee "$OUTDIR/bench_simulators_gpu.txt"
echo "results in $OUTDIR"
ls -la "$OUTDIR"
