#!/usr/bin/env bash
# Installs the Debian 12 packages tsuchi needs, only those missing (apt-get; root or sudo).
set -euo pipefail
packages=(
  build-essential cmake            # compiler and build system
  libeigen3-dev                    # small fixed-size vectors/tensors, 3x3 eigen-solver
  libtomlplusplus-dev              # input files (TOML, with line numbers for errors)
  libcli11-dev                     # command line
  libfmt-dev                       # formatting
  libmuparser-dev                  # formulas of position in input files (initial velocity)
  zlib1g-dev                       # CRC-32 of checkpoints
  openmpi-bin libopenmpi-dev       # distributed runs (mpirun -np N); the build works without them
  libgtest-dev                     # tests
  clang libclang-rt-14-dev         # fuzzing (scripts/fuzz.sh): clang, its libFuzzer and sanitizer runtimes
  libomp-14-dev                    # clang's OpenMP runtime (gcc's ASan/UBSan come with build-essential)
  python3 python3-numpy python3-matplotlib  # plots of the examples
  python3-scipy                    # the independent band estimate of the tests (tests/band_reference.py)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
