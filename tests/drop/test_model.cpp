// Garg & Nayar's drop model (alpha = 0) against an exact ray trace of a sphere, and the paper's
// checks: field of view about 165 degrees, refraction dominating away from the rim (Figure 4).
#include <gtest/gtest.h>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/snell.hpp"

namespace hydrolux::drop {
namespace {

struct Traced {
  Vec3 direction;   // leaving the drop
  double weight;    // product of the Fresnel factors along the path
};

// Exact trace in a unit sphere: a ray from the camera (travelling +z) at image radius rho,
// azimuth 0, enters, reflects n_internal times inside, leaves. Vector Snell's law (optics::refract)
// and chords of the sphere; Fresnel from optics::fresnel_dielectric at each actual angle.
Traced trace_from(Vec3 p, Vec3 d, double mu, int n_internal) {
  const auto in = optics::refract(-d, p, mu);
  double w = optics::fresnel_dielectric(std::abs(glm::dot(-d, p)), 1.0, mu).T;
  d = in->wt;
  for (int n = 0;; ++n) {
    p = p + (-2 * glm::dot(p, d)) * d;  // the chord to the sphere's other side
    const double cos_in = std::abs(glm::dot(d, p));
    if (n == n_internal) {
      const auto out = optics::refract(-d, -p, 1 / mu);  // normal on the inside: -p
      w *= optics::fresnel_dielectric(cos_in, mu, 1.0).T;
      return {out->wt, w};
    }
    w *= optics::fresnel_dielectric(cos_in, mu, 1.0).R;
    d = d - 2 * glm::dot(d, p) * p;  // internal reflection
  }
}

Traced trace(double rho, double mu, int n_internal) {
  return trace_from({rho, 0, -std::sqrt(1 - rho * rho)}, {0, 0, 1}, mu, n_internal);
}

// Direction of a model path as a unit vector.
Vec3 unit(const Direction& dir) { return spherical_direction(dir.theta, dir.phi); }

// The exact sphere and the model agree to rounding for alpha = 0: the model's angles are the
// sphere's exact geometry (no approximation for a distant scene), and its transfer factors are
// the products of the Fresnel factors (entry and exit transmittances are equal for the two ends of
// a chord). Tolerance 1e-9 (the rim samples lose digits in asin near 1).
TEST(DropModel, MatchesExactSphereTrace) {
  for (double mu : {1.333, 1.49}) {
    for (int s = 0; s <= 99; ++s) {
      const double rho = 0.995 * s / 99.0;
      const auto model = drop_paths_at_rho(rho, mu, 2);
      const auto refr = trace(rho, mu, 0);
      EXPECT_LT(glm::length(refr.direction - unit(model.refraction)), 1e-9) << mu << " rho " << rho;
      EXPECT_NEAR(refr.weight, model.R, 1e-12);
      for (int n = 1; n <= 2; ++n) {
        const auto t = trace(rho, mu, n);
        EXPECT_LT(glm::length(t.direction - unit(model.internal[std::size_t(n - 1)])), 1e-9)
            << mu << " rho " << rho << " N " << n;
        EXPECT_NEAR(t.weight, model.P[std::size_t(n - 1)], 1e-12);
      }
      // Specular reflection off the front surface.
      const Vec3 p{rho, 0, -std::sqrt(1 - rho * rho)};
      EXPECT_LT(glm::length(optics::reflect(Vec3{0, 0, -1}, p) - unit(model.reflection)), 1e-9);
      EXPECT_NEAR(model.S, optics::fresnel_dielectric(std::sqrt(1 - rho * rho), 1.0, mu).R, 1e-12);
    }
  }
}

// Off the optical axis (the paper's alpha): random viewing directions and random visible points of
// the sphere, the vector form against the exact trace. Tolerance 1e-9 as above.
TEST(DropModel, OffAxisRaysMatchExactSphereTrace) {
  Rng rng(17);
  int tested = 0;
  for (int k = 0; k < 2000; ++k) {
    const double z = 1 - 2 * rng.uniform(), phi = 2 * kPi<> * rng.uniform(), rr = std::sqrt(1 - z * z);
    const Vec3 view{rr * std::cos(phi), rr * std::sin(phi), z};
    const double z2 = 1 - 2 * rng.uniform(), phi2 = 2 * kPi<> * rng.uniform(), rr2 = std::sqrt(1 - z2 * z2);
    const Vec3 n{rr2 * std::cos(phi2), rr2 * std::sin(phi2), z2};
    if (glm::dot(view, n) > -1e-3) continue;  // the point must face the camera (and not graze)
    ++tested;
    const auto model = drop_rays(view, n, 1.333, 2);
    const auto refr = trace_from(n, view, 1.333, 0);
    EXPECT_LT(glm::length(refr.direction - model.refraction), 1e-9);
    EXPECT_NEAR(refr.weight, model.R, 1e-12);
    for (int m = 1; m <= 2; ++m) {
      const auto t = trace_from(n, view, 1.333, m);
      EXPECT_LT(glm::length(t.direction - model.internal[std::size_t(m - 1)]), 1e-9) << m;
      EXPECT_NEAR(t.weight, model.P[std::size_t(m - 1)], 1e-12);
    }
    EXPECT_LT(glm::length(optics::reflect(-view, n) - model.reflection), 1e-12);
  }
  EXPECT_GT(tested, 800);
  // On the axis the vector form and the angle form agree.
  const auto a = drop_paths_at_rho(0.6, 1.333);
  const auto b = drop_rays({0, 0, 1}, {0.6, 0, -0.8}, 1.333);
  EXPECT_LT(glm::length(unit(a.refraction) - b.refraction), 1e-12);
  EXPECT_LT(glm::length(unit(a.internal[1]) - b.internal[1]), 1e-12);
  EXPECT_THROW((void)drop_rays({0, 0, 1}, {0, 0, 1}, 1.333), DomainError);  // faces away
  // Head-on views whose cosine rounds just past 1 are fine (normal = -view for random views).
  for (int k = 0; k < 1000; ++k) {
    const Vec3 v = glm::normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
    EXPECT_NO_THROW((void)drop_rays(v, -v, 1.333));
  }
}

// The paper: a drop's field of view is about 165 degrees (section 4.4); for mu = 1.333 the rim ray
// leaves 2 (90 - 48.6) = 82.8 degrees off the axis on either side.
TEST(DropModel, FieldOfView) {
  EXPECT_NEAR(field_of_view_deg(1.333), 165.6, 0.1);
  const auto rim = drop_paths_at_rho(1.0, 1.333);
  EXPECT_NEAR(2 * rad_to_deg(rim.refraction.theta), field_of_view_deg(1.333), 1e-9);
}

// Figure 4 (Le = 1, alpha = 0): refraction dominates the drop's radiance except near its rim. At
// the centre R = (1 - k)^2 with k = ((mu - 1)/(mu + 1))^2 = 0.0204 for water; refraction exceeds
// all the reflected paths together for rho < 0.98, and they overtake it only at the rim.
TEST(DropModel, RefractionDominatesAwayFromTheRim) {
  const auto f = radiance_profile(1.333, 201);
  EXPECT_NEAR(f.refraction.front(), sqr(1 - sqr(0.333 / 2.333)), 1e-12);
  EXPECT_NEAR(f.reflection.front(), sqr(0.333 / 2.333), 1e-12);
  for (std::size_t s = 0; s < f.rho.size(); ++s) {
    const double others = f.reflection[s] + f.internal[0][s] + f.internal[1][s];
    if (f.rho[s] < 0.98) {
      EXPECT_GT(f.refraction[s], others) << f.rho[s];
    }
  }
  EXPECT_LT(f.refraction.back(), f.reflection.back());  // at the rim everything is reflected
  EXPECT_EQ(f.internal.size(), 2u);
  EXPECT_THROW((void)radiance_profile(1.333, 1), DomainError);
  EXPECT_THROW((void)drop_paths_at_rho(1.5, 1.333), DomainError);
  EXPECT_THROW((void)drop_paths_at_rho(0.5, 0.9), DomainError);
}

}  // namespace
}  // namespace hydrolux::drop
