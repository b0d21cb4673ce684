#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Creates (once) the project-local virtual environment .venv with what the Python checks need,
# installs the project's Python package into it (pip install ., scikit-build-core builds the C++
# module and the pybind11 extension in build-wheel/), and prints its python's path.
# The package is reinstalled only when the sources it is built from change.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$here/.venv"
requirements="$here/tests/python/requirements.txt"
stamp="$venv/.requirements.stamp"
if [ ! -x "$venv/bin/python" ]; then
  echo "[python] creating $venv" >&2
  python3 -m venv "$venv" >&2
fi
if [ ! -f "$stamp" ] || ! cmp -s "$requirements" "$stamp"; then
  echo "[python] installing $(tr '\n' ' ' < "$requirements")" >&2
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$requirements" >&2
  cp "$requirements" "$stamp"
fi

# The dynblur package: rebuilt when any file it is built from changed (content hash).
package_stamp="$venv/.dynblur-package.stamp"
sources_hash="$(cd "$here" && find CMakeLists.txt pyproject.toml modules python -type f \
                  -not -path '*/__pycache__/*' -not -name '*.so' -not -name '*.pyc' -print0 \
                | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)"
if [ ! -f "$package_stamp" ] || [ "$(cat "$package_stamp")" != "$sources_hash" ]; then
  echo "[python] building and installing the dynblur package (pip install .)" >&2
  CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}" \
    "$venv/bin/pip" install -q --disable-pip-version-check --no-deps "$here" >&2
  echo "$sources_hash" > "$package_stamp"
fi
echo "$venv/bin/python"
