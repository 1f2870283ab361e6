#!/usr/bin/env bash
# Run HERE (a machine with PyPI access), in the repository root, before a GPU session:
# downloads into .whl/ the pure-CPU Python packages that the GPU machine's image lacks and
# benchmarks/gpu_session.sh needs (pymoo and its small dependencies; the image already has
# numpy, scipy, numba, numba-cuda, rich, matplotlib, pytest). The GPU machine runs Python
# 3.12 on x86-64 and cannot reach a package index. Keep .whl/ out of git
# (echo /.whl/ >> .git/info/exclude) and carry it to the GPU machine.
set -euo pipefail
cd "$(dirname "$0")/.."
grep -qx '/.whl/' .git/info/exclude 2>/dev/null || echo '/.whl/' >> "$(git rev-parse --git-common-dir)/info/exclude"
mkdir -p .whl
plat=(--platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64
      --platform manylinux2014_x86_64 --platform manylinux1_x86_64 --platform any)
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
  "${plat[@]}" -d .whl \
  pymoo==0.6.2 moocore cffi pycparser platformdirs alive-progress==3.3.0 about-time==4.2.1 \
  graphemeu==0.7.2 autograd cma Deprecated
ls -la .whl
