// The gallery's rain drop figures: the drop on the builtin environment by the model and by the exact
// tracer, their difference, Beard & Chuang's drop, the environment itself, the undistorted view,
// and the drop shapes.
#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "entries.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/render.hpp"
#include "hydrolux/drop/trace.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/svg_plot.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/drop_shape.hpp"
#include "hydrolux/scene/environment.hpp"

namespace hydrolux::gallery::detail {

namespace {

constexpr int kSize = 384;        // drop pictures, pixels
constexpr int kSamples = 3;       // supersamples per axis

// Shared between the figures: rendered once, on first use.
struct DropRenders {
  scene::BuiltinSky sky;
  drop::DropCamera camera;
  double mu = 0;
  Image model, exact;
  // RMS of (model - exact) / mean exact radiance over the drop's pixels with rho <= 0.9 and on the
  // rim (0.9 < rho < 1), as in tests/drop/test_render_exact.cpp.
  double rms_inner = 0, rms_rim = 0;
};

const DropRenders& renders() {
  static const DropRenders r = [] {
    DropRenders d;
    d.camera.radius_m = 1e-3;
    d.camera.distance_m = 2.0;
    d.camera.frame_m = 5e-3;
    d.camera.width = d.camera.height = kSize;
    d.mu = optics::find_medium("water")->n(589.3) / optics::find_medium("air")->n(589.3);
    drop::RenderOptions opt;
    opt.samples_per_axis = kSamples;
    const drop::ChannelIndex mu{d.mu, d.mu, d.mu};
    d.model = drop::render_model(d.camera, d.sky, mu, opt);
    const auto sphere = drop::make_drop_surface(d.camera, drop::DropShapeKind::sphere);
    d.exact = drop::render_exact(d.camera, d.sky, mu, *sphere, opt, drop::TraceOptions{});
    const auto diff = drop::compare_by_zone(d.model, d.exact, d.camera);
    d.rms_inner = diff.inner;
    d.rms_rim = diff.rim;
    return d;
  }();
  return r;
}

Image rgb_only(const Image& in) {
  Image out(in.width, in.height, 3);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = in.at(x, y, c);
  return out;
}

Entry builtin_environment_figure() {
  return image_entry(
      "builtin_environment.png", "The builtin environment",
      "The procedural panorama behind hydrolux drop render --env builtin (equirectangular: straight ahead in the "
      "middle, the zenith at the top): a clear sky and sun, a road running ahead, grass checks, and landmarks on "
      "the horizon so that a drop's inverted, compressed view of it can be read.",
      [] { return scene::bake_equirect(scene::BuiltinSky{}, 1024, 2); });
}

Entry drop_model_figure() {
  return image_entry(
      "drop_model.png", "A rain drop from the builtin environment: Garg & Nayar's model",
      "A 1 mm drop 2 m from the camera, in focus, rendered by the model (eq. 19: refraction, reflection and two "
      "internal reflections, each Fresnel-weighted), every pixel with its own viewing direction, 3 x 3 samples "
      "per pixel. The drop shows the world behind it upside down (the road at the top, the sky at the bottom) "
      "squeezed into its 165.6 degree field of view, like Figure 8 of the paper.",
      [] { return rgb_only(renders().model); });
}

Entry drop_exact_figure() {
  return image_entry(
      "drop_exact.png", "The same drop by the exact tracer",
      fmt::format("Every Fresnel-split path followed to 8 surface interactions, s and p polarisation tracked "
                  "separately, no small-angle or distant-scene assumption. The model differs from it by "
                  "{:.2f}% RMS of the mean radiance within 0.9 of the drop's radius and by {:.1f}% on the "
                  "rim: its unpolarised Fresnel products part from the polarised ones towards grazing "
                  "incidence, and the sun's sub-pixel glints there weigh heavily.",
                  100 * renders().rms_inner, 100 * renders().rms_rim),
      [] { return rgb_only(renders().exact); });
}

Entry drop_difference_figure() {
  return image_entry(
      "drop_difference.png", "Model minus exact, x 20",
      "|model - exact| per channel, amplified 20 times. The differences sit at the rim, where the polarisation "
      "of the Fresnel factors and internal reflections beyond the second matter. Elsewhere refraction "
      "dominates; its direction is exact in the model for a sphere and its weight low only by the "
      "unpolarised product, ((T_s - T_p) / 2)^2.",
      [] {
        const auto& d = renders();
        Image diff(d.model.width, d.model.height, 3);
        for (int y = 0; y < diff.height; ++y)
          for (int x = 0; x < diff.width; ++x)
            for (int c = 0; c < 3; ++c) diff.at(x, y, c) = 20.f * std::abs(d.model.at(x, y, c) - d.exact.at(x, y, c));
        return diff;
      });
}

Entry drop_beard_chuang_figure() {
  return image_entry(
      "drop_beard_chuang.png", "A 2 mm falling drop: Beard & Chuang's shape, exact tracer",
      fmt::format("The equilibrium shape of a falling drop of 2 mm equivalent radius (Chuang & Beard 1990 cosine "
                  "series: rounded top, flattened base), traced exactly on the builtin environment. The model assumes a "
                  "sphere; at this size the real drop's axis ratio is {:.2f}.",
                  scatter::axis_ratio(scatter::drop_shape(2e-3))),
      [] {
        drop::DropCamera cam = renders().camera;
        cam.radius_m = 2e-3;
        cam.frame_m = 10e-3;
        cam.width = cam.height = 256;
        const auto surface = drop::make_drop_surface(cam, drop::DropShapeKind::beard_chuang);
        drop::RenderOptions opt;
        opt.samples_per_axis = 2;
        const double mu = renders().mu;
        return rgb_only(drop::render_exact(cam, renders().sky, {mu, mu, mu}, *surface, opt, drop::TraceOptions{}));
      });
}

Entry drop_undistorted_figure() {
  return image_entry(
      "drop_undistorted.png", "The world seen through the drop, undistorted",
      fmt::format("The model's drop picture above, with its refraction mapping inverted (Figure 9 of the paper): "
                  "a 60 degree perspective view straight ahead, recovered from the drop's {:.0f} pixel wide "
                  "image, with the refraction's Fresnel loss divided out. Compare the direct view beside it; "
                  "detail is lost to the drop's resolution and its compression of the view towards the rim.",
                  2 * renders().camera.drop_radius_px()),
      [] {
        const auto& d = renders();
        drop::UndistortView view;
        view.fov_deg = 60;
        view.width = view.height = 256;
        const auto c = d.camera.drop_center_px();
        return rgb_only(drop::undistort(d.model, c[0], c[1], d.camera.drop_radius_px(), d.mu, view, true));
      });
}

Entry direct_view_figure() {
  return image_entry(
      "direct_view.png", "The direct view for comparison",
      "The builtin environment seen directly by a 60 degree perspective camera looking the same way.",
      [] {
        drop::UndistortView view;
        view.fov_deg = 60;
        view.width = view.height = 256;
        Image img(view.width, view.height, 3);
        const scene::BuiltinSky sky;
        for (int y = 0; y < img.height; ++y)
          for (int x = 0; x < img.width; ++x) {
            const auto l = sky.radiance(view.direction(x + 0.5, y + 0.5));
            for (int ch = 0; ch < 3; ++ch) img.at(x, y, ch) = float(l[ch]);
          }
        return img;
      });
}

Entry drop_shapes_figure() {
  return plot_entry(
      "drop_shapes.svg", "Rain drop shapes (Beard & Chuang)",
      fmt::format("Profiles of falling drops of 0.5 to 3 mm equivalent radius from the cosine series "
                  "r = a (1 + sum c_n cos n theta), theta from the direction of fall, coefficients of "
                  "Chuang & Beard (1990) interpolated in radius. Small drops are spheres; large ones "
                  "flatten at the base and their axis ratio falls to {:.2f} at 3 mm.",
                  scatter::axis_ratio(scatter::drop_shape(3e-3))),
      [] {
        io::Plot p;
        p.title = "Falling drops: Beard & Chuang shapes (fall is downwards)";
        p.x_label = "horizontal (mm)";
        p.y_label = "vertical (mm)";
        p.x_min = -4.5, p.x_max = 4.5, p.x_tick = 1;
        p.y_min = -3, p.y_max = 5, p.y_tick = 1;  // room above the drops for the legend
        p.width = 720, p.height = 620;             // about the same mm per pixel on both axes
        p.legend = io::LegendCorner::TopRight;
        const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
        int k = 0;
        for (double a_mm : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0}) {
          const auto s = scatter::drop_shape(a_mm * 1e-3);
          io::PlotSeries line{fmt::format("a = {:g} mm, axis ratio {:.2f}", a_mm, scatter::axis_ratio(s)), {}, {},
                              colours[k++], false};
          for (int i = 0; i <= 360; ++i) {
            // theta from the fall direction (down), swept once around the profile.
            const double t = kPi<> * i / 180.0;
            const double rr = scatter::shape_radius(s, t <= kPi<> ? t : 2 * kPi<> - t) * 1e3;
            line.x.push_back(rr * std::sin(t));
            line.y.push_back(-rr * std::cos(t));
          }
          p.series.push_back(std::move(line));
        }
        return p;
      });
}

}  // namespace

std::vector<Entry> drop_entries() {
  return {builtin_environment_figure(), drop_model_figure(), drop_exact_figure(),
          drop_difference_figure(), drop_beard_chuang_figure(), drop_undistorted_figure(),
          direct_view_figure(), drop_shapes_figure()};
}

}  // namespace hydrolux::gallery::detail
