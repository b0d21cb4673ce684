#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs those of the Debian packages named on the command line that are not installed yet:
# apt-get update, then apt-get install, quiet and non-interactive, through sudo only when not root.
# Used by scripts/setup.sh, scripts/arm_check.sh and scripts/compare_revisions.sh.
#   --check   install nothing: name the missing packages on stderr and exit 1 if there are any
set -euo pipefail
check=0
if [ "${1:-}" = --check ]; then
  check=1
  shift
fi
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$check" -eq 1 ]; then
  echo "[packages] missing Debian packages: ${missing[*]}" >&2
  exit 1
fi
echo "[packages] installing Debian packages: ${missing[*]}"
sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
