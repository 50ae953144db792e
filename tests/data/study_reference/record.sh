#!/usr/bin/env bash
# Records samples.csv of every study in plan.txt with the given poise binary:
#   tests/data/study_reference/record.sh build/poise
# Run it only when a change is meant to change the samples (and say so in the commit).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
poise="$(realpath "${1:?usage: record.sh POISE_BINARY}")"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
grep -v '^#' "$here/plan.txt" | while read -r study samples seed; do
  [ -n "$study" ] || continue
  echo "record: $study ($samples samples, seed $seed)"
  (cd "$root" && "$poise" run "studies/$study.toml" --samples "$samples" --seed "$seed" --threads 2 \
     --out "$tmp/$study" --quiet --no-plots > /dev/null)
  cp "$tmp/$study/samples.csv" "$here/$study.csv"
done
