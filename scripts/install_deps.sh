#!/usr/bin/env bash
# Installs the Debian 12 packages Poise needs. Idempotent: installs only what is missing.
# Without arguments (the first README command): what building and running `poise` needs.
# --tests (the test command): also what only the tests, benchmarks, fuzzers and the Python module
# need.
set -euo pipefail
PKGS=(
  build-essential cmake git pkg-config
  ccache  # every compilation goes through it (CMakeLists.txt): a clean clone reuses the objects
  libeigen3-dev libsundials-dev libnlopt-cxx-dev libembree-dev libtbb-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev librandom123-dev libboost-dev
  libmuparser-dev  # expressions of budget gains (poise budget)
  libfmt-dev  # core/format.h: every number and sentence formatted (fmt::format)
  libhdf5-dev zlib1g-dev  # samples.h5: per-sample grid values of a run (HDF5, deflated chunks)
  libopenmpi-dev openmpi-bin  # runs over MPI ranks (poise is built with MPI where it is found)
  gnuplot-nox  # the report's figures
)
if [ "${1:-}" = "--tests" ]; then
  PKGS+=(
    time  # bench/los_scale: peak memory of a run (GNU time)
    python3-h5py  # samples_h5_test: samples.h5 read as results/README.md shows (h5py)
    libgtest-dev libbenchmark-dev
    clang-14 libclang-rt-14-dev  # tests/fuzz: libFuzzer, ASan, UBSan (clang++-14 -fsanitize=fuzzer)
    python3-numpy python3-scipy  # bench/baselines: the NumPy and SciPy scripts Poise is compared with
    python3-dev pybind11-dev python3-pybind11  # python/: the module build/python/poise (pybind11)
    python3-pytest python3-openturns  # python/tests (pytest) and the OpenTURNS example
    chromium  # tests/reports: every report rendered as a person sees it; the guide's gallery and checks
    mkdocs  # scripts/docs.sh: the guide (docs/), mkdocs build --strict
    clang-format-14 clang-tidy-14  # scripts/check_format.sh (run by test.sh), scripts/check_tidy.sh
  )
fi
missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PKGS[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
