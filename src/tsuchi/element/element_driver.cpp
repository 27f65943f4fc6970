#include "tsuchi/element/element_driver.hpp"

#include "tsuchi/core/errors.hpp"
#include "tsuchi/core/principal_frame.hpp"

#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <string_view>
#include <cmath>
#include <string>
#include <variant>

namespace tsuchi::element {

namespace {

using Stiffness = Eigen::Matrix<double, 6, 6>;
// At most six unknowns: fixed-capacity storage keeps the iteration free of heap traffic.
using VecU = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using MatU = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

// The stress and the material state (its model's fields, material/state_field.hpp) of the point.
template <class Model>
struct PointState {
  Voigt<3> stress = Voigt<3>::Zero();
  PointStateOf<Model> state;
};

// The state is taken by value: trial evaluations must never touch the committed history.
template <class Model>
PointState<Model> advance(const Model& m, PointState<Model> s, const Voigt<3>& d_eps) {
  m.template update<3>(s.stress, d_eps, Mat<3>::Zero(), m.context(), s.state.ref());
  return s;
}

// Hooke's law on tensor components (sigma_xy = 2 G eps_xy), for the first guess and as the
// fallback tangent where the finite-difference one is singular.
Stiffness elastic_stiffness(const LinearElastic& e) {
  Stiffness c = Stiffness::Zero();
  const double lambda = e.K - 2.0 * e.G / 3.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c(i, j) = lambda;
    c(i, i) += 2.0 * e.G;
  }
  for (int k = 3; k < 6; ++k) c(k, k) = 2.0 * e.G;
  return c;
}

double max_abs(const Voigt<3>& v) { return v.cwiseAbs().maxCoeff(); }

// Position of an increment along the path, for messages.
struct Where {
  long increment;
  int segment, k, n;

  std::string text() const {
    return fmt::format("increment {} (segment {}, increment {} of {})", increment, segment, k, n);
  }
};

// Voigt slots of the components the axisymmetric tie below relates.
constexpr int kXX = 0, kZZ = 2, kXY = 3, kYZ = 4;

// One increment under mixed control: the driven strain components are known, the others must be
// found so that the updated stress meets `target` on them.
//
// Axisymmetric tie: a segment that controls sigma_xx and sigma_zz alike (and xy, yz alike), started
// from a state symmetric under the swap of x and z (sigma_xx = sigma_zz, sigma_xy = sigma_yz), is
// a test with cylindrical symmetry about y, as a triaxial cell is. Its solution has eps_zz =
// eps_xx, but at an edge of a yield surface with corners (Mohr-Coulomb's triaxial edge, where the
// two lateral principal stresses are equal) the lateral plastic flow may split between x and z in
// any proportion without changing the stress: Newton's method on eps_xx and eps_zz apart then
// picks a split that depends on round-off (eps_xx 0.023 against eps_zz 0.030 at 5 % axial strain,
// with q and the dilatancy ratio right). Tied, eps_zz follows eps_xx and the one unknown meets the
// mean of sigma_xx and sigma_zz, which the symmetric state holds equal.
struct MixedIncrement {
  Voigt<3> given = Voigt<3>::Zero();  // strain increment of the driven components (others 0)
  std::array<int, n_components> unknown{};
  std::array<bool, n_components> held{};  // of each unknown: held at its start value, not loaded
  int m = 0;
  bool tied = false;  // eps_zz = eps_xx, xx's residual on the mean of sigma_xx and sigma_zz
  VecU target;

  // What an unknown's residual measures, and how the strain it solves for spreads: for the tied
  // xx, half of xx's and zz's stress, and the same strain on both.
  double stress_of(const Voigt<3>& s, int c) const { return tied && c == kXX ? 0.5 * (s[kXX] + s[kZZ]) : s[c]; }
  void spread(Voigt<3>& d_eps) const {
    if (tied) d_eps[kZZ] = d_eps[kXX];
  }
};

// Whether a segment, started at stress s0, controls x and z alike from a state symmetric in them.
bool axisymmetric(const Segment& seg, const Voigt<3>& s0, double tolerance) {
  const auto same = [&](int a, int b) {
    const ComponentControl &ca = seg.control[a], &cb = seg.control[b];
    return ca.kind == cb.kind && (ca.kind == Control::StressHold || ca.value == cb.value);
  };
  const double scale = std::max(max_abs(s0), 1.0);
  return seg.control[kXX].by_stress() && same(kXX, kZZ) && same(kXY, kYZ) &&
         std::abs(s0[kXX] - s0[kZZ]) <= tolerance * scale && std::abs(s0[kXY] - s0[kYZ]) <= tolerance * scale;
}

template <class Model>
class Driver {
  using PointState = element::PointState<Model>;

 public:
  // `start`: the point at the path's initial stress, its state started (material.hpp start_state);
  // its moduli give the first guesses and the fallback tangent of the stress control.
  Driver(const Model& model, const PointState& start, const IterationSettings& settings)
      : model_(model), start_(start), settings_(settings) {
    PointState s = start;
    const LinearElastic elastic = model.stiffness(s.state.ref());
    C_ = elastic_stiffness(elastic);
    M_ = elastic.constrained_modulus();
  }

  void run(const ElementPath& path, const std::function<void(const ElementRow&)>& on_row) const {
    PointState state = start_;
    Voigt<3> strain = Voigt<3>::Zero();
    long increment = 0;
    on_row(row(increment, 0, strain, state));
    for (std::size_t s = 0; s < path.segments.size(); ++s) {
      const Segment& seg = path.segments[s];
      const Voigt<3> sigma0 = state.stress;
      MixedIncrement inc;
      inc.tied = axisymmetric(seg, sigma0, settings_.tolerance);
      for (int c = 0; c < n_components; ++c) {
        if (inc.tied && c == kZZ) continue;  // follows xx
        if (seg.control[c].by_stress()) {
          inc.held[inc.m] = seg.control[c].kind == Control::StressHold;
          inc.unknown[inc.m++] = c;
        }
        else inc.given[c] = seg.control[c].value / seg.increments;
      }
      inc.target.resize(inc.m);
      VecU previous;  // unknown strains of the last increment: the best guess in steady flow
      for (int k = 1; k <= seg.increments; ++k) {
        ++increment;
        const Where where{increment, static_cast<int>(s), k, seg.increments};
        // Targets are interpolated from the segment's start, so the last one is met exactly.
        const double f = static_cast<double>(k) / seg.increments;
        for (int a = 0; a < inc.m; ++a) {
          const int c = inc.unknown[a];
          const ComponentControl& ctl = seg.control[c];
          const double from = inc.stress_of(sigma0, c);
          inc.target[a] = ctl.kind == Control::StressHold ? from : from + (ctl.value - from) * f;
        }
        Voigt<3> d_eps = inc.given;
        const PointState next = inc.m == 0 ? advance(model_, state, d_eps) : solve(state, inc, previous, where, d_eps);
        if (!next.stress.allFinite())
          throw RunError(fmt::format("{}: the stress became non-finite", where.text()));
        previous.resize(inc.m);
        for (int a = 0; a < inc.m; ++a) previous[a] = d_eps[inc.unknown[a]];
        state = next;
        strain += d_eps;
        on_row(row(increment, static_cast<int>(s), strain, state));
      }
    }
  }

 private:
  static ElementRow row(long increment, int segment, const Voigt<3>& strain, const PointState& s) {
    ElementRow r;
    r.increment = increment;
    r.segment = segment;
    r.strain = strain;
    r.stress = s.stress;
    // The element CSV's state columns (element_csv.cpp), from the model's fields of those names.
    r.mode = static_cast<YieldMode>(static_cast<int>(s.state.field(field_name::yield_mode)));
    r.plastic_shear_strain = s.state.field(field_name::plastic_shear_strain);
    r.plastic_volumetric_strain = s.state.field(field_name::plastic_volumetric_strain);
    r.state.reserve(Model::state_fields.size());
    for (const StateField& f : Model::state_fields) r.state.emplace_back(f.name, s.state.field(f.name));
    return r;
  }

  // Newton's method on the unknown strain components. Fills the unknown entries of d_eps and
  // returns the converged state.
  PointState solve(const PointState& start, const MixedIncrement& inc, const VecU& previous, const Where& where,
                   Voigt<3>& d_eps) const {
    const int m = inc.m;
    const double scale = std::max({max_abs(start.stress), inc.target.cwiseAbs().maxCoeff(), M_ * max_abs(inc.given), 1.0});
    const double tol = settings_.tolerance * scale;
    // Finite-difference steps move the stress by ~1e-7 of its scale: far above round-off, small
    // enough that the tangent is that of the current piece of the (piecewise smooth) return.
    const double strain_scale = scale / M_;

    const auto evaluate = [&](const VecU& x, PointState& out) {
      Voigt<3> de = inc.given;
      for (int a = 0; a < m; ++a) de[inc.unknown[a]] = x[a];
      inc.spread(de);
      out = advance(model_, start, de);
      VecU r(m);
      for (int a = 0; a < m; ++a) r[a] = inc.stress_of(out.stress, inc.unknown[a]) - inc.target[a];
      return r;
    };

    // The elastic map from the unknowns to their residuals: Hooke's rows of the measured stresses,
    // the columns of the strains each unknown moves (xx and zz together when tied).
    const auto hooke_row = [&](int c) -> Eigen::Matrix<double, 1, 6> {
      return inc.tied && c == kXX ? Eigen::Matrix<double, 1, 6>(0.5 * (C_.row(kXX) + C_.row(kZZ))) : C_.row(c);
    };
    MatU C_uu(m, m);
    VecU rhs(m);
    for (int a = 0; a < m; ++a) {
      const int ca = inc.unknown[a];
      const auto row_a = hooke_row(ca);
      rhs[a] = inc.target[a] - inc.stress_of(start.stress, ca) - row_a.dot(inc.given);
      for (int b = 0; b < m; ++b) {
        const int cb = inc.unknown[b];
        C_uu(a, b) = row_a[cb] + (inc.tied && cb == kXX ? row_a[kZZ] : 0.0);
      }
    }
    const Eigen::PartialPivLU<MatU> elastic_lu(C_uu);

    // First guess: the elastic predictor, or the last increment's strains if they do better.
    VecU x = elastic_lu.solve(rhs);
    PointState state;
    VecU r = evaluate(x, state);
    if (previous.size() == m) {
      PointState s2;
      const VecU r2 = evaluate(previous, s2);
      if (r2.allFinite() && !(r2.norm() >= r.norm())) x = previous, r = r2, state = s2;
    }

    int iterations = 0;
    const char* reason = nullptr;
    while (!(r.cwiseAbs().maxCoeff() <= tol)) {
      if (iterations == settings_.max_iterations) {
        reason = "no convergence";
        break;
      }
      ++iterations;
      MatU J(m, m);
      for (int b = 0; b < m; ++b) {
        VecU xp = x;
        const double h = 1e-7 * std::max(std::abs(x[b]), strain_scale);
        xp[b] += h;
        PointState tmp;
        J.col(b) = (evaluate(xp, tmp) - r) / h;
      }
      const Eigen::FullPivLU<MatU> lu(J);
      VecU dx = lu.isInvertible() ? VecU(-lu.solve(r)) : VecU(-elastic_lu.solve(r));
      if (!dx.allFinite()) dx = -elastic_lu.solve(r);
      // Backtracking on |r|: the return mapping has kinks where the active yield planes change,
      // and a full step across one can overshoot.
      const auto try_step = [&](const VecU& step) {
        double alpha = 1.0;
        for (int ls = 0; ls < 30; ++ls, alpha *= 0.5) {
          PointState st;
          const VecU xt = x + alpha * step;
          const VecU rt = evaluate(xt, st);
          if (rt.allFinite() && rt.norm() < (1.0 - 1e-4 * alpha) * r.norm()) {
            x = xt, r = rt, state = st;
            return true;
          }
        }
        return false;
      };
      if (!try_step(dx) && !try_step(VecU(-elastic_lu.solve(r)))) {
        reason = "the iteration stalled";
        break;
      }
    }
    if (reason) throw RunError(failure(where, inc, state, reason, iterations, tol));
    for (int a = 0; a < m; ++a) d_eps[inc.unknown[a]] = x[a];
    inc.spread(d_eps);
    return state;
  }

  // The targets cannot be met together: list every stress-controlled component (the loaded ones
  // first, as the likely cause) with what it reached.
  static std::string failure(const Where& where, const MixedIncrement& inc, const PointState& state, const char* reason,
                             int iterations, double tol) {
    std::string list, loaded;
    for (bool held : {false, true})
      for (int a = 0; a < inc.m; ++a) {
        if (inc.held[a] != held) continue;
        const int c = inc.unknown[a];
        list += fmt::format("{}sig_{} {} {:.9g} Pa reached {:.9g} Pa{}", list.empty() ? "" : "; ", component_name[c],
                            held ? "held at" : "loaded to", inc.target[a], inc.stress_of(state.stress, c),
                            inc.tied && c == kXX ? " (with sig_zz: their mean, eps_zz following eps_xx)" : "");
        if (!held) loaded += fmt::format("{}sig_{}", loaded.empty() ? "" : " or ", component_name[c]);
      }
    return fmt::format(
        "{}: the stress targets cannot be met ({} after {} iterations, tolerance {:.3g} Pa): {}. The stress asked for "
        "is probably beyond the material's strength, which stress control cannot follow: drive {} by strain instead",
        where.text(), reason, iterations, tol, list, loaded.empty() ? "one of these components" : loaded);
  }

  const Model& model_;
  PointState start_;
  Stiffness C_;
  double M_;
  IterationSettings settings_;
};

}  // namespace

void drive_element(const Material& material, const ElementPath& path, const IterationSettings& settings,
                   const std::function<void(const ElementRow&)>& on_row) {
  std::visit(
      [&](const auto& model) {
        using M = std::decay_t<decltype(model)>;
        PointState<M> start;
        start.stress = path.initial_stress;
        start_state(model, PrincipalFrame<3>(path.initial_stress).values, start.state.ref());
        Driver<M>(model, start, settings).run(path, on_row);
      },
      material.model);
}

std::vector<ElementRow> drive_element(const Material& material, const ElementPath& path,
                                      const IterationSettings& settings) {
  std::vector<ElementRow> rows;
  rows.reserve(static_cast<std::size_t>(path.total_increments()) + 1);
  drive_element(material, path, settings, [&](const ElementRow& r) { rows.push_back(r); });
  return rows;
}

}  // namespace tsuchi::element
