#!/usr/bin/env bash
# Runs the whole test suite: installs what is missing, builds (Release), runs ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
