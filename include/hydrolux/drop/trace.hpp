#pragma once
// The exact reference for the drop model (model.hpp): a ray tracer of a closed dielectric surface
// (a sphere, or any star-shaped drop such as Beard & Chuang's) that follows every Fresnel-split
// path, with no small-angle, distant-scene or orthographic assumption (seed 000 makes all three;
// docs/drop-exact-tracer.md lists what is exact here and what is not).
//
// Geometry: world frame of scene/environment.hpp and render.hpp (camera rays are render.hpp's
// Ray). A surface reports its first hit along a ray with the outward unit normal there.
//
// Transport: at every hit the ray splits into the reflected and the refracted ray (vector Snell,
// optics::refract), each carrying the power reflectance or transmittance of optics::
// fresnel_dielectric for that hit's angle; under total internal reflection only the reflected
// ray, with weight 1. The s- and p-polarised weights are tracked separately (unpolarised light:
// 1/2 each), relative to each hit's own plane of incidence. For a sphere every path stays in one
// plane of incidence, so this is exact; for any other shape the plane turns from hit to hit and
// the rotation of the polarisation frame (and the s-p mixing it brings) is neglected.
// Radiance: crossing into the drop multiplies radiance by mu^2 and crossing out by 1 / mu^2
// (seed 003; Garg & Nayar eqs. 9, 24); every reported path ends outside the drop after as many
// exits as entries, so the factors cancel and a path's radiance transfer is the product of its
// Fresnel power factors, the weight reported.
#include <functional>
#include <optional>

#include "hydrolux/core/vec.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::drop {

struct SurfaceHit {
  double t = 0;   // ray parameter: point = origin + t direction
  Vec3 point;     // on the surface
  Vec3 normal;    // outward unit normal
};

// A closed surface bounding the drop.
class DropSurface {
 public:
  virtual ~DropSurface() = default;
  // First intersection with t > t_min, or nothing. `ray.direction` must be a unit vector.
  virtual std::optional<SurfaceHit> intersect(const Ray& ray, double t_min) const = 0;
  // A sphere (centre, radius) enclosing the surface.
  virtual Vec3 centre() const = 0;
  virtual double bounding_radius() const = 0;
};

// A sphere, intersected analytically: the squared distance from the centre to the ray's line is
// computed from the perpendicular vector itself and the two roots from the stable form of the
// quadratic (Haines, Guenther & Akenine-Moeller, "Precision improvements for ray/sphere
// intersection", Ray Tracing Gems, 2019, ch. 7), so a small sphere far from the origin keeps its
// digits. Hit points are put back on the sphere (centre + radius * unit vector).
// DomainError ("radius") unless radius is in (0, 1e6].
class SphereSurface final : public DropSurface {
 public:
  SphereSurface(const Vec3& centre, double radius);
  std::optional<SurfaceHit> intersect(const Ray& ray, double t_min) const override;
  Vec3 centre() const override { return centre_; }
  double bounding_radius() const override { return radius_; }
  double radius() const { return radius_; }

 private:
  Vec3 centre_;
  double radius_;
};

// Any star-shaped closed surface: r(u) > 0 the distance from `centre` to the surface along each
// unit direction u, no larger than max_radius (the bounding sphere). Optionally the outward unit
// normal at the surface point along u; without it the normal is the normalised gradient of
// F(p) = |p - c| - r((p - c) / |p - c|), with r's angular derivatives taken by fourth-order central
// differences (error ~1e-11 or less for a surface as smooth as an ellipsoid or Beard & Chuang's:
// measured 5e-12 for an ellipsoid of axis ratio 1.6).
// Intersection (details in trace.cpp): F is sampled along the ray inside the bounding sphere at a
// step of 2 max_radius / samples_per_diameter; a sign change is refined by safeguarded secant
// steps (bisection when they stall) to 1e-12 max_radius, and every sampled local minimum of |F| is
// searched for a sliver the samples stepped over (golden section). Features of the surface
// narrower than about two steps can be missed; the default 64 samples resolve Beard & Chuang's
// series (up to cos 10 theta) with more than ten samples per lobe. DomainError ("max_radius",
// "samples_per_diameter") for a bad argument, and ("radius") when r is evaluated outside
// (0, max_radius (1 + 1e-9)] or NaN.
class StarSurface final : public DropSurface {
 public:
  using RadiusFn = std::function<double(const Vec3& unit_dir)>;
  using NormalFn = std::function<Vec3(const Vec3& unit_dir)>;
  StarSurface(const Vec3& centre, RadiusFn radius_toward, double max_radius,
              NormalFn normal_toward = {}, int samples_per_diameter = 64);
  std::optional<SurfaceHit> intersect(const Ray& ray, double t_min) const override;
  Vec3 centre() const override { return centre_; }
  double bounding_radius() const override { return max_radius_; }
  // r along unit direction u (checked), and the outward unit normal at the surface point along u.
  double radius_toward(const Vec3& unit_dir) const;
  Vec3 normal_toward(const Vec3& unit_dir) const;

 private:
  double signed_distance(const Vec3& p) const;  // F(p) = |p - c| - r(dir)
  Vec3 centre_;
  RadiusFn radius_;
  double max_radius_;
  NormalFn normal_;
  int samples_;
};

// Options of the Fresnel-split tracer.
struct TraceOptions {
  // Surface interactions (reflections and refractions) a path may make, in [6, 64]: with 8 a path
  // reaches N = 6 internal reflections (2 + N interactions).
  int max_depth = 8;
  // Paths whose weight (s + p) falls below this are dropped; 0 follows every path to max_depth.
  // In [0, 1].
  double min_weight = 0;
};

// Which path a ray leaving the drop took.
enum class PathKind {
  Miss,        // the camera ray never met the drop
  Reflection,  // reflected off the first surface it hit
  Refraction,  // entered and left, no reflection inside (the model's R path)
  Internal,    // entered, reflected inside internal_reflections >= 1 times, left (P_N)
  Other,       // anything else: a ray that met the surface again after leaving (non-convex drop)
};

struct ExitPath {
  Ray ray;                       // origin on the surface where it leaves (the camera's for a miss)
  double weight_s = 0, weight_p = 0;  // s- and p-polarised intensity weights (1/2 each at start)
  double weight = 0;             // weight_s + weight_p: the path's radiance transfer
  int internal_reflections = 0;  // reflections inside the drop
  int interactions = 0;          // surface interactions, the path's depth
  PathKind kind = PathKind::Miss;
};

struct TraceSummary {
  bool hit = false;            // the camera ray met the surface
  int exits = 0;               // paths reported
  double exit_weight = 0;      // sum of the reported weights
  double dropped_depth = 0;    // weight still travelling when its next hit would pass max_depth
  double dropped_min_weight = 0;  // weight of the paths dropped under min_weight
  double lost = 0;  // weight of rays inside the drop that found no way out (numerical failure)
};

using ExitCallback = std::function<void(const ExitPath&)>;

// Follows `camera_ray` (unit direction, starting outside the drop) through the drop of relative
// index mu in [0.1, 10] and reports every path that leaves to `on_exit` (may be empty), a miss
// as one path of weight 1. exit_weight + dropped_depth + dropped_min_weight + lost = 1 up to
// rounding (lost is 0 unless a ray grazing the inside of the surface loses its hit): the
// Fresnel factors conserve power at every split (nothing is absorbed). DomainError ("mu",
// "max_depth", "min_weight", "camera_ray_direction") for a bad argument.
TraceSummary trace_paths(const DropSurface& surface, const Ray& camera_ray, double mu,
                         const TraceOptions& options, const ExitCallback& on_exit);

// Radiance along the camera ray from an environment at infinity: sum over the exit paths of
// weight * env.radiance(exit direction) (the weight dropped at the depth limit contributes
// nothing), or nothing if the ray misses the drop. Exact for a scene at infinity only: for a scene
// at a finite distance the exit point matters as well, which is why trace_paths reports the
// whole exit ray.
std::optional<scene::Rgb> trace_radiance(const DropSurface& surface, const Ray& camera_ray,
                                         double mu, const scene::Environment& env,
                                         const TraceOptions& options = {});

}  // namespace hydrolux::drop
