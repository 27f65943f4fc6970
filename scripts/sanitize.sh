#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer
# (gcc, RelWithDebInfo) in build-asan/ and runs it. Every sanitizer report is fatal, so a test that
# triggers one fails. Tests run single-threaded (OMP_NUM_THREADS=1, set per test; the determinism
# test runs two threads), and no suppression is needed.
#
# Left out, for time: the sanitized code runs 10 to 20 times slower than Release.
#   triaxial_reduced_bands  about 4 min alone; its solver paths are run by Triaxial.Reduced* and
#                           the Geomaterial tests, its band analysis by bands_python
#   kill_and_restart        about 1.5 min; and its full-disk case expects frame 1 (step ~20) to be
#                           written before the 0.12 s wall-time checkpoint, which under the
#                           sanitizers comes first
#   triaxial_main_job, triaxial_bands_reference, triaxial_convergence_script
#                           full-size or reduced triaxial runs of 5 to 35 s in Release (minutes
#                           sanitized); the same solver paths as Triaxial.Reduced*
#   AntiLocking.StripFootingNearPrandtl
#                           two footing runs of 5 to 10 s in Release (over 5 min sanitized); the
#                           anti-locking, reaction and damping paths are run by the other
#                           AntiLocking, Reaction and ReleasedVolume tests and column_collapse
#   SupportReaction.FixedBaseCarriesTheWeight, SupportReaction.PlatenBalancesTheBase,
#   Bodies.TunnelExample, Loads.GravityRampReachesTheStateOfConstantGravity,
#   BaseMotion.SlopeOnTheTableCarriesItsWeight
#                           2 to 4 min each sanitized (measured on a loaded host); the support
#                           reaction, driven nodes, shapes, K0 and load paths they run are run by
#                           the other BaseMotion, Bodies and Loads tests (Loads.BaseReaction...,
#                           BaseMotion.ShakenColumn..., Bodies.SlopeExample)
#   SlidingBlock.AccelerationIsCoulombsOnWallAndRigidBase, Contact.OneAndTwoThreadsGiveTheSameBits
#                           12 s and up to 50 s in Release on a loaded host (minutes sanitized);
#                           the contact stage's paths (walls, rigid and deformable partners, every
#                           scheme, 3D, free rigid bodies, damping) are run by the other
#                           SlidingBlock, Contact and DiskCollision tests
#   Restart.ContactContinuesBitwise, Restart.FreeRigidBodyContinuesBitwise
#                           three runs of the program each (44 s and more in Release on a loaded
#                           host); contact keeps no state of its own across a checkpoint, and the
#                           checkpoint paths are run by the other Restart tests
#   bench_quick             tsuchi-bench's small cases (45 s in Release, over the 300 s timeout
#                           sanitized); a benchmark measures nothing under the sanitizers, and its
#                           cases (the triaxial specimen, a 3D block) run what Triaxial.Reduced* and
#                           Verification.* run
#   slope_fos               four factor-of-safety searches (12 s in Release); the stage and
#                           strength-reduction code under it is run by Stages.* and staged
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTSUCHI_SANITIZE=ON
cmake --build build-asan -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:check_initialization_order=1:strict_init_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -E '^(triaxial_reduced_bands|softening_compression|kill_and_restart|triaxial_main_job|triaxial_bands_reference|triaxial_convergence_script|AntiLocking.StripFootingNearPrandtl|SupportReaction.FixedBaseCarriesTheWeight|SupportReaction.PlatenBalancesTheBase|Bodies.TunnelExample|Loads.GravityRampReachesTheStateOfConstantGravity|BaseMotion.SlopeOnTheTableCarriesItsWeight|SlidingBlock.AccelerationIsCoulombsOnWallAndRigidBase|Contact.OneAndTwoThreadsGiveTheSameBits|Restart.ContactContinuesBitwise|Restart.FreeRigidBodyContinuesBitwise|slope_fos|bench_quick)$'
