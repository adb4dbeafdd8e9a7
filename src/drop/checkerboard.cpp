#include "hydrolux/drop/checkerboard.hpp"
#include "hydrolux/optics/snell.hpp"

#include <cmath>
#include <limits>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/trace.hpp"

namespace hydrolux::drop {

namespace {
constexpr const char* kContext = "the checkerboard experiment (Garg & Nayar 2004, section 4.4)";

double image_radius_px(const CheckerboardSetup& s) { return s.diameter_px / 2; }

Vec3 ball_centre(const CheckerboardSetup& s) { return {0, 0, s.distance_m}; }

double board_z(const CheckerboardSetup& s) { return s.distance_m + s.board_behind_centre_m; }

// Where a ray from `origin` along `dir` meets the board plane; nothing if it runs parallel to the
// board or away from it.
std::optional<BoardPoint> on_board(const CheckerboardSetup& s, const Vec3& origin,
                                   const Vec3& dir) {
  if (!(dir.z > 1e-12)) return std::nullopt;
  const double t = (board_z(s) - origin.z) / dir.z;
  if (t < 0) return std::nullopt;
  return BoardPoint{origin.x + t * dir.x, origin.y + t * dir.y};
}
}  // namespace

void validate(const CheckerboardSetup& s) {
  require_in_range("radius_m", s.radius_m, 1e-6, 1.0, kContext);
  require_in_range("distance_m", s.distance_m, 1.01 * s.radius_m, 1e4, kContext);
  require_in_range("board_behind_centre_m", s.board_behind_centre_m, 1.01 * s.radius_m, 1e3,
                   kContext);
  require_in_range("mu", s.mu, 1.0001, 10.0, kContext);
  require_in_range("square_m", s.square_m, 1e-6, 10.0, kContext);
  require_in_range("diameter_px", s.diameter_px, 10.0, 1e5, kContext);
}

double focal_px(const CheckerboardSetup& s) {
  // The silhouette is the cone of half-angle asin(a / D) tangent to the ball; its image circle
  // has radius f tan(asin(a / D)) = f a / sqrt(D^2 - a^2).
  return image_radius_px(s) * std::sqrt(sqr(s.distance_m) - sqr(s.radius_m)) / s.radius_m;
}

Ray pixel_ray(const CheckerboardSetup& s, const ImagePoint& pixel) {
  return {{0, 0, 0}, glm::normalize(Vec3{pixel.x, pixel.y, focal_px(s)})};
}

std::optional<BoardPoint> board_point(const CheckerboardSetup& s, BoardMapping mapping,
                                      const ImagePoint& pixel) {
  validate(s);
  const SphereSurface ball(ball_centre(s), s.radius_m);
  switch (mapping) {
    case BoardMapping::Exact: {
      // The refraction-only path of the Fresnel-split trace, from the point where it leaves the
      // ball: no assumption about the scene's distance.
      std::optional<Ray> exit;
      TraceOptions options;
      options.max_depth = 6;
      trace_paths(ball, pixel_ray(s, pixel), s.mu, options, [&](const ExitPath& e) {
        if (e.kind == PathKind::Refraction) exit = e.ray;
      });
      if (!exit) return std::nullopt;
      return on_board(s, exit->origin, exit->direction);
    }
    case BoardMapping::Model: {
      // The model's direction for this pixel's view and the normal where the view meets the
      // ball, sent from the centre: the scene is taken to be far enough that where on the ball
      // the ray leaves does not matter.
      const Ray ray = pixel_ray(s, pixel);
      const auto hit = ball.intersect(ray, 0.0);
      if (!hit) return std::nullopt;
      const auto paths = drop_rays(ray.direction, hit->normal, s.mu, 0);
      return on_board(s, ball_centre(s), paths.refraction);
    }
    case BoardMapping::ModelExitPoint: {
      // The model's geometry for a finite scene: the view refracts at the entry point A by Snell's
      // law (angle q), crosses the ball along a chord of length 2 a cos q and leaves at B in the
      // model's refraction direction.
      const Ray ray = pixel_ray(s, pixel);
      const auto hit = ball.intersect(ray, 0.0);
      if (!hit) return std::nullopt;
      const auto inside = optics::refract(-ray.direction, hit->normal, s.mu);
      if (!inside) return std::nullopt;
      const Vec3 exit_point = hit->point + 2 * s.radius_m * inside->cos_t * inside->wt;
      const auto paths = drop_rays(ray.direction, hit->normal, s.mu, 0);
      return on_board(s, exit_point, paths.refraction);
    }
    case BoardMapping::ModelOrthographic: {
      // Seed 000's geometry: an orthographic view along +z; the image point at radius rho (in
      // units of the ball's image radius) sees the surface point whose normal has sin(theta_n)
      // = rho (image coordinates rho = m a sin(theta_n)), and the direction leaves from the centre.
      const double x = pixel.x / image_radius_px(s), y = pixel.y / image_radius_px(s);
      const double rho2 = x * x + y * y;
      if (rho2 > 1) return std::nullopt;
      const Vec3 normal{x, y, -std::sqrt(1 - rho2)};
      const auto paths = drop_rays({0, 0, 1}, normal, s.mu, 0);
      return on_board(s, ball_centre(s), paths.refraction);
    }
  }
  return std::nullopt;
}

bool checker_dark(const CheckerboardSetup& s, const BoardPoint& p) {
  const auto i = static_cast<long long>(std::floor(p.u / s.square_m));
  const auto j = static_cast<long long>(std::floor(p.v / s.square_m));
  return ((i + j) & 1) != 0;
}

std::optional<ImagePoint> image_of_board_point(const CheckerboardSetup& s, BoardMapping mapping,
                                               const BoardPoint& target, const ImagePoint& start) {
  validate(s);
  const double h = 1e-4 * image_radius_px(s);
  const auto residual = [&](const ImagePoint& p) -> std::optional<BoardPoint> {
    const auto b = board_point(s, mapping, p);
    if (!b) return std::nullopt;
    return BoardPoint{b->u - target.u, b->v - target.v};
  };
  ImagePoint p = start;
  auto r = residual(p);
  if (!r) return std::nullopt;
  for (int it = 0; it < 60; ++it) {
    // Jacobian d(u, v) / d(x, y) by central differences: the mapping is smooth inside the ball's
    // image, and an error of h^2 in the Jacobian only slows Newton's last steps, not its answer.
    const auto xp = residual({p.x + h, p.y}), xm = residual({p.x - h, p.y});
    const auto yp = residual({p.x, p.y + h}), ym = residual({p.x, p.y - h});
    if (!xp || !xm || !yp || !ym) return std::nullopt;
    const double a = (xp->u - xm->u) / (2 * h), b = (yp->u - ym->u) / (2 * h);
    const double c = (xp->v - xm->v) / (2 * h), d = (yp->v - ym->v) / (2 * h);
    const double det = a * d - b * c;
    if (!(std::abs(det) > 0)) return std::nullopt;
    const double dx = -(d * r->u - b * r->v) / det, dy = -(-c * r->u + a * r->v) / det;
    // Step halving: accept the first fraction of the Newton step that reduces |residual|.
    const double norm = std::hypot(r->u, r->v);
    double step_px = -1;  // length of the accepted step
    for (double lambda = 1; lambda > 1e-12 && step_px < 0; lambda /= 2) {
      const ImagePoint q{p.x + lambda * dx, p.y + lambda * dy};
      const auto rq = residual(q);
      if (rq && std::hypot(rq->u, rq->v) <= norm) {
        p = q;
        r = rq;
        step_px = lambda * std::hypot(dx, dy);
      }
    }
    if (step_px < 0) return std::nullopt;
    if (step_px < 1e-9) return p;
  }
  return std::nullopt;
}

CornerComparison compare_corners(const CheckerboardSetup& s, BoardMapping model, double rho_max) {
  validate(s);
  require_in_range("rho_max", rho_max, 1e-3, 0.999, kContext);
  if (model == BoardMapping::Exact) {
    throw DomainError("mapping", 0, 1, 2, "compare_corners: the model mapping must not be Exact");
  }
  const double radius_px = image_radius_px(s);

  // Starting points: a square grid of image samples inside a slightly larger disk, each with the
  // board point it sees under each mapping.
  struct Sample {
    ImagePoint pixel;
    BoardPoint board;
  };
  std::vector<Sample> exact_grid, model_grid;
  const int n = 48;
  const double spacing = radius_px / n;
  const double reach = std::min(1.0, rho_max + 0.05) * radius_px;
  double max_board = 0;  // the largest |u|, |v| the exact mapping reaches within rho_max
  for (int iy = -n; iy <= n; ++iy) {
    for (int ix = -n; ix <= n; ++ix) {
      const ImagePoint p{ix * spacing, iy * spacing};
      const double r = std::hypot(p.x, p.y);
      if (r > reach) continue;
      if (const auto b = board_point(s, BoardMapping::Exact, p)) {
        exact_grid.push_back({p, *b});
        if (r <= rho_max * radius_px)
          max_board = std::max({max_board, std::abs(b->u), std::abs(b->v)});
      }
      if (const auto b = board_point(s, model, p)) model_grid.push_back({p, *b});
    }
  }
  const auto nearest = [](const std::vector<Sample>& grid, const BoardPoint& target) {
    double best = std::numeric_limits<double>::infinity();
    ImagePoint at;
    for (const auto& g : grid) {
      const double dist = std::hypot(g.board.u - target.u, g.board.v - target.v);
      if (dist < best) {
        best = dist;
        at = g.pixel;
      }
    }
    return at;
  };

  CornerComparison out;
  out.diameter_px = s.diameter_px;
  const int k_max = int(std::ceil(max_board / s.square_m)) + 1;
  double sum2 = 0;
  for (int j = -k_max; j <= k_max; ++j) {
    for (int i = -k_max; i <= k_max; ++i) {
      const BoardPoint corner{i * s.square_m, j * s.square_m};
      const auto exact =
          image_of_board_point(s, BoardMapping::Exact, corner, nearest(exact_grid, corner));
      if (!exact) continue;
      const double rho = std::hypot(exact->x, exact->y) / radius_px;
      if (rho > rho_max) continue;
      const auto predicted = image_of_board_point(s, model, corner, nearest(model_grid, corner));
      if (!predicted) {
        ++out.unmatched;
        continue;
      }
      CornerMatch m;
      m.i = i;
      m.j = j;
      m.exact = *exact;
      m.model = *predicted;
      m.error_px = std::hypot(exact->x - predicted->x, exact->y - predicted->y);
      m.rho = rho;
      sum2 += sqr(m.error_px);
      out.max_px = std::max(out.max_px, m.error_px);
      out.corners.push_back(m);
    }
  }
  if (!out.corners.empty()) out.rms_px = std::sqrt(sum2 / double(out.corners.size()));
  out.rms_fraction = out.rms_px / s.diameter_px;
  return out;
}

}  // namespace hydrolux::drop
