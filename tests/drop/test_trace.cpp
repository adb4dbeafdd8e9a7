// The exact reference tracer (trace.hpp): its surfaces against analytic intersections, power
// conservation of the Fresnel splits, the drop model (model.hpp) against it for a sphere, and the
// paper's claim that refraction dominates away from the rim (Garg & Nayar 2004, Fig. 4; seed 000).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "support/stats.hpp"

namespace hydrolux::drop {
namespace {

// A ray from a random point on a sphere of radius 3 R around `centre` towards a random point of
// the ball of radius R there: it may hit or miss the drop.
Ray random_ray_towards(Rng& rng, const Vec3& centre, double R) {
  const Vec3 from = centre + 3 * R * test::uniform_sphere(rng);
  const Vec3 to = centre + R * std::cbrt(rng.uniform()) * test::uniform_sphere(rng);
  return {from, glm::normalize(to - from)};
}

// An ellipsoid x^2/A^2 + y^2/B^2 + z^2/C^2 = 1 around `centre`: as a star-shaped surface
// (r(u) = 1 / sqrt(sum u_k^2 / A_k^2)), and its exact intersection (the unit sphere in coordinates
// scaled by 1/A, 1/B, 1/C).
struct Ellipsoid {
  Vec3 centre, axes;

  double level(const Vec3& p) const {  // x^2/A^2 + ... - 1
    const Vec3 q = (p - centre) / axes;
    return glm::dot(q, q) - 1;
  }
  Vec3 normal(const Vec3& p) const { return glm::normalize((p - centre) / (axes * axes)); }
  double radius(const Vec3& u) const { return 1 / std::sqrt(glm::dot(u / axes, u / axes)); }
  double max_axis() const { return std::max({axes.x, axes.y, axes.z}); }

  StarSurface star(bool analytic_normal) const {
    StarSurface::NormalFn nf;
    if (analytic_normal) nf = [this](const Vec3& u) { return normal(centre + radius(u) * u); };
    return StarSurface(centre, [this](const Vec3& u) { return radius(u); }, max_axis(), nf);
  }

  // First root t > t_min of |(o + t d - c) / axes|^2 = 1, in long double.
  std::optional<double> exact_t(const Ray& ray, double t_min) const {
    using L = long double;
    L o[3], d[3], a2 = 0, b = 0, c = -1;
    for (int k = 0; k < 3; ++k) {
      o[k] = (L(ray.origin[k]) - L(centre[k])) / L(axes[k]);
      d[k] = L(ray.direction[k]) / L(axes[k]);
      a2 += d[k] * d[k];
      b += o[k] * d[k];
      c += o[k] * o[k];
    }
    const L disc = b * b - a2 * c;
    if (disc < 0) return std::nullopt;
    const L t0 = (-b - std::sqrt(disc)) / a2, t1 = (-b + std::sqrt(disc)) / a2;
    if (t0 > t_min) return double(t0);
    if (t1 > t_min) return double(t1);
    return std::nullopt;
  }
};

struct Uniform final : scene::Environment {
  scene::Rgb radiance(const Vec3&) const override { return {1, 1, 1}; }
};
// A smooth function of direction, different in every channel.
struct Gradient final : scene::Environment {
  scene::Rgb radiance(const Vec3& d) const override {
    return {0.5 + 0.5 * d.y, d.x * d.x, 1 + d.z + 0.25 * d.x * d.y};
  }
};

double total(const TraceSummary& s) {
  return s.exit_weight + s.dropped_depth + s.dropped_min_weight + s.lost;
}

// ------------------------------------------------------------------------------------------------
// Surfaces
// ------------------------------------------------------------------------------------------------

TEST(SphereSurface, AnalyticHits) {
  const SphereSurface s({0, 0, 2}, 0.5);
  const auto h = s.intersect({{0, 0, 0}, {0, 0, 1}}, 0.0);
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 1.5);
  EXPECT_LT(glm::length(h->normal - Vec3{0, 0, -1}), 1e-15);
  // From inside (the centre): the far side, normal outward.
  const auto in = s.intersect({{0, 0, 2}, {1, 0, 0}}, 0.0);
  ASSERT_TRUE(in);
  EXPECT_DOUBLE_EQ(in->t, 0.5);
  EXPECT_LT(glm::length(in->normal - Vec3{1, 0, 0}), 1e-15);
  // t_min skips the front hit; a ray pointing away misses.
  const auto back = s.intersect({{0, 0, 0}, {0, 0, 1}}, 1.6);
  ASSERT_TRUE(back);
  EXPECT_DOUBLE_EQ(back->t, 2.5);
  EXPECT_FALSE(s.intersect({{0, 0, 0}, {0, 0, -1}}, 0.0));
  EXPECT_FALSE(s.intersect({{0, 0.6, 0}, {0, 0, 1}}, 0.0));
  EXPECT_THROW(SphereSurface({0, 0, 0}, 0.0), DomainError);
}

// A 1 mm drop 1 km away: the stable form keeps its hits on the sphere and its grazing hits. Hit
// points are within a few rounding units of the coordinates (1e3 * 2.2e-16 = 2e-13 m) of the
// sphere; the tolerance 1e-12 m is 1e-9 of the radius.
TEST(SphereSurface, SmallSphereFarAway) {
  const Vec3 c{0.3, -0.2, 1000};
  const double a = 1e-3;
  const SphereSurface s(c, a);
  Rng rng(3);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 target = c + a * 1.2 * Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, 0} * 2.0;
    const Ray ray{{0, 0, 0}, glm::normalize(target)};
    const auto h = s.intersect(ray, 0.0);
    // The distance from the centre to the ray's line, in long double, decides hit or miss.
    const long double b = glm::dot(c, ray.direction);
    const Vec3 perp = c - double(b) * ray.direction;
    const double miss_by = glm::length(perp) - a;
    if (std::abs(miss_by) < 1e-12) continue;  // too close to call
    ASSERT_EQ(bool(h), miss_by < 0) << k;
    if (!h) continue;
    ++hits;
    EXPECT_NEAR(glm::length(h->point - c), a, 1e-12);
    EXPECT_LT(glm::length(ray.origin + h->t * ray.direction - h->point), 1e-12);
  }
  EXPECT_GT(hits, 800);
}

// StarSurface with r(u) = a is the sphere: the same hits as SphereSurface to 1e-10 of the radius
// (the root is refined to 1e-12 of the bounding radius; the numerical normal is good to ~1e-12),
// for rays from outside, from inside and from points on the surface moving either way.
TEST(StarSurface, SphereMatchesAnalytic) {
  const Vec3 c{0.1, -0.2, 2};
  const double a = 0.5;
  const SphereSurface sphere(c, a);
  const StarSurface star(c, [a](const Vec3&) { return a; }, a);
  Rng rng(11);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    Ray ray;
    double t_min = 0;
    switch (k % 3) {
      case 0: ray = random_ray_towards(rng, c, 1.1 * a); break;
      case 1:
        ray = {c + 0.99 * a * std::cbrt(rng.uniform()) * test::uniform_sphere(rng), test::uniform_sphere(rng)};
        break;
      default: {
        // On the surface (as after a refraction), with a small t_min.
        const Vec3 u = test::uniform_sphere(rng);
        ray = {c + a * u, test::uniform_sphere(rng)};
        t_min = 1e-9;
      }
    }
    const auto hs = sphere.intersect(ray, t_min);
    const auto ht = star.intersect(ray, t_min);
    ASSERT_EQ(bool(hs), bool(ht)) << k;
    if (!hs) continue;
    ++hits;
    EXPECT_NEAR(ht->t, hs->t, 1e-10 * a) << k;
    EXPECT_LT(glm::length(ht->point - hs->point), 1e-10 * a) << k;
    EXPECT_LT(glm::length(ht->normal - hs->normal), 1e-10) << k;
  }
  EXPECT_GT(hits, 2000);
}

// A ray grazing the sphere so closely that its chord (2 a sqrt(2e-6) = 0.0028 a) is ten times
// shorter than the sampling step (a / 32): the sliver search finds it; a ray passing just outside
// finds nothing.
TEST(StarSurface, FindsThinSlivers) {
  const double a = 1;
  const StarSurface star({0, 0, 0}, [a](const Vec3&) { return a; }, a);
  const SphereSurface sphere({0, 0, 0}, a);
  for (double off : {1 - 1e-6, 1 - 1e-8}) {
    const Ray ray{{off, 0, -3}, {0, 0, 1}};
    const auto hs = sphere.intersect(ray, 0.0);
    const auto ht = star.intersect(ray, 0.0);
    ASSERT_TRUE(hs);
    ASSERT_TRUE(ht) << off;
    EXPECT_NEAR(ht->t, hs->t, 1e-10);
  }
  EXPECT_FALSE(star.intersect({{1 + 1e-9, 0, -3}, {0, 0, 1}}, 0.0));
}

// An ellipsoid (axes 0.8, 0.5, 0.6) through StarSurface: hit points on the ellipsoid to 1e-10
// (of the level function, i.e. of the radius), t against the exact quadratic to 1e-10, and normals
// against the analytic gradient to 1e-8 whether given analytically or differentiated numerically
// (measured: 5e-12 at worst).
TEST(StarSurface, EllipsoidMatchesAnalytic) {
  const Ellipsoid e{{0.05, 0.1, 2}, {0.8, 0.5, 0.6}};
  Rng rng(5);
  double worst_normal = 0;
  for (bool analytic : {false, true}) {
    const auto star = e.star(analytic);
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
      Ray ray;
      if (k % 2 == 0) {
        ray = random_ray_towards(rng, e.centre, e.max_axis());
      } else {  // from inside
        const Vec3 u = test::uniform_sphere(rng);
        ray = {e.centre + 0.99 * e.radius(u) * rng.uniform() * u, test::uniform_sphere(rng)};
      }
      const auto h = star.intersect(ray, 0.0);
      const auto t = e.exact_t(ray, 0.0);
      ASSERT_EQ(bool(h), bool(t)) << k;
      if (!h) continue;
      ++hits;
      EXPECT_NEAR(h->t, *t, 1e-10) << k;
      EXPECT_LT(std::abs(e.level(h->point)), 1e-10) << k;
      const double dn = glm::length(h->normal - e.normal(h->point));
      EXPECT_LT(dn, 1e-8) << k;
      worst_normal = std::max(worst_normal, dn);
    }
    EXPECT_GT(hits, 1200);
  }
  std::printf("ellipsoid: worst normal error %.2e\n", worst_normal);
}

// A non-convex star shape, r = a (1 + 0.12 cos 4 theta) (theta from +z: dents around the
// equator and the poles): first hits against a brute-force search (20000 samples along the chord,
// then bisection; slivers thinner than 1e-4 of the chord are beyond it, and none showed up) to
// 1e-10, for rays from outside, inside and from surface points.
TEST(StarSurface, NonConvexMatchesBruteForce) {
  const double a = 0.5;
  const Vec3 c{0, 0.1, 2};
  const auto r = [a](const Vec3& u) {
    return a * (1 + 0.12 * std::cos(4 * std::acos(std::clamp(u.z, -1.0, 1.0))));
  };
  const StarSurface star(c, r, 1.12 * a);
  const auto brute = [&](const Ray& ray, double t_min) -> std::optional<double> {
    const auto f = [&](double t) {
      const Vec3 v = ray.origin + t * ray.direction - c;
      return glm::length(v) - r(glm::normalize(v));
    };
    const double t_end = glm::length(ray.origin - c) + 1.2 * a;
    const int n = 20000;
    double t0 = t_min, f0 = f(t0);
    for (int k = 1; k <= n; ++k) {
      double t1 = t_min + (t_end - t_min) * k / n;
      const double f1 = f(t1);
      if ((f0 > 0) != (f1 > 0)) {
        for (int it = 0; it < 200; ++it) {
          const double m = (t0 + t1) / 2;
          ((f(m) > 0) == (f0 > 0) ? t0 : t1) = m;
        }
        return (t0 + t1) / 2;
      }
      t0 = t1;
      f0 = f1;
    }
    return std::nullopt;
  };
  Rng rng(41);
  int hits = 0;
  for (int k = 0; k < 600; ++k) {
    Ray ray;
    double t_min = 0;
    if (k % 3 == 0) {
      ray = random_ray_towards(rng, c, 1.12 * a);
    } else if (k % 3 == 1) {
      const Vec3 u = test::uniform_sphere(rng);
      ray = {c + 0.98 * r(u) * rng.uniform() * u, test::uniform_sphere(rng)};
    } else {
      const Vec3 u = test::uniform_sphere(rng);
      ray = {c + r(u) * u, test::uniform_sphere(rng)};
      t_min = 1e-7;
    }
    const auto h = star.intersect(ray, t_min);
    const auto t = brute(ray, t_min);
    ASSERT_EQ(bool(h), bool(t)) << k;
    if (!h) continue;
    ++hits;
    EXPECT_NEAR(h->t, *t, 1e-10) << k;
  }
  EXPECT_GT(hits, 300);
}

TEST(StarSurface, RejectsBadRadii) {
  EXPECT_THROW(StarSurface({0, 0, 0}, [](const Vec3&) { return 1.0; }, 0.0), DomainError);
  EXPECT_THROW(StarSurface({0, 0, 0}, nullptr, 1.0), DomainError);
  const StarSurface too_big({0, 0, 0}, [](const Vec3&) { return 2.0; }, 1.0);
  EXPECT_THROW((void)too_big.intersect({{0, 0, -3}, {0, 0, 1}}, 0.0), DomainError);
}

// ------------------------------------------------------------------------------------------------
// The Fresnel-split tracer
// ------------------------------------------------------------------------------------------------

// Power conservation: R + T = 1 at every split, so what leaves plus what is still inside at the
// depth limit is 1, to the rounding of 64 products and sums (a few 1e-15; asserted 1e-12). For the
// ellipsoid, total internal reflection traps some paths for many bounces: that weight is in
// dropped_depth.
TEST(TracePaths, ConservesPower) {
  const SphereSurface sphere({0, 0, 2}, 0.5);
  const Ellipsoid e{{0, 0, 2}, {0.7, 0.45, 0.5}};
  const auto ellipsoid = e.star(false);
  TraceOptions deep;
  deep.max_depth = 64;
  Rng rng(23);
  double worst = 0, trapped = 0;
  for (double mu : {1.333, 1.49}) {
    for (const DropSurface* s : {static_cast<const DropSurface*>(&sphere),
                                 static_cast<const DropSurface*>(&ellipsoid)}) {
      int hits = 0;
      for (int k = 0; k < 300; ++k) {
        const Ray ray = random_ray_towards(rng, s->centre(), s->bounding_radius());
        double reported = 0;
        const auto sum = trace_paths(*s, ray, mu, deep, [&](const ExitPath& p) {
          reported += p.weight;
          EXPECT_NEAR(p.weight, p.weight_s + p.weight_p, 1e-15);
          EXPECT_NEAR(glm::length(p.ray.direction), 1, 1e-14);
        });
        EXPECT_EQ(sum.lost, 0);
        EXPECT_DOUBLE_EQ(reported, sum.exit_weight);
        worst = std::max(worst, std::abs(total(sum) - 1));
        EXPECT_NEAR(total(sum), 1, 1e-12) << mu << " " << k;
        hits += sum.hit;
        if (s == &ellipsoid) trapped = std::max(trapped, sum.dropped_depth);
      }
      EXPECT_GT(hits, 100);
    }
  }
  // With a weight cut-off the dropped weight is accounted for as well.
  TraceOptions cut;
  cut.min_weight = 1e-3;
  for (int k = 0; k < 100; ++k) {
    const auto sum = trace_paths(ellipsoid, random_ray_towards(rng, e.centre, 0.7), 1.333, cut, {});
    EXPECT_NEAR(total(sum), 1, 1e-12);
  }
  std::printf("power: worst |sum - 1| = %.2e; ellipsoid, most weight trapped at depth 64: %.3g\n",
              worst, trapped);
}

// A non-convex drop: rays that leave can meet the surface again (PathKind::Other); power is
// still conserved to rounding and no ray inside loses its way out.
TEST(TracePaths, NonConvexDrop) {
  const double a = 0.5;
  const auto r = [a](const Vec3& u) {
    return a * (1 + 0.12 * std::cos(4 * std::acos(std::clamp(u.z, -1.0, 1.0))));
  };
  const StarSurface star({0, 0, 2}, r, 1.12 * a);
  TraceOptions deep;
  deep.max_depth = 32;
  Rng rng(43);
  int other = 0;
  for (int k = 0; k < 200; ++k) {
    const auto sum = trace_paths(star, random_ray_towards(rng, {0, 0, 2}, 1.12 * a), 1.333, deep,
                                 [&](const ExitPath& p) { other += p.kind == PathKind::Other; });
    EXPECT_NEAR(total(sum), 1, 1e-12);
    EXPECT_EQ(sum.lost, 0);
  }
  EXPECT_GT(other, 0);
}

// The tracer through StarSurface(r = a) and through SphereSurface: the same paths, weights to
// 1e-10 and directions to 1e-9 (the star surface's hits are good to ~1e-12 of the radius and its
// numerical normals to ~1e-12; a path of 8 interactions compounds them).
TEST(TracePaths, StarSphereTracesLikeTheSphere) {
  const Vec3 c{0, 0, 2};
  const SphereSurface sphere(c, 0.5);
  const StarSurface star(c, [](const Vec3&) { return 0.5; }, 0.5);
  Rng rng(47);
  for (int k = 0; k < 200; ++k) {
    const Ray ray = random_ray_towards(rng, c, 0.5);
    std::vector<ExitPath> a, b;
    trace_paths(sphere, ray, 1.49, {}, [&](const ExitPath& p) { a.push_back(p); });
    trace_paths(star, ray, 1.49, {}, [&](const ExitPath& p) { b.push_back(p); });
    ASSERT_EQ(a.size(), b.size()) << k;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].kind, b[i].kind);
      EXPECT_EQ(a[i].internal_reflections, b[i].internal_reflections);
      EXPECT_NEAR(a[i].weight, b[i].weight, 1e-10);
      EXPECT_LT(glm::length(a[i].ray.direction - b[i].ray.direction), 1e-9);
      EXPECT_LT(glm::length(a[i].ray.origin - b[i].ray.origin), 1e-9);
    }
  }
}

// For a sphere every ray that hits gives one reflection, one refraction and max_depth - 2 paths
// with N = 1 .. max_depth - 2 internal reflections; a miss is reported as itself with weight 1.
TEST(TracePaths, PathStructureOfASphere) {
  const SphereSurface sphere({0, 0, 2}, 0.5);
  TraceOptions options;  // max_depth 8
  std::vector<ExitPath> paths;
  const auto sum = trace_paths(sphere, {{0, 0, 0}, glm::normalize(Vec3{0.1, 0.05, 1})}, 1.333,
                               options, [&](const ExitPath& p) { paths.push_back(p); });
  EXPECT_TRUE(sum.hit);
  ASSERT_EQ(paths.size(), 8u);
  std::vector<int> internal_seen(7, 0);
  for (const auto& p : paths) {
    switch (p.kind) {
      case PathKind::Reflection: EXPECT_EQ(p.interactions, 1); break;
      case PathKind::Refraction: EXPECT_EQ(p.interactions, 2); break;
      case PathKind::Internal: EXPECT_EQ(p.interactions, 2 + p.internal_reflections); break;
      default: ADD_FAILURE() << "unexpected path kind";
    }
    if (p.kind != PathKind::Reflection) ++internal_seen[std::size_t(p.internal_reflections)];
    // Exit points are on the sphere.
    EXPECT_NEAR(glm::length(p.ray.origin - Vec3{0, 0, 2}), 0.5, 1e-15);
  }
  for (int n = 0; n <= 6; ++n) EXPECT_EQ(internal_seen[std::size_t(n)], 1) << n;
  EXPECT_GT(sum.dropped_depth, 0);

  std::vector<ExitPath> miss;
  const Ray away{{0, 0, 0}, {0, 1, 0}};
  const auto none =
      trace_paths(sphere, away, 1.333, options, [&](const ExitPath& p) { miss.push_back(p); });
  EXPECT_FALSE(none.hit);
  ASSERT_EQ(miss.size(), 1u);
  EXPECT_EQ(miss[0].kind, PathKind::Miss);
  EXPECT_EQ(miss[0].weight, 1);
  EXPECT_EQ(miss[0].ray.direction, away.direction);
}

TEST(TracePaths, Validation) {
  const SphereSurface sphere({0, 0, 2}, 0.5);
  const Ray ray{{0, 0, 0}, {0, 0, 1}};
  TraceOptions o;
  EXPECT_NO_THROW((void)trace_paths(sphere, ray, 1.333, o, {}));
  o.max_depth = 5;
  EXPECT_THROW((void)trace_paths(sphere, ray, 1.333, o, {}), DomainError);
  o.max_depth = 65;
  EXPECT_THROW((void)trace_paths(sphere, ray, 1.333, o, {}), DomainError);
  o = {};
  o.min_weight = -1;
  EXPECT_THROW((void)trace_paths(sphere, ray, 1.333, o, {}), DomainError);
  EXPECT_THROW((void)trace_paths(sphere, ray, 0.0, {}, {}), DomainError);
  EXPECT_THROW((void)trace_paths(sphere, {{0, 0, 0}, {0, 0, 2}}, 1.333, {}, {}), DomainError);
}

// The model's directions are the sphere's exact geometry (model.hpp): for camera rays from a
// camera at the origin to a sphere at (0, 0, 2) (every pixel off the axis, alpha up to 14.5
// degrees), the tracer's exit directions for 0, 1, 2 internal reflections and the reflection equal
// drop_rays' for the same view and the normal where the ray meets the sphere, to 1e-9 (measured
// 6e-12 at worst, near grazing entry; the tracer nudges each new ray ~1e-13 of the radius off the
// surface, which turns the path by about as much, and the rest is rounding).
// Weights: the tracer keeps s and p apart. A refraction-only path crosses two interfaces at the
// same angle pair (i, q), and T(i: 1 -> mu) = T(q: mu -> 1) for each polarisation, so its weight
// is (T_s^2 + T_p^2) / 2, and with N internal reflections (T_s^2 R_s^N + T_p^2 R_p^N) / 2, where
// the model's unpolarised transfer is ((T_s + T_p) / 2)^2 = (1 - k)^2 and k^N (1 - k)^2. For
// refraction the model is low by exactly ((T_s - T_p) / 2)^2 = ((R_s - R_p) / 2)^2: the variance of
// the two polarisations' transmittances (Jensen's inequality for the square). Weight tolerance
// 1e-11: the nudge above changes the exit angle by ~1e-13 rad, and T's slope grows without bound
// towards grazing incidence (measured 3e-12 at worst for cos i >= 1e-3).
TEST(TracePaths, SphereMatchesTheModel) {
  const Vec3 c{0, 0, 2};
  const SphereSurface sphere(c, 0.5);
  TraceOptions options;
  Rng rng(29);
  int tested = 0;
  double worst_dir = 0, worst_gap = 0, worst_weight = 0;
  for (int k = 0; k < 3000; ++k) {
    // A random direction within the sphere's silhouette cone (half angle asin(0.25) = 14.5 deg).
    const Vec3 target = c + 0.5 * std::cbrt(rng.uniform()) * test::uniform_sphere(rng);
    const Ray ray{{0, 0, 0}, glm::normalize(target)};
    const auto first = sphere.intersect(ray, 0.0);
    if (!first) continue;
    const double cos_i = -glm::dot(ray.direction, first->normal);
    if (cos_i < 1e-3) continue;  // too close to grazing for drop_rays' clamp to matter
    ++tested;
    const auto model = drop_rays(ray.direction, first->normal, 1.333, 2);
    const auto f_in = optics::fresnel_dielectric(cos_i, 1.0, 1.333);
    const double Ts = f_in.T_s, Tp = f_in.T_p, Rs = f_in.R_s, Rp = f_in.R_p;
    trace_paths(sphere, ray, 1.333, options, [&](const ExitPath& p) {
      const auto check_dir = [&](const Vec3& expected) {
        const double err = glm::length(p.ray.direction - expected);
        worst_dir = std::max(worst_dir, err);
        EXPECT_LT(err, 1e-9) << k;
      };
      switch (p.kind) {
        case PathKind::Reflection:
          check_dir(model.reflection);
          EXPECT_NEAR(p.weight, model.S, 1e-14);
          EXPECT_NEAR(p.weight_s, Rs / 2, 1e-14);
          EXPECT_NEAR(p.weight_p, Rp / 2, 1e-14);
          EXPECT_LT(glm::length(p.ray.origin - first->point), 1e-15);
          break;
        case PathKind::Refraction: {
          check_dir(model.refraction);
          EXPECT_NEAR(p.weight, (Ts * Ts + Tp * Tp) / 2, 1e-11);
          worst_weight = std::max(worst_weight, std::abs(p.weight - (Ts * Ts + Tp * Tp) / 2));
          const double gap = p.weight - model.R;
          EXPECT_NEAR(gap, sqr((Ts - Tp) / 2), 1e-11);
          EXPECT_GE(gap, -1e-15);
          worst_gap = std::max(worst_gap, gap);
          break;
        }
        case PathKind::Internal:
          if (p.internal_reflections <= 2) {
            const int n = p.internal_reflections;
            check_dir(model.internal[std::size_t(n - 1)]);
            const double expected = (Ts * Ts * std::pow(Rs, n) + Tp * Tp * std::pow(Rp, n)) / 2;
            EXPECT_NEAR(p.weight, expected, 1e-11);
            worst_weight = std::max(worst_weight, std::abs(p.weight - expected));
          }
          break;
        default: ADD_FAILURE();
      }
    });
  }
  EXPECT_GT(tested, 2000);
  std::printf("sphere vs drop_rays: worst direction difference %.2e; worst weight error %.2e; "
              "refraction weight - (1-k)^2 up to %.4f\n", worst_dir, worst_weight, worst_gap);
}

// The polarisation gap of the refraction weight against the image radius (alpha = 0, water):
// zero at the centre, (T_s - T_p)^2 / 4 growing towards the rim. Printed for the docs; the values
// at rho = 0.5 and 0.9 pin the formula.
TEST(TracePaths, PolarisationGapAlongTheRadius) {
  const SphereSurface sphere({0, 0, 0}, 1.0);
  std::printf("rho   exact R     model (1-k)^2  gap\n");
  for (double rho : {0.0, 0.5, 0.8, 0.9, 0.95, 0.99}) {
    double exact = 0;
    trace_paths(sphere, {{rho, 0, -3}, {0, 0, 1}}, 1.333, {}, [&](const ExitPath& p) {
      if (p.kind == PathKind::Refraction) exact = p.weight;
    });
    const double model = drop_paths_at_rho(rho, 1.333, 0).R;
    std::printf("%.2f  %.6f    %.6f       %.2e\n", rho, exact, model, exact - model);
    const auto f = optics::fresnel_dielectric(std::sqrt(1 - rho * rho), 1.0, 1.333);
    EXPECT_NEAR(exact - model, sqr((f.T_s - f.T_p) / 2), 1e-11);
  }
}

// The radiance along a camera ray from a distant environment is the weighted sum over the exit
// paths; a miss gives nothing.
TEST(TraceRadiance, SumsTheExitPaths) {
  const SphereSurface sphere({0, 0, 2}, 0.5);
  const Gradient env;
  const Ray ray{{0, 0, 0}, glm::normalize(Vec3{0.12, -0.07, 1})};
  scene::Rgb expected{0, 0, 0};
  trace_paths(sphere, ray, 1.333, {}, [&](const ExitPath& p) {
    expected += p.weight * env.radiance(p.ray.direction);
  });
  const auto got = trace_radiance(sphere, ray, 1.333, env);
  ASSERT_TRUE(got);
  EXPECT_LT(glm::length(*got - expected), 1e-15);
  EXPECT_FALSE(trace_radiance(sphere, {{0, 0, 0}, {0, 1, 0}}, 1.333, env));
  // A uniform environment gives what is not dropped: 1 - dropped_depth.
  const auto sum = trace_paths(sphere, ray, 1.333, {}, {});
  const auto uniform = trace_radiance(sphere, ray, 1.333, Uniform{});
  EXPECT_NEAR(uniform->x, 1 - sum.dropped_depth, 1e-14);
}

// Seed 000, Figure 4: with a uniform environment (Le = 1, alpha = 0) refraction dominates a water
// drop's radiance away from the rim. Measured with the exact tracer (all paths to depth 64; the
// pixel's radiance is then 1 to 1e-12, nothing being absorbed), the refraction-only share:
//   rho    0     0.5     0.7     0.8     0.85    0.9     0.95    0.97    0.98    0.99
//   share  0.9597 0.9577 0.9465 0.9248 0.8996 0.8483 0.7187 0.6001 0.5019 0.3455
// (Brewster's angle for water, 53.1 degrees, is at rho = 0.80: there the p wave enters and leaves
// whole). So the share exceeds 0.92 for rho <= 0.8 (asserted), 0.9 up to rho ~ 0.85, and the
// reflected paths together overtake refraction only at rho ~ 0.98, as test_model.cpp finds with the
// model. The model's share R / (R + S + P_1 + P_2) from radiance_profile is within 0.006 of the
// exact one up to rho = 0.95 (asserted 0.01): its R is low by the polarisation gap above, and it
// stops at N = 2.
TEST(TracePaths, RefractionDominatesAwayFromTheRim) {
  const SphereSurface sphere({0, 0, 0}, 1.0);
  const Uniform env;
  TraceOptions deep;
  deep.max_depth = 64;
  const auto profile = radiance_profile(1.333, 201, 2);  // rho in steps of 0.005
  std::printf("rho    exact R   exact share  model R   model share\n");
  for (const int s : {0, 20, 40, 60, 80, 100, 120, 140, 150, 160, 170, 180, 190, 194, 196, 198}) {
    const double rho = profile.rho[std::size_t(s)];
    const Ray ray{{rho, 0, -3}, {0, 0, 1}};
    double refraction = 0;
    const auto sum = trace_paths(sphere, ray, 1.333, deep, [&](const ExitPath& p) {
      if (p.kind == PathKind::Refraction) refraction = p.weight;
    });
    const double radiance = trace_radiance(sphere, ray, 1.333, env, deep)->x;
    EXPECT_NEAR(radiance, sum.exit_weight, 1e-14);
    EXPECT_NEAR(radiance, 1, 1e-12);  // lossless: the uniform environment comes back whole
    const double share = refraction / radiance;
    const auto k = std::size_t(s);
    const double model_share =
        profile.refraction[k] / (profile.refraction[k] + profile.reflection[k] +
                                 profile.internal[0][k] + profile.internal[1][k]);
    std::printf("%.3f  %.4f    %.4f       %.4f    %.4f\n", rho, refraction, share,
                profile.refraction[k], model_share);
    if (rho <= 0.8) {
      EXPECT_GT(share, 0.92) << rho;
    }
    if (rho <= 0.95) {
      EXPECT_NEAR(share, model_share, 0.01) << rho;
    }
    if (rho <= 0.97) {
      EXPECT_GT(share, 0.5) << rho;  // refraction outweighs everything else together
    }
  }
}

}  // namespace
}  // namespace hydrolux::drop
