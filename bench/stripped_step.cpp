// tsuchi-stripped-step: a yardstick for tsuchi-bench, not a solver. The 2D step of tsuchi's
// default numerics written for speed alone, with nothing a model can vary: MUSL, APIC, cpGIMP
// (half-widths stretched with the strain), the nodal volumetric average (solver.anti_locking =
// "node", eq V3), linear elastic with the Jaumann rate, gravity, one thread, flat arrays of doubles,
// every stencil loop 3 x 3 with the node index computed inline, scatters in particle order.
// It has no grid edge (the body sits two cells above the lowest node row, and rows 0-2 are held),
// no body fields, prescribed motion, damping, loads, fault checks, block schedule or critical
// time step per step. The case is tsuchi-bench's 2D elastic block (1 x 1 m on a 1.5 x 1.5 m grid,
// 2 x 2 particles per cell, E = 10 MPa, nu = 0.3, rho = 2000 kg/m^3, dt = 0.5 h / c_p).
//
// What it is for: the time and the instruction count (valgrind --tool=callgrind) of this loop
// bound what a rewrite of tsuchi's step into special-purpose passes could reach on a machine with
// the same numerics; BENCHMARKS.md (ninth part) sets them beside tsuchi's own figures.
// Usage: tsuchi-stripped-step [cells per side = 50] [steps = 400]
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using Column = std::vector<double>;

// GIMP weights and derivatives along one axis for the three nodes from c0, without a branch
// (the same algebra as shape/gimp.hpp): s = x / h, q = l_p / h.
inline void gimp_axis(double s, double q, double inv_h, int& c0, double* w, double* dw) {
  const auto max = [](double a, double b) { return a > b ? a : b; };
  const auto min = [](double a, double b) { return a < b ? a : b; };
  const int c = static_cast<int>(s + 0.5) - 1;
  const double r = s - (c + 1);
  const double tl = q - r, tr = q + r, q2 = 2.0 * q, inv4q = 0.25 / q;
  const double cl = min(max(tl, 0.0), q2), cr = min(max(tr, 0.0), q2);
  w[0] = cl * cl * inv4q + max(tl - q2, 0.0);
  w[2] = cr * cr * inv4q + max(tr - q2, 0.0);
  w[1] = 1.0 - w[0] - w[2];
  dw[0] = (-2.0 * inv_h) * cl * inv4q;
  dw[2] = (2.0 * inv_h) * cr * inv4q;
  dw[1] = -dw[0] - dw[2];
  c0 = c;
}

struct Block {
  // Grid: nx * ny nodes, node (i, j) at (i h, j h), index i + nx j.
  int nx = 0, held_rows = 3;
  double h = 0.0, inv_h = 0.0, dt = 0.0, lambda = 0.0, mu = 0.0, gy = -9.81;
  Column gm, gpx, gpy, gfx, gfy, gvx, gvy, gnum, gden;
  // Particles.
  Column x, y, vx, vy, m, vol, lx, ly, sxx, syy, szz, sxy, c00, c01, c10, c11, ux, uy, exx, eyy, exy;
  // The step's stencil factors per particle (first node, weights and derivatives per axis).
  std::vector<int> i0, j0;
  Column wx, dwx, wy, dwy;
  double seconds[6] = {};  // per pass, for the report

  std::size_t node(std::size_t p, int b) const {
    return static_cast<std::size_t>(i0[p]) + static_cast<std::size_t>(j0[p] + b) * static_cast<std::size_t>(nx);
  }
  bool held(std::size_t k) const { return k < static_cast<std::size_t>(held_rows * nx); }

  void kernel() {
    for (std::size_t p = 0; p < x.size(); ++p) {
      gimp_axis(x[p] * inv_h, lx[p] * inv_h, inv_h, i0[p], &wx[3 * p], &dwx[3 * p]);
      gimp_axis(y[p] * inv_h, ly[p] * inv_h, inv_h, j0[p], &wy[3 * p], &dwy[3 * p]);
    }
  }

  // Mass, APIC momentum m (v + C (x_i - x_p)) and force S m g - V sigma grad S, eqs (1)-(3).
  void p2g() {
    for (std::size_t k = 0; k < gm.size(); ++k) gm[k] = gpx[k] = gpy[k] = gfx[k] = gfy[k] = 0.0;
    for (std::size_t p = 0; p < x.size(); ++p) {
      const double *Wx = &wx[3 * p], *Dx = &dwx[3 * p], *Wy = &wy[3 * p], *Dy = &dwy[3 * p];
      const double mp = m[p], mvx = mp * vx[p], mvy = mp * vy[p];
      const double a00 = -vol[p] * sxx[p], a01 = -vol[p] * sxy[p], a11 = -vol[p] * syy[p];
      const double m00 = mp * c00[p], m01 = mp * c01[p], m10 = mp * c10[p], m11 = mp * c11[p];
      const double rx0 = i0[p] * h - x[p], ry0 = j0[p] * h - y[p];
      for (int b = 0; b < 3; ++b) {
        const double T = Wy[b], dT = Dy[b], ry = ry0 + b * h;
        const double rm = T * mp, rvx = T * (mvx + m01 * ry), rvy = T * (mvy + m11 * ry);
        const double cx = T * m00, cy = T * m10;
        const double fwx = dT * a01, fwy = dT * a11 + T * mp * gy, fdx = T * a00, fdy = T * a01;
        std::size_t k = node(p, b);
        for (int a = 0; a < 3; ++a, ++k) {
          const double w = Wx[a], dw = Dx[a], wrx = w * (rx0 + a * h);
          gm[k] += w * rm;
          gpx[k] += w * rvx + wrx * cx;
          gpy[k] += w * rvy + wrx * cy;
          gfx[k] += w * fwx + dw * fdx;
          gfy[k] += w * fwy + dw * fdy;
        }
      }
    }
  }

  // v^L = (p + dt f) / m into gv, held rows at rest; p cleared for the remap.
  void solve() {
    for (std::size_t k = 0; k < gm.size(); ++k) {
      const bool free = gm[k] > 1e-12 && !held(k);
      const double im = free ? 1.0 / gm[k] : 0.0;
      gvx[k] = (gpx[k] + dt * gfx[k]) * im, gvy[k] = (gpy[k] + dt * gfy[k]) * im;
      gpx[k] = gpy[k] = 0.0;
    }
  }

  // APIC g2p: v_p = sum S v^L, C_p = B_p D_p^-1; then the remap of the particle's affine momentum.
  void g2p_remap() {
    for (std::size_t p = 0; p < x.size(); ++p) {
      const double *Wx = &wx[3 * p], *Wy = &wy[3 * p];
      const double rx0 = i0[p] * h - x[p], ry0 = j0[p] * h - y[p];
      double s_w = 0.0, s_wrx = 0.0, s_wrx2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double rx = rx0 + a * h;
        s_w += Wx[a], s_wrx += Wx[a] * rx, s_wrx2 += Wx[a] * rx * rx;
      }
      double sx = 0.0, sy = 0.0, bxx = 0.0, bxy = 0.0, byx = 0.0, byy = 0.0, dxx = 0.0, dyy = 0.0, dxy = 0.0;
      for (int b = 0; b < 3; ++b) {
        const double T = Wy[b], ry = ry0 + b * h;
        std::size_t k = node(p, b);
        double rvx = 0.0, rvy = 0.0, rrx = 0.0, rry = 0.0;
        for (int a = 0; a < 3; ++a, ++k) {
          const double w = Wx[a], wrx = w * (rx0 + a * h);
          rvx += w * gvx[k], rvy += w * gvy[k], rrx += wrx * gvx[k], rry += wrx * gvy[k];
        }
        sx += T * rvx, sy += T * rvy, bxx += T * rrx, byx += T * rry;
        bxy += (T * ry) * rvx, byy += (T * ry) * rvy;
        dxx += T * s_wrx2, dyy += T * ry * ry * s_w, dxy += T * ry * s_wrx;
      }
      const double id = 1.0 / (dxx * dyy - dxy * dxy), i00 = dyy * id, i01 = -dxy * id, i11 = dxx * id;
      c00[p] = bxx * i00 + bxy * i01, c01[p] = bxx * i01 + bxy * i11;
      c10[p] = byx * i00 + byy * i01, c11[p] = byx * i01 + byy * i11;
      vx[p] = sx, vy[p] = sy;
      const double mp = m[p], mvx = mp * sx, mvy = mp * sy;
      const double m00 = mp * c00[p], m01 = mp * c01[p], m10 = mp * c10[p], m11 = mp * c11[p];
      for (int b = 0; b < 3; ++b) {
        const double T = Wy[b], ry = ry0 + b * h;
        const double rvx = T * (mvx + m01 * ry), rvy = T * (mvy + m11 * ry), cx = T * m00, cy = T * m10;
        std::size_t k = node(p, b);
        for (int a = 0; a < 3; ++a, ++k) {
          const double w = Wx[a], wrx = w * (rx0 + a * h);
          gpx[k] += w * rvx + wrx * cx;
          gpy[k] += w * rvy + wrx * cy;
        }
      }
    }
    for (std::size_t k = 0; k < gm.size(); ++k) {
      const double im = gm[k] > 1e-12 && !held(k) ? 1.0 / gm[k] : 0.0;
      gvx[k] = gpx[k] * im, gvy[k] = gpy[k] * im;
      gnum[k] = gden[k] = 0.0;
    }
  }

  // Eq (V3): e_i = sum S V tr(d eps) / sum S V from the remapped velocities.
  void average() {
    for (std::size_t p = 0; p < x.size(); ++p) {
      const double *Wx = &wx[3 * p], *Dx = &dwx[3 * p], *Wy = &wy[3 * p], *Dy = &dwy[3 * p];
      double l00 = 0.0, l11 = 0.0;
      for (int b = 0; b < 3; ++b) {
        std::size_t k = node(p, b);
        double s0 = 0.0, s1 = 0.0;
        for (int a = 0; a < 3; ++a, ++k) s0 += Dx[a] * gvx[k], s1 += Wx[a] * gvy[k];
        l00 += Wy[b] * s0, l11 += Dy[b] * s1;
      }
      const double q = vol[p] * dt * (l00 + l11), v0 = vol[p];
      for (int b = 0; b < 3; ++b) {
        std::size_t k = node(p, b);
        for (int a = 0; a < 3; ++a, ++k) {
          const double S = Wx[a] * Wy[b];
          gnum[k] += S * q, gden[k] += S * v0;
        }
      }
    }
    for (std::size_t k = 0; k < gm.size(); ++k) gnum[k] = gden[k] > 0.0 ? gnum[k] / gden[k] : 0.0;
  }

  // Strain increment with the averaged volume change, Jaumann rotation, Hooke, volume, domain, move.
  void stress() {
    for (std::size_t p = 0; p < x.size(); ++p) {
      const double *Wx = &wx[3 * p], *Dx = &dwx[3 * p], *Wy = &wy[3 * p], *Dy = &dwy[3 * p];
      double l00 = 0.0, l01 = 0.0, l10 = 0.0, l11 = 0.0, e = 0.0;
      for (int b = 0; b < 3; ++b) {
        std::size_t k = node(p, b);
        double s0x = 0.0, s0y = 0.0, s1x = 0.0, s1y = 0.0, se = 0.0;
        for (int a = 0; a < 3; ++a, ++k) {
          s0x += Dx[a] * gvx[k], s0y += Dx[a] * gvy[k];
          s1x += Wx[a] * gvx[k], s1y += Wx[a] * gvy[k], se += Wx[a] * gnum[k];
        }
        l00 += Wy[b] * s0x, l10 += Wy[b] * s0y, l01 += Dy[b] * s1x, l11 += Dy[b] * s1y, e += Wy[b] * se;
      }
      double dxx = dt * l00, dyy = dt * l11;
      const double dxy = 0.5 * dt * (l01 + l10), w01 = 0.5 * dt * (l01 - l10);
      const double shift = 0.5 * (e - (dxx + dyy));
      dxx += shift, dyy += shift;
      const double ev = dxx + dyy;
      const double s00 = sxx[p], s11 = syy[p], s01 = sxy[p];
      sxx[p] = s00 + 2.0 * w01 * s01 + lambda * ev + 2.0 * mu * dxx;
      syy[p] = s11 - 2.0 * w01 * s01 + lambda * ev + 2.0 * mu * dyy;
      sxy[p] = s01 + w01 * (s11 - s00) + 2.0 * mu * dxy;
      szz[p] += lambda * ev;
      exx[p] += dxx, eyy[p] += dyy, exy[p] += dxy;
      vol[p] *= 1.0 + ev;
      lx[p] *= 1.0 + dxx, ly[p] *= 1.0 + dyy;
      x[p] += dt * vx[p], y[p] += dt * vy[p];
      ux[p] += dt * vx[p], uy[p] += dt * vy[p];
    }
  }

  void step() {
    using clock = std::chrono::steady_clock;
    auto t = clock::now();
    const auto lap = [&](int i) {
      const auto u = clock::now();
      seconds[i] += std::chrono::duration<double>(u - t).count();
      t = u;
    };
    kernel(), lap(0);
    p2g(), lap(1);
    solve(), g2p_remap(), lap(2);
    average(), lap(3);
    stress(), lap(4);
  }
};

}  // namespace

int main(int argc, char** argv) {
  const int cells = argc > 1 ? std::atoi(argv[1]) : 50;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 400;
  if (cells < 2 || steps < 1) {
    std::fprintf(stderr, "usage: tsuchi-stripped-step [cells per side >= 2] [steps >= 1]\n");
    return 2;
  }
  Block s;
  s.h = 1.0 / cells, s.inv_h = cells;
  s.nx = static_cast<int>(std::lround(1.5 / s.h)) + 1;
  const std::size_t nodes = static_cast<std::size_t>(s.nx) * static_cast<std::size_t>(s.nx + 3);
  const double rho = 2000.0, E = 1.0e7, nu = 0.3;
  s.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), s.mu = E / (2.0 * (1.0 + nu));
  s.dt = 0.5 * s.h / std::sqrt((s.lambda + 2.0 * s.mu) / rho);
  const int first_column = static_cast<int>(std::lround(0.25 / s.h));
  for (int cj = 0; cj < cells; ++cj)
    for (int ci = 0; ci < cells; ++ci)
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          s.x.push_back((first_column + ci + 0.25 + 0.5 * a) * s.h);
          s.y.push_back((s.held_rows - 1 + cj + 0.25 + 0.5 * b) * s.h);
        }
  const std::size_t n = s.x.size();
  for (Column* c : {&s.vx, &s.vy, &s.sxx, &s.syy, &s.szz, &s.sxy, &s.c00, &s.c01, &s.c10, &s.c11, &s.ux, &s.uy,
                    &s.exx, &s.eyy, &s.exy})
    c->assign(n, 0.0);
  s.vol.assign(n, s.h * s.h / 4.0), s.m.assign(n, rho * s.h * s.h / 4.0);
  s.lx.assign(n, s.h / 4.0), s.ly.assign(n, s.h / 4.0);
  s.i0.resize(n), s.j0.resize(n);
  for (Column* c : {&s.wx, &s.dwx, &s.wy, &s.dwy}) c->assign(3 * n, 0.0);
  for (Column* c : {&s.gm, &s.gpx, &s.gpy, &s.gfx, &s.gfy, &s.gvx, &s.gvy, &s.gnum, &s.gden}) c->assign(nodes, 0.0);

  s.step();  // warm-up: first touch of every array
  for (double& t : s.seconds) t = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) s.step();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double kinetic = 0.0;
  for (std::size_t p = 0; p < n; ++p) kinetic += 0.5 * s.m[p] * (s.vx[p] * s.vx[p] + s.vy[p] * s.vy[p]);
  const double per = 1e9 / (static_cast<double>(n) * steps);
  std::printf("stripped 2D step (MUSL, APIC, cpGIMP, nodal average, elastic): %zu particles, %d steps, %.3f s, "
              "%.3e particle-steps/s; kinetic energy %.6e J/m\n",
              n, steps, wall, static_cast<double>(n) * steps / wall, kinetic);
  const char* names[5] = {"kernel", "p2g (m, p, f)", "solve, g2p and remap", "nodal average", "stress and move"};
  for (int i = 0; i < 5; ++i) std::printf("  %-22s %6.1f ns per particle-step\n", names[i], per * s.seconds[i]);
  return 0;
}
