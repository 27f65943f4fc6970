// libFuzzer target for the checkpoint reader: decode_checkpoint on arbitrary bytes, with the
// checksum check off (a mutated file would otherwise never get past it; a hostile file can carry
// a right checksum anyway). The dimension field of the header picks the 2D or the 3D model, so
// real checkpoints of both are seeds as they are. A refused file must end in InputError and leave
// the model as it was; an accepted one must be a state the solver can step from: one explicit
// step is taken, which may end in RunError (a blown-up state is a fault the run reports) but must
// not read or write out of bounds.
#include "fuzz_models.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/io/checkpoint.hpp"
#include "tsuchi/solver/explicit_step.hpp"
#include "tsuchi/solver/time_step.hpp"

#include <omp.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace {

using namespace tsuchi;

template <int D>
void decode_into(std::string_view bytes, const Model<D>& pristine) {
  Model<D> m = pristine;
  RunProgress r;
  try {
    r = decode_checkpoint<D>(bytes, "fuzz.tsuchi", m, /*verify_checksum=*/false);
  } catch (const InputError&) {
    // Refused: the model must be untouched.
    if (m.particles.x_p != pristine.particles.x_p || m.particles.id_p != pristine.particles.id_p) {
      std::fprintf(stderr, "decode_checkpoint changed the model and then threw\n");
      std::abort();
    }
    return;
  }
  if (m.particles.size() != pristine.particles.size()) {
    std::fprintf(stderr, "decode_checkpoint accepted another particle count\n");
    std::abort();
  }
  ExplicitSolver<D> solver(m);
  solver.resume(r.time, r.steps);
  try {
    const double dt = critical_time_step<D>(m.particles, m.materials, m.grid.h);
    if (std::isfinite(dt) && dt > 0.0) solver.step(0.5 * dt);
  } catch (const RunError&) {
  }
}

const Model<2>& model2() {
  static const Model<2> m = fuzz::small_model<2>();
  return m;
}
const Model<3>& model3() {
  static const Model<3> m = fuzz::small_model<3>();
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  omp_set_num_threads(1);  // one input at a time, as fast as it goes; no thread pool to wake
  model2();
  model3();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::uint32_t dim = 2;
  if (size >= 16) std::memcpy(&dim, data + 12, 4);
  if (dim == 3) decode_into<3>(bytes, model3());
  else decode_into<2>(bytes, model2());
  return 0;
}
