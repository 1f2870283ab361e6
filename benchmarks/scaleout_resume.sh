#!/bin/bash
# Interrupt a large closed-loop campaign with SIGINT once K of its chunk files are on disk, then
# run the same command again: it resumes from the chunks, and its digest (printed by
# scaleout_campaign.py) equals an uninterrupted run's.
#
# Usage: benchmarks/scaleout_resume.sh DIR [K] [extra scaleout_campaign.py arguments]
#   e.g. benchmarks/scaleout_resume.sh /tmp/c1e6 12 --n 1000000 --t-final 10 --executor dask-local:2 --chunk-size 25000
# A non-interactive shell starts background jobs with SIGINT ignored (and Python then keeps
# ignoring it), so the campaign is started through a one-line Python wrapper that resets SIGINT
# to its default before exec.
set -u
cd "$(dirname "$0")/.."
D=$1; K=${2:-12}; shift; shift || true
CMD=(python benchmarks/scaleout_campaign.py --dir "$D" "$@")
date -u; uptime
python -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execvp(sys.argv[1], sys.argv[1:])' \
    nice -n 5 env PYTHONPATH=src "${CMD[@]}" --json "$D.interrupted.json" > "$D.interrupted.out" 2>&1 &
PID=$!
while [ "$(ls "$D" 2>/dev/null | grep -c '\.pkl$')" -lt "$K" ]; do
    kill -0 $PID 2>/dev/null || { echo "campaign ended before $K chunks"; exit 1; }
    sleep 2
done
date -u; echo "chunks on disk before SIGINT: $(ls "$D" | grep -c '\.pkl$')"; kill -INT $PID
T0=$(date +%s); wait $PID; echo "exit status after SIGINT: $? (returned $(( $(date +%s) - T0 )) s after the signal)"
sleep 2; echo "chunks on disk after the interruption: $(ls "$D" | grep -c '\.pkl$'); temporary files left: $(ls "$D" | grep -c '\.tmp$')"
uptime
/usr/bin/time -v nice -n 5 env PYTHONPATH=src "${CMD[@]}" --json "$D.resumed.json"
echo "exit $?"; date -u; uptime
