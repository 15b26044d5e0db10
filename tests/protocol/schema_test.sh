#!/usr/bin/env bash
# The bounds check's schema table (lcmtypes/lcm_schema.py's output) equals
# lcm-gen's own parse of the .lcm files (lcm-gen -d): every type, field,
# primitive or struct type and array dimension, in order.
# Usage: schema_test.sh LCM_GEN SCHEMA_DUMP FILE.lcm...
set -euo pipefail
lcm_gen=$1 dump=$2
shift 2
normalise() { sed -E 's/ \[hash=[^]]*\]//; s/^[[:space:]]+//; s/[[:space:]]+/ /g; s/ $//'; }
expected=$("$lcm_gen" -d "$@" | normalise | grep -v '^$')
actual=$("$dump" | normalise)
if [ "$expected" != "$actual" ]; then
  echo "schema table differs from lcm-gen -d:" >&2
  diff <(echo "$expected") <(echo "$actual") >&2 || true
  exit 1
fi
echo "schema table matches lcm-gen -d: $(grep -c '^struct' <<<"$actual") types, $(grep -vc '^struct' <<<"$actual") fields"
