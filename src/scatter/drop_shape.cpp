#include "hydrolux/scatter/drop_shape.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/table.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::scatter {

namespace {

constexpr const char* kTableFile = "drop/chuang_beard_1990_shape.csv";
constexpr const char* kContext = "the Chuang & Beard (1990) shape table";

// The table in SI units: radii in metres, coefficients dimensionless. Dividing by the exact 1e3 and
// 1e4 rounds correctly, so a row's 0.0017 is the double nearest 0.0017 (3.25 mm the nearest 3.25e-3).
struct ShapeTable {
  std::vector<double> radius_m;
  std::array<std::vector<double>, kShapeTerms> c;
};

const ShapeTable& shape_table() {
  static const ShapeTable t = [] {
    const Table raw = parse_table(embedded_file(kTableFile), kTableFile);
    static constexpr const char* kColumns[kShapeTerms] = {"c0", "c1", "c2", "c3", "c4", "c5",
                                                          "c6", "c7", "c8", "c9", "c10"};
    ShapeTable out;
    for (const double r : raw.column("radius_mm")) out.radius_m.push_back(r / 1e3);
    for (int n = 0; n < kShapeTerms; ++n)
      for (const double v : raw.column(kColumns[n])) out.c[n].push_back(v / 1e4);
    return out;
  }();
  return t;
}

// The series 1 + sum_n c_n T_n(x) in x = cos(theta), with T_n(cos t) = cos(n t), and its derivative
// d/dx = sum_n n c_n U_{n-1}(x) (U the Chebyshev polynomials of the second kind). Both by the
// three-term recurrences T_{n+1} = 2x T_n - T_{n-1}, U_{n+1} = 2x U_n - U_{n-1}: no trigonometric
// calls, and well conditioned on [-1, 1] for ten terms.
struct SeriesValue {
  double value;
  double d_dx;
};

SeriesValue series(const std::array<double, kShapeTerms>& c, double x) {
  double t_prev = 1, t = x;        // T_{n-2}, T_{n-1} entering the loop at n = 2
  double u_prev = 1, u = 2 * x;    // U_{n-2}, U_{n-1} entering the loop at n = 2
  double value = 1 + c[0] + c[1] * x;
  double d = c[1];  // 1 * c_1 * U_0
  for (int n = 2; n < kShapeTerms; ++n) {
    const double t_n = 2 * x * t - t_prev;
    value += c[n] * t_n;
    d += n * c[n] * u;  // u = U_{n-1}
    t_prev = t;
    t = t_n;
    const double u_n = 2 * x * u - u_prev;
    u_prev = u;
    u = u_n;
  }
  return {value, d};
}

// The maximum of a smooth f on [0, pi]: a scan at 0.25 degree (the series' shortest period is
// 36 degrees, so the scan brackets the global maximum) refined by golden-section search to
// 1e-12 rad.
template <class F>
double max_on_half_circle(F&& f) {
  constexpr int kSteps = 720;
  const double h = kPi<double> / kSteps;
  int best = 0;
  double best_f = f(0.0);
  for (int k = 1; k <= kSteps; ++k) {
    const double v = f(k * h);
    if (v > best_f) best_f = v, best = k;
  }
  double lo = std::max(0, best - 1) * h, hi = std::min(kSteps, best + 1) * h;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  while (hi - lo > 1e-12) {
    if (f1 < f2) {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + g * (hi - lo), f2 = f(x2);
    } else {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - g * (hi - lo), f1 = f(x1);
    }
  }
  // The end points themselves (the poles) are often the maximum.
  return std::max({best_f, f1, f2});
}

}  // namespace

std::array<double, 2> drop_shape_radius_range_m() {
  const auto& r = shape_table().radius_m;
  return {r.front(), r.back()};
}

DropShape drop_shape(double radius_m) {
  const auto& t = shape_table();
  DropShape s;
  s.radius_m = radius_m;
  // A radius within rounding of a row (3.25e-3 and 3.25 * 1e-3 differ in the last bit) takes that
  // row's coefficients exactly, not an interpolation off by an ulp, and is in range at the ends.
  for (std::size_t i = 0; i < t.radius_m.size(); ++i)
    if (std::abs(radius_m - t.radius_m[i]) <= 1e-12 * t.radius_m[i]) {
      for (int n = 0; n < kShapeTerms; ++n) s.c[n] = t.c[n][i];
      return s;
    }
  require_in_range("radius_m", radius_m, t.radius_m.front(), t.radius_m.back(), kContext);
  for (int n = 0; n < kShapeTerms; ++n) s.c[n] = interpolate_linear(t.radius_m, t.c[n], radius_m);
  return s;
}

double shape_radius(const DropShape& s, double theta) {
  return s.radius_m * series(s.c, std::cos(theta)).value;
}

double shape_radius_derivative(const DropShape& s, double theta) {
  // dr/dtheta = dr/dx dx/dtheta with x = cos(theta).
  return -std::sin(theta) * s.radius_m * series(s.c, std::cos(theta)).d_dx;
}

double vertical_extent_m(const DropShape& s) {
  // Height below the centre is r cos(theta) (theta = 0 points down), height above it -r cos(theta).
  const double below = max_on_half_circle([&](double t) { return shape_radius(s, t) * std::cos(t); });
  const double above = max_on_half_circle([&](double t) { return -shape_radius(s, t) * std::cos(t); });
  return below + above;
}

double horizontal_extent_m(const DropShape& s) {
  return 2 * max_on_half_circle([&](double t) { return shape_radius(s, t) * std::sin(t); });
}

double axis_ratio(const DropShape& s) { return vertical_extent_m(s) / horizontal_extent_m(s); }

double volume_m3(const DropShape& s) {
  // V = (2 pi / 3) int_{-1}^{1} r(x)^3 dx, x = cos(theta); r^3 is a polynomial of degree 30 in x,
  // integrated exactly by 16-node Gauss-Legendre (exact to degree 31). Nodes from the Legendre
  // recurrence's Jacobi matrix (diagonal 0, off-diagonal k / sqrt(4k^2 - 1), mu0 = 2).
  static const auto rule = [] {
    constexpr int kNodes = 16;
    std::vector<double> diag(kNodes, 0.0), off(kNodes - 1);
    for (int k = 1; k < kNodes; ++k) off[k - 1] = k / std::sqrt(4.0 * k * k - 1.0);
    std::pair<std::vector<double>, std::vector<double>> nw;
    scatter::gauss_from_jacobi(std::move(diag), std::move(off), 2.0, nw.first, nw.second);
    return nw;
  }();
  double sum = 0;
  for (std::size_t i = 0; i < rule.first.size(); ++i) {
    const double r = series(s.c, rule.first[i]).value;
    sum += rule.second[i] * r * r * r;
  }
  return 2 * kPi<double> / 3 * s.radius_m * s.radius_m * s.radius_m * sum;
}

double shape_radius_toward(const DropShape& s, const Vec3& unit_dir) {
  const double x = std::clamp(-unit_dir.y, -1.0, 1.0);  // cos(theta), theta from -y
  return s.radius_m * series(s.c, x).value;
}

Vec3 shape_normal_toward(const DropShape& s, const Vec3& unit_dir) {
  // In the meridian plane the surface point is r u, u = sin(theta) e_rho + cos(theta) e with e the
  // fall direction; its tangent along theta is r' u + r e_theta, e_theta = (cos(theta) u - e) /
  // sin(theta). The outward normal is proportional to r u - r' e_theta, and with r' = -sin(theta)
  // dr/dx this is r u + dr/dx (x u - e): regular at the poles, where it reduces to u.
  const Vec3 e(0.0, -1.0, 0.0);
  const double x = std::clamp(-unit_dir.y, -1.0, 1.0);
  const auto v = series(s.c, x);
  const Vec3 n = v.value * unit_dir + v.d_dx * (x * unit_dir - e);
  return glm::normalize(n);
}

}  // namespace hydrolux::scatter
