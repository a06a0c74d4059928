// Small meshes made in code, with answers known by construction.
#pragma once

#include <cmath>
#include <string>

#include "core/parameterize.h"

namespace sdp::test {

struct Mesh {
  Positions V;
  Triangles F;
};

// A regular n-gon fan around a centre vertex 0 in the plane z = 0 (radius 1).
inline Mesh regularFan(int n, double centre_height = 0) {
  Mesh m;
  m.V.resize(n + 1, 3);
  m.F.resize(n, 3);
  m.V.row(0) << 0, 0, centre_height;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    m.V.row(k + 1) << std::cos(a), std::sin(a), 0;
    m.F.row(k) << 0, k + 1, (k + 1) % n + 1;
  }
  return m;
}

// An (n+1) x (n+1) grid over [0, sx] x [0, sy], z = height(x, y), triangulated with alternating
// diagonals so vertex rings are not all alike.
template <class Height>
Mesh grid(int n, double sx, double sy, Height height) {
  Mesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  m.F.resize(2 * n * n, 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = sx * i / n, y = sy * j / n;
      m.V.row(j * (n + 1) + i) << x, y, height(x, y);
    }
  int f = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if ((i + j) % 2 == 0) {
        m.F.row(f++) << a, b, d;
        m.F.row(f++) << a, d, c;
      } else {
        m.F.row(f++) << a, b, c;
        m.F.row(f++) << b, d, c;
      }
    }
  return m;
}

inline Mesh planarGrid(int n) {
  return grid(n, 2.0, 1.0, [](double, double) { return 0.0; });
}

// Signed area of face f in the returned UVs: positive = not flipped.
inline double uvArea(const Result& r, const Triangles& F, int f) {
  const auto a = r.layout.uv.row(F(f, 0)), b = r.layout.uv.row(F(f, 1)),
             c = r.layout.uv.row(F(f, 2));
  return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
}

// Counted independently of the core's metrics.
inline int countNonPositiveFaces(const Result& r, const Triangles& F) {
  int bad = 0;
  for (int f = 0; f < F.rows(); ++f) bad += uvArea(r, F, f) > 0 ? 0 : 1;
  return bad;
}

}  // namespace sdp::test
