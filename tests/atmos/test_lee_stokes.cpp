// Stokes Lee tables (LeeSpec::stokes): the rainbow's polarisation against the published values and
// the ray limit, I unchanged by the switch, and |Q| <= I.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "support/asan.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/geometric.hpp"

namespace {

using namespace hydrolux;
using atmos::LeeSpec;
using atmos::LeeTable;

constexpr bool kSanitized = HYDROLUX_TEST_ASAN;  // smaller tables under the sanitizers

// One drop radius over [a0, a1] degrees, with Q.
LeeSpec stokes_profile(const std::string& theory, double radius_um, double a0, double a1, int rows) {
  LeeSpec s = atmos::profile_spec(atmos::LeeTableKind::rainbow, radius_um, a0, a1, rows);
  s.theory = scatter::parse_theory(theory);
  s.stokes = true;
  return s;
}

// One wavelength, the sun a point: the single drop's own polarisation.
LeeSpec monochromatic(LeeSpec s, double nm) {
  s.wavelength_min_nm = s.wavelength_max_nm = nm;
  s.sun_disk_deg = 0;
  return s;
}

// The row of the largest luminance.
int peak_row(const LeeTable& t) {
  int best = 0;
  for (int r = 1; r < t.rows(); ++r)
    if (t.at(r, 0).Y > t.at(best, 0).Y) best = r;
  return best;
}

// The degree of linear polarisation of the rainbow ray of order p by ray optics: its power in each
// polarisation is T_j^2 R_j^(p-1), T_j and R_j the exact Fresnel power coefficients (entering at the
// rainbow ray's theta_i, reflected p - 1 times inside at its theta_t, leaving at theta_t).
double ray_limit_dolp(double n, int p) {
  const scatter::RainbowRay ray = scatter::rainbow_ray(n, p);
  const auto in = optics::fresnel_dielectric(std::cos(ray.theta_i), 1.0, n);
  const auto inside = optics::fresnel_dielectric(std::cos(ray.theta_t), n, 1.0);
  const auto out = inside;  // leaving: the same interface and angle as the internal reflections
  const double s = in.T_s * out.T_s * std::pow(inside.R_s, p - 1);
  const double q = in.T_p * out.T_p * std::pow(inside.R_p, p - 1);
  return (s - q) / (s + q);
}

// Water's index relative to air at `nm` (the table's media and temperature defaults).
double water_index(double nm) {
  const auto water = optics::find_medium("water");
  const auto air = optics::find_medium("air");
  return water->index(nm, std::nullopt).real() / air->n(nm);
}

// (1) Published values. Natural rainbows (white sunlight, the sun's disk) of 1 mm diameter drops
// (radius 500 um), Mie theory. What is published is the fraction of the bow's light polarised
// tangentially, I_perp / I = (1 + dolp) / 2: "typically 96% polarized ... tangential to the arcs"
// for the primary (lightcolourvision.org, "Polarization - rainbows"), "~95% polarization is
// typical" (D. Lien, NASA EPOD, 2 March 2006). 96% is the ray-optics value: (1 + 0.926) / 2 = 0.963
// from the Fresnel factors at the rainbow ray (ray_limit_dolp, n = 1.3343; and 0.905 for the secondary), and
// Konnen & de Boer (Appl. Opt. 18, 1961, 1979; abstract) find the degree of polarisation of real
// drops "less than expected from geometrical optics; it increases with droplet size" (no exact
// secondary figure was found in the sources at hand, so the secondary is held to the ray limit
// from below). Tolerances: the published figures are given to 1% (96%, ~95%), and the finite drop
// and the white light's spread of peaks lower the value below the ray limit (Konnen & de Boer), by
// 1.3% here for the primary (0.949) and 3.5% for the secondary (0.869): the bounds are
// [0.93, 0.963 + 0.005] and [0.85, 0.905 + 0.005].
TEST(LeeStokes, PolarisationOfThePrimaryAndSecondaryPeaks) {
  LeeSpec primary = stokes_profile("mie", 500, 136, 142, kSanitized ? 61 : 121);
  LeeSpec secondary = stokes_profile("mie", 500, 126, 132, kSanitized ? 61 : 121);
  if (kSanitized) primary.wavelengths = secondary.wavelengths = 10;
  const double n = water_index(550);
  const LeeTable tp = atmos::compute_lee_table(primary);
  const int rp = peak_row(tp);
  const double fp = (1 + tp.dolp(rp, 0)) / 2;
  const double ray_p = (1 + ray_limit_dolp(n, 2)) / 2;
  EXPECT_NEAR(ray_p, 0.963, 0.005) << "the ray optics value of the published 96%";
  EXPECT_GT(fp, 0.93) << "primary peak at " << tp.angle_deg[std::size_t(rp)] << " deg";
  EXPECT_LT(fp, ray_p + 0.005);
  const LeeTable ts = atmos::compute_lee_table(secondary);
  const int rs = peak_row(ts);
  const double fs = (1 + ts.dolp(rs, 0)) / 2;
  const double ray_s = (1 + ray_limit_dolp(n, 3)) / 2;
  EXPECT_GT(fs, 0.85) << "secondary peak at " << ts.angle_deg[std::size_t(rs)] << " deg";
  EXPECT_LT(fs, ray_s + 0.005);
  // Tangential: Q > 0 at both peaks.
  EXPECT_GT(tp.q_at(rp, 0).Y, 0);
  EXPECT_GT(ts.q_at(rs, 0).Y, 0);
}

// (2) The ray limit. Airy theory takes the Fresnel factors at the rainbow ray, so its dolp is the
// ray limit at every angle, to rounding (1e-12): this checks the integration carries Q as I. The
// Debye series of the primary (debye:2, exact wave theory of that order) at 1000 um approaches it
// as the drop grows (Konnen & de Boer 1979), from below: measured 0.9229, 0.9241, 0.9250, 0.9255
// at 250, 500, 1000 and 2000 um against 0.9264 (550 nm, n = 1.3343): its peak lies z = 1.0188 inside the rainbow
// ray (docs/rainbow-theories.md), where the Fresnel ratio differs by O(x^(-1/3)); 0.002 holds the
// 1000 um value (x = 11400) with room for that offset. The secondary's bow is sharper (its q is
// 5.7 times the primary's, van de Hulst's h), so the peak's offset and the Fresnel ratio's change
// are larger: debye:3 at 1000 um gives 0.795 against 0.808, held to 0.02.
TEST(LeeStokes, RainbowRayLimit) {
  const double nm = 550, n = water_index(nm);
  for (int p : {2, 3}) {
    const double a0 = p == 2 ? 136 : 126;
    const LeeTable airy = atmos::compute_lee_table(
        monochromatic(stokes_profile(p == 2 ? "airy" : "airy:3", 1000, a0, a0 + 6, 61), nm));
    const double limit = ray_limit_dolp(n, p);
    for (int r = 0; r < airy.rows(); ++r)
      if (airy.at(r, 0).Y > 0) {
        EXPECT_NEAR(airy.dolp(r, 0), limit, 1e-12) << "p " << p << " row " << r;
      }
    const LeeTable debye = atmos::compute_lee_table(
        monochromatic(stokes_profile(p == 2 ? "debye:2" : "debye:3", 1000, a0, a0 + 6, 121), nm));
    const int r = peak_row(debye);
    EXPECT_NEAR(debye.dolp(r, 0), limit, p == 2 ? 0.002 : 0.02) << "p " << p << " at " << debye.angle_deg[std::size_t(r)];
  }
}

// A small table of each computation path: the shared radius grid (spread), one radius per column,
// the sun's disk kernel, each theory, and non-spherical drops.
std::vector<LeeSpec> small_tables() {
  std::vector<LeeSpec> v;
  LeeSpec s = atmos::default_lee_spec(atmos::LeeTableKind::rainbow);
  s.columns = 6, s.rows = 24, s.radius_min_um = 20, s.radius_max_um = 400, s.wavelengths = 4;
  s.stokes = true;
  v.push_back(s);  // Mie, spread 0.1
  LeeSpec g = s;
  g.theory = scatter::parse_theory("geometric");
  g.size_spread = 0;
  v.push_back(g);
  LeeSpec a = s;
  a.theory = scatter::parse_theory("airy");
  a.radius_min_um = 200, a.radius_max_um = 1000;
  v.push_back(a);
  LeeSpec sh = a;
  sh.shape = atmos::parse_drop_shape("beard-chuang");
  sh.radius_max_um = 850;  // within beard-chuang's 888 um (axis ratio 0.77 at the largest drop)
  sh.canting_deg = 5;
  sh.position_deg = 90;
  v.push_back(sh);
  LeeSpec c = atmos::default_lee_spec(atmos::LeeTableKind::corona);
  c.columns = 4, c.rows = 16, c.wavelengths = 4, c.stokes = true;
  v.push_back(c);
  return v;
}

// (3) I is the same with and without Q, bit for bit; without, no Q is kept.
TEST(LeeStokes, IntensityUnchanged) {
  for (const LeeSpec& with : small_tables()) {
    LeeSpec without = with;
    without.stokes = false;
    const LeeTable a = atmos::compute_lee_table(with), b = atmos::compute_lee_table(without);
    EXPECT_EQ(a.xyz, b.xyz) << scatter::theory_name(with.theory) << " " << atmos::drop_shape_name(with.shape);
    EXPECT_EQ(a.q_xyz.size(), a.xyz.size());
    EXPECT_TRUE(b.q_xyz.empty());
    EXPECT_THROW((void)b.q_at(0, 0), Error);
  }
}

// (4) |Q| <= I in every channel (x_bar, y_bar, z_bar >= 0 weigh |Q| <= I per wavelength, drop and
// angle), up to rounding (1e-12 relative); and some polarisation somewhere.
TEST(LeeStokes, PolarisationBounded) {
  for (const LeeSpec& s : small_tables()) {
    const LeeTable t = atmos::compute_lee_table(s);
    double most = 0;
    for (std::size_t i = 0; i < t.xyz.size(); ++i) {
      ASSERT_LE(std::abs(t.q_xyz[i]), t.xyz[i] * (1 + 1e-12) + 1e-300)
          << scatter::theory_name(s.theory) << " value " << i;
      if (t.xyz[i] > 0) most = std::max(most, std::abs(t.q_xyz[i]) / t.xyz[i]);
    }
    EXPECT_GT(most, 0.1) << scatter::theory_name(s.theory);
  }
}

}  // namespace
