#!/usr/bin/env bash
# Every GPU figure of issue 14 in one go, on a machine with an NVIDIA GPU (e.g. an H100 with
# 16 cores beside it). Writes everything to one folder (default: $OUT if set, else
# gpu_results/):
#   env.txt                 nvidia-smi, numba / numba-cuda versions, the device adcskit sees
#   tests.txt               tests/control/test_onoff_cuda.py with the real device (incl. slow:
#                           GPU == CPU kernel, 1e7 samples in chunks)
#   bench_onoff_cuda.{txt,json}  CPU (all cores) vs GPU sample-steps/s and ratio, registers
#                           and local memory per thread, CPU/GPU agreement
#   paper_scale_tuning.{txt,json}  S4 robust GA at paper scale vs capped, per Table 6 case,
#                           10 000-run evaluations, whether the capped verdicts hold
#
# Needs: numba-cuda (pip install 'adcskit[gpu]'), pymoo. A machine without a package index
# (the workplace's GPU machines) gets pymoo as wheels: run benchmarks/gpu_wheels.sh where pip
# works, carry .whl/, and this script installs them to /tmp/site first.
#
# Usage: bash benchmarks/gpu_session.sh [OUTDIR]      (at most ~9.5 minutes)
#   PAPER_CASES=all,delay,...  subset of the S4 cases (default: all five, "all" first)
#   TEST_TIMEOUT, BENCH_TIMEOUT, PAPER_TIMEOUT  limits in seconds (150, 150, 270: the whole
#   script stays under the 10-minute limit of one device command)
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
timeout "${TEST_TIMEOUT:-150}" "$PY" -m pytest -q -p no:cacheprovider tests/control/test_onoff_cuda.py \
  -m "slow or not slow" 2>&1 | tee "$OUTDIR/tests.txt"

echo "== benchmark: CPU all cores vs GPU =="
timeout "${BENCH_TIMEOUT:-150}" "$PY" benchmarks/bench_onoff.py --backend cuda --json "$OUTDIR/bench_onoff_cuda.json" \
  2>&1 | tee "$OUTDIR/bench_onoff_cuda.txt"

echo "== paper-scale robust tuning (S4) =="
timeout "${PAPER_TIMEOUT:-270}" "$PY" benchmarks/paper_scale_tuning.py --backend cuda \
  --cases "${PAPER_CASES:-all,inertia,thrust,disturbance,delay}" --out "$OUTDIR" \
  2>&1 | tee "$OUTDIR/paper_scale_tuning.txt"
echo "results in $OUTDIR"
ls -la "$OUTDIR"
