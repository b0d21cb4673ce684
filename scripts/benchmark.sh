#!/usr/bin/env bash
# The speed benchmark of issue #8: builds the project (scripts/setup.sh), prepares the Python
# environment (scripts/python_env.sh), then runs scripts/benchmark.py, which runs the C++ benchmark
# program and the Python peers in one run, prints every target with PASS/MISS and writes
# benchmark_out/. Takes about 5 minutes; run it on an otherwise idle machine. Extra arguments go to
# benchmark.py (see --help).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/setup.sh" >&2
python="$("$here/scripts/python_env.sh")"
exec "$python" "$here/scripts/benchmark.py" "$@"
