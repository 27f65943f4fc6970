#!/usr/bin/env bash
# Set-up on a fresh Debian 12 machine: installs what is missing, builds tsuchi (Release), and runs
# the main job: the paper's triaxial test 1 (10 kPa confining, cap fixed) to 15 % axial strain,
# writing its frames, recorders and plots under results/triaxial/test1_fixed/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
case_dir=results/triaxial/test1_fixed
./build/app/tsuchi run examples/triaxial/test1_fixed.toml --output "$case_dir"
/usr/bin/python3 examples/triaxial/plot.py results/triaxial test1_fixed
last=$(ls "$case_dir"/particles_*.vtu | tail -n 1)
echo
echo "shear bands in the last frame ($last):"
/usr/bin/python3 tools/bands.py "$last"
echo
echo "results in $case_dir:"
echo "  particles.pvd       the particle frames (one per 1 % axial strain), open in ParaView"
echo "  recorders.csv       axial strain, vertical stress and q of the bottom row, cap displacement"
echo "  global.csv          energies, mass and momentum per time"
echo "  shear_strain.png    maximum shear strain of the deformed specimen at 2, 5, 10, 15 %"
echo "  ../stress_strain.png  q against axial strain, with the Mohr-Coulomb peak"
echo "all six cases and the report: /usr/bin/python3 examples/triaxial/study.py (about 3 min on 2 cores)"
