#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The speed benchmark (docs/performance.md): builds the project (scripts/setup.sh), prepares the Python
# environment (scripts/python_env.sh), then runs scripts/benchmark.py, which runs the C++ benchmark
# program and the Python peers in one run, prints every target with its verdict and writes
# benchmark_out/. Takes about 5 minutes; run it on an otherwise idle machine. Exits 1 only when a held
# target fails (the out-of-reach scikit-image target and the absolute frame time are reported).
# --ci: the short check run_tests.sh runs (paired rounds of the row-wise restoration and its filter2D
# peer, ratio only, under a minute). Extra arguments go to benchmark.py (see --help).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/setup.sh" >&2
python="$("$here/scripts/python_env.sh")"
exec "$python" "$here/scripts/benchmark.py" "$@"
