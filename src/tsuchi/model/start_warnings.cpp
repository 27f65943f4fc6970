#include "tsuchi/model/start_warnings.hpp"

#include "tsuchi/model/free_faces.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <unordered_set>

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

// Free rigid bodies lighter than the soil around them: the body's velocity takes M dV/dt = F + M g
// explicitly (eq R3 of solver/explicit_step.cpp), with F the contact force of the nodes it shares,
// so a mass M below the mass of those nodes amplifies each step's velocity jump and the body rings
// out of the grid (issue 41: M 1e-9 times the soil's left it at step 15; rigid_block.toml at
// 8e-8 kg/m at step 30). The nodes it touches are not known before the step; the soil within a
// cell of its particles (the cells its particles lie in, grown by one cell each way) stands for
// them. A body that touches nothing at the start is not judged.
template <int D>
void warn_light_rigid_bodies(const Config& c, const Model<D>& m, std::vector<std::string>& out) {
  const auto& p = m.particles;
  const auto& g = m.grid;
  auto cell = [&](std::size_t i, const std::array<int, D>& shift) {
    std::int64_t key = 0;
    for (int d = 0; d < D; ++d)
      key = key * (g.n_nodes[d] + 2) +
            (std::clamp(static_cast<int>(std::floor((p.x_p[i][d] - g.origin[d]) * g.inv_h)), 0, g.n_nodes[d] - 2) +
             shift[d] + 1);
    return key;
  };
  for (std::size_t b = 0; b < m.motion.size(); ++b) {
    const double M = m.motion[b].rigid_mass;
    if (!(M > 0.0)) continue;
    std::unordered_set<std::int64_t> near;
    double own = 0.0;  // its particles' mass, what the body would weigh at its material's density
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (static_cast<std::size_t>(p.body_p[i]) != b) continue;
      own += p.m_p[i];
      std::array<int, D> shift{};
      for (int k = 0; k < (D == 2 ? 9 : 27); ++k) {
        for (int d = 0, r = k; d < D; ++d, r /= 3) shift[d] = r % 3 - 1;
        near.insert(cell(i, shift));
      }
    }
    std::map<int, double> soil;  // body -> mass within a cell of body b
    const std::array<int, D> here{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto other = static_cast<std::size_t>(p.body_p[i]);
      const auto& mo = m.motion[other];
      if (other == b || mo.rigid_mass > 0.0 || mo.fully_prescribed()) continue;  // rigid bodies do not act on each other
      if (near.count(cell(i, here))) soil[p.body_p[i]] += p.m_p[i];
    }
    double total = 0.0;
    for (const auto& [body, mass] : soil) total += mass;
    if (!(M < total)) continue;
    const auto heaviest = std::max_element(soil.begin(), soil.end(), [](const auto& a, const auto& z) { return a.second < z.second; });
    const char* unit = D == 2 ? "kg/m" : "kg";
    out.push_back(fmt::format(
        "free rigid body \"{}\" (rigid_mass = {:g} {}) is lighter than the soil within a cell of it ({:.4g} {}, "
        "most of it of body \"{}\"): its velocity is updated explicitly from the contact force, so a body lighter "
        "than the nodes it touches rings and leaves the grid; give rigid_mass well above {:.4g} {} (its particles "
        "weigh {:.4g} {}), or model it as a deformable body of a stiff material",
        c.bodies[b].name, M, unit, total, unit, c.bodies[static_cast<std::size_t>(heaviest->first)].name, total, unit,
        own, unit));
  }
}

}  // namespace

template <int D>
std::vector<std::string> start_warnings(const Config& c, const Model<D>& m) {
  std::vector<std::string> out;
  warn_free_faces(c, m, out);
  warn_light_rigid_bodies(c, m, out);
  return out;
}

template std::vector<std::string> start_warnings<2>(const Config&, const Model<2>&);
template std::vector<std::string> start_warnings<3>(const Config&, const Model<3>&);

}  // namespace tsuchi
