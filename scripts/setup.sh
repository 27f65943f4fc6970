#!/usr/bin/env bash
# Set-up on a fresh Debian 12 machine: installs what is missing, builds tsuchi (Release), and runs
# the main example, writing its results and plot under results/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
example=examples/column_self_weight
./build/app/tsuchi run "$example/column.toml" --output results/column
/usr/bin/python3 "$example/plot.py" results/column
echo
echo "results: results/column (particles.pvd for ParaView, global.csv, stress_profile.png)"
