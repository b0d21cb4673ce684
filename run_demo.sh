#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job: builds the project (installing what it needs) and runs the deblurring demo.
# Extra arguments go to the demo (see ./run_demo.sh --help).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/scripts/setup.sh" >&2
build="${DYNBLUR_BUILD_DIR:-$here/build}"
exec "$build/samples/dynblur_demo" "$@"
