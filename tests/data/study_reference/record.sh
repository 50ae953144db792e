#!/usr/bin/env bash
# Records samples.csv of every shipped study (studies/*.toml with a [study] table; samples and
# seed from plan.txt, else 2 and 11) with the given poise binary (files over 200 kB as their
# SHA-1) and, for a study with wide values in samples.h5, the digest of its values:
#   tests/data/study_reference/record.sh build/poise               # every study
#   tests/data/study_reference/record.sh build/poise my_new_study  # only these
# Run it only when a change is meant to change the samples (and say so in the commit). The
# shipped studies' own programs (kind = "external") are ours: they run with --allow-programs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
poise="$(realpath "${1:?usage: record.sh POISE_BINARY}")"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
shift
wanted=" $* "
for file in "$root"/studies/*.toml; do
  grep -q '^\[study\]' "$file" || continue  # an optimization file
  study="$(basename "$file" .toml)"
  [ "$wanted" = "  " ] || [[ "$wanted" == *" $study "* ]] || continue
  samples=""; seed=""
  read -r samples seed < <(awk -v s="$study" '$1 == s { print $2, $3 }' "$here/plan.txt") || true
  samples="${samples:-2}"
  seed="${seed:-11}"
  echo "record: $study ($samples samples, seed $seed)"
  if grep -q '^kind = "python"' "$file"; then
    # A Python function's study (its function `model` in models/<study>.py) runs from Python,
    # through the module built beside the binary; python/tests checks its reference.
    PYTHONPATH="$(dirname "$poise")/python" /usr/bin/python3 - "$root" "$study" "$samples" "$seed" "$tmp/$study" <<'PY'
import os, runpy, sys
import poise
root, study, samples, seed, out = sys.argv[1:]
os.chdir(root)
f = runpy.run_path("models/" + study + ".py")["model"]
poise.run("studies/" + study + ".toml", samples=int(samples), seed=int(seed), threads=2, out=out, model=f)
PY
  else
    (cd "$root" && "$poise" run "studies/$study.toml" --samples "$samples" --seed "$seed" --threads 2 --allow-programs \
       --out "$tmp/$study" --quiet --no-plots > /dev/null)
  fi
  rm -f "$here/$study.csv" "$here/$study.sha1"
  if [ "$(stat -c %s "$tmp/$study/samples.csv")" -le 200000 ]; then
    cp "$tmp/$study/samples.csv" "$here/$study.csv"
  else  # a large file is kept as its SHA-1 only
    sha1sum "$tmp/$study/samples.csv" | cut -d' ' -f1 > "$here/$study.sha1"
  fi
  # A run with wide data (samples.h5) records the digest of its values (summary.json).
  rm -f "$here/$study.h5.digest"
  if grep -q '"values_digest"' "$tmp/$study/summary.json"; then
    grep -o '"values_digest": "[0-9a-f]*"' "$tmp/$study/summary.json" | cut -d'"' -f4 > "$here/$study.h5.digest"
  fi
done
