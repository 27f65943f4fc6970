#!/usr/bin/env bash
# Configures and builds tsuchi (Release, warnings as errors) in build/: the one build folder and set
# of flags that setup.sh and test.sh share, so that test.sh after setup.sh has nothing to rebuild.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTSUCHI_WERROR=ON
cmake --build build -j"$(nproc)"
