#pragma once
// A body's particles from a file (`particles = "FILE"` in [[bodies]]): a CSV table, or a .vtu
// frame written by tsuchi (to go on from a deformed state with another model). Errors name the
// particle file, its line (or point) and column, and the input key that named the file.
#include "tsuchi/model/config.hpp"

#include <memory>
#include <string>

namespace tsuchi::io {

struct ParticleFileRequest {
  std::string path;        // as resolved against the input's folder
  std::string key;         // e.g. "bodies.2.particles"
  std::string key_where;   // "FILE:LINE:COL" of the key
  int dimension = 2;
  GridConfig grid;         // every particle must lie inside it
  bool keep_velocity = false;  // .vtu: carry the frame's velocity over
};

std::shared_ptr<const ParticleTable> read_particle_file(const ParticleFileRequest& request);

}  // namespace tsuchi::io
