#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Every source file of the project states its licence in an SPDX line near its top (LICENSE holds
# the text). --check (the default; CTest's LicenceHeaders runs it) lists the files without one and
# exits 1; --add writes the line into them: `//` for C and C++, `#` for Python, shell and CMake,
# after a shebang line where there is one.
set -euo pipefail
usage() { sed -n '3,6p' "$0" | sed 's/^# \{0,1\}//'; echo "usage: $0 [--check | --add]"; }
mode=check
case "${1:---check}" in
  --check) mode=check ;;
  --add) mode=add ;;
  -h|--help) usage; exit 0 ;;
  *) echo "$0: unknown option '$1' (allowed: --check, --add)" >&2; exit 2 ;;
esac
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
line="SPDX-License-Identifier: Apache-2.0"

# The project's own sources; test inputs (fuzz corpora, recordings) and generated files have none.
list_sources() {
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files
  else
    find . -type f -not -path './.git/*' -not -path './build*' -not -path './.venv/*' | sed 's|^\./||'
  fi | grep -E '(\.(cpp|hpp|h|py|pyi|sh|cmake)|(^|/)CMakeLists\.txt)$' | grep -v -E '^(build|fuzz/corpus)/'
}

missing=()
while IFS= read -r file; do
  [ -f "$file" ] || continue
  head -n 3 "$file" | grep -q "$line" && continue
  missing+=("$file")
done < <(list_sources)

if [ "$mode" = check ]; then
  if [ "${#missing[@]}" -eq 0 ]; then
    echo "licence headers: every source file has '$line'"
    exit 0
  fi
  echo "licence headers: ${#missing[@]} source file(s) without '$line' in their first 3 lines" \
       "(scripts/licence_headers.sh --add writes it):"
  printf '  %s\n' "${missing[@]}"
  exit 1
fi

for file in "${missing[@]}"; do
  case "$file" in
    *.cpp|*.hpp|*.h) comment="// $line" ;;
    *) comment="# $line" ;;
  esac
  tmp="$(mktemp "$file.XXXXXX")"
  if head -n 1 "$file" | grep -q '^#!'; then
    { head -n 1 "$file"; echo "$comment"; tail -n +2 "$file"; } >"$tmp"
  else
    { echo "$comment"; cat "$file"; } >"$tmp"
  fi
  chmod --reference="$file" "$tmp"
  mv "$tmp" "$file"
done
echo "licence headers: added to ${#missing[@]} file(s)"
