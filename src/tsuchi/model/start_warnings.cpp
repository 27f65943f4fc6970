#include "tsuchi/model/start_warnings.hpp"

#include "tsuchi/model/free_faces.hpp"

#include <fmt/format.h>

#include <array>
#include <cstddef>
#include <map>

namespace tsuchi {

namespace {

// Bodies that lie on a free face: a free face holds nothing (model/free_faces.hpp), so a body
// laid on the bottom of the grid with no [boundary] leaves the grid at its first step (exit 7).
// Said before the run, with the condition the author likely forgot.
template <int D>
void warn_free_faces(const Config& c, const Model<D>& m, std::vector<std::string>& out) {
  const double touch = -1e-6 * m.grid.h;  // a domain within a millionth of a cell of the face
  std::map<std::pair<int, int>, std::size_t> count;  // (body, face) -> particles
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    if (const int face = free_face_reached(m, i, touch); face >= 0) ++count[{m.particles.body_p[i], face}];
  for (const auto& [key, n] : count) {
    const auto [body, face] = key;
    const int d = face / 2;
    const double g = c.gravity[static_cast<std::size_t>(d)];
    const bool towards = face % 2 ? g > 0.0 : g < 0.0;
    out.push_back(fmt::format(
        "{} particle{} of body \"{}\" lie{} on the free face {} of the grid{}: a free face holds nothing, so the "
        "body leaves the grid (exit 7) as soon as it moves across it{}; give the face a condition ([boundary] "
        "{} = \"fixed\" or \"roller\") if the body rests on it, or enlarge grid.extent",
        n, n == 1 ? "" : "s", c.bodies[static_cast<std::size_t>(body)].name, n == 1 ? "s" : "", face_name(face),
        " (no [boundary] condition there)", towards ? ", which gravity makes it do at the first step" : "", face_name(face)));
  }
}

}  // namespace

template <int D>
std::vector<std::string> start_warnings(const Config& c, const Model<D>& m) {
  std::vector<std::string> out;
  warn_free_faces(c, m, out);
  return out;
}

template std::vector<std::string> start_warnings<2>(const Config&, const Model<2>&);
template std::vector<std::string> start_warnings<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
