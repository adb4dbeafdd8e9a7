// Rendering with the exact tracer: the reference the model's pictures are measured against.
#include <algorithm>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/scatter/drop_shape.hpp"

namespace hydrolux::drop {

Image render_exact(const DropCamera& camera, const scene::Environment& env, const ChannelIndex& mu,
                   const DropSurface& surface, const RenderOptions& options, const TraceOptions& trace) {
  validate(camera);
  for (double m : mu) require_in_range("mu", m, 1.0 + 1e-9, 10.0, "the exact drop tracer");
  const bool dispersive = !(mu[0] == mu[1] && mu[1] == mu[2]);
  const RayShader shade = [&](const Ray& ray) -> std::optional<scene::Rgb> {
    if (!dispersive) return trace_radiance(surface, ray, mu[0], env, trace);
    scene::Rgb out{0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      const auto l = trace_radiance(surface, ray, mu[std::size_t(c)], env, trace);
      if (!l) return std::nullopt;
      out[c] = (*l)[c];
    }
    return out;
  };
  return render(camera, env, options, shade);
}

std::unique_ptr<DropSurface> make_drop_surface(const DropCamera& camera, DropShapeKind shape) {
  validate(camera);
  const Vec3 centre{0, 0, camera.distance_m};
  if (shape == DropShapeKind::sphere) return std::make_unique<SphereSurface>(centre, camera.radius_m);
  const scatter::DropShape s = scatter::drop_shape(camera.radius_m);
  // The bounding sphere: the largest r(theta) over a fine sweep. Between samples h = pi / 2000 apart
  // the maximum can exceed the sampled one by at most |r''| h^2 / 8 ~ 1e-6 r for these shapes
  // (|r''| < 10 r); the margin of 1e-4 covers that a hundredfold.
  double r_max = 0;
  for (int k = 0; k <= 2000; ++k) r_max = std::max(r_max, scatter::shape_radius(s, kPi<> * k / 2000));
  return std::make_unique<StarSurface>(
      centre, [s](const Vec3& u) { return scatter::shape_radius_toward(s, u); }, r_max * (1 + 1e-4),
      [s](const Vec3& u) { return scatter::shape_normal_toward(s, u); });
}

}  // namespace hydrolux::drop
