#include "tsuchi/io/shape_reader.hpp"

#include "tsuchi/geometry/box.hpp"

namespace tsuchi::io {

namespace {

geometry::ShapePtr read_box(Section& s, int dim) {
  const Triple lo = s.vector("min", dim, "m", any);
  const Triple hi = s.vector("max", dim, "m", any);
  for (int d = 0; d < dim; ++d)
    if (hi[d] <= lo[d])
      s.fail("max", fmt::format("expected max > min along {}, got {} <= {}", axis_name[d], hi[d], lo[d]));
  geometry::Point a = geometry::Point::Zero(), b = geometry::Point::Zero();
  for (int d = 0; d < dim; ++d) a[d] = lo[d], b[d] = hi[d];
  return std::make_shared<geometry::Box>(a, b, dim);
}

}  // namespace

geometry::ShapePtr read_shape(Section& s, int dim, const std::string& /*directory*/) {
  s.choice("shape", {"box"}, 0);
  return read_box(s, dim);
}

}  // namespace tsuchi::io
