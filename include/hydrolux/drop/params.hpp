#pragma once
// What a user sets for a drop render (hydrolux drop render, hydrolux.drop_render), declared once
// (core/params.hpp): each value's name, unit, range, default and help. The defaults are
// DropRenderRequest's initializers. The medium is a name each door resolves (optics::find_medium).
#include <optional>
#include <span>
#include <string_view>

#include "hydrolux/core/image.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/drop/render.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::drop {

enum class RenderMethod { model, exact };

struct DropRenderRequest {
  double radius_mm = 1.0;
  double distance_m = 2.0;
  double focal_mm = 50.0;
  double f_number = 2.8;
  std::optional<double> frame_mm;  // the field's width at the drop; else 5 x the drop radius
  int size = 512;
  int samples = 4;
  int internal = 2;
  std::optional<double> temperature_c;  // of the drop's medium; else the medium's default
  double wavelength_nm = 589.3;
  bool dispersion = false;
  bool background_blur = false;
  bool background = true;
  double exposure_ev = 0;
  int depth = 8;
  RenderMethod method = RenderMethod::model;
  DropShapeKind shape = DropShapeKind::sphere;
};

std::span<const Field<DropRenderRequest>> drop_render_params();
// A drop render parameter by name; throws std::logic_error for a name not declared.
const Param& drop_render_param(std::string_view name);

// How a door names a parameter in its messages: the CLI by its flag ("--distance-m"), Python by
// its keyword ("distance_m").
enum class ParamWords { flags, names };

// Error unless the drop is at least 1% of its radius clear of the camera.
void check_clearance(const DropRenderRequest& request, ParamWords words);
// Error unless the drop's shape suits the request: Beard & Chuang's shape for radii of 0.5-4.5 mm
// (scatter/drop_shape.hpp), and the exact tracer only (the model is for a sphere).
void check_shape(const DropRenderRequest& request, ParamWords words);
// The angular radius of the background's defocus disk with background_blur (0 without): Error
// unless the drop is beyond the focal length and the disk is at most 60 degrees wide.
double background_blur_rad(const DropRenderRequest& request, ParamWords words);
// The drop's index relative to the medium around it: per channel with dispersion
// (kChannelWavelengthsNm), else at wavelength_nm in all three.
ChannelIndex relative_index(const DropRenderRequest& request, const optics::Medium& drop,
                            const optics::Medium& around);
// The request's camera (a square image of `size`); not validated (validate(DropCamera)).
DropCamera camera_for(const DropRenderRequest& request);
// The picture: the model or the exact tracer (to `depth`, through the request's shape), the
// background blurred by blur_rad, the exposure applied.
Image render_request(const DropRenderRequest& request, const DropCamera& camera, const scene::Environment& env,
                     const ChannelIndex& mu, double blur_rad, ProgressFn progress);

}  // namespace hydrolux::drop
