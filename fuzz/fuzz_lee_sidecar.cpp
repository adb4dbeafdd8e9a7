// libFuzzer target: a Lee table's JSON sidecar as `hydrolux sky --lut` reads it (io/lee_files.hpp),
// then the compositor's checks of the table's axes (scene::bow_table) and a slice looked up across
// the sphere. Invariants: a refused sidecar throws hydrolux::Error, nothing else; an accepted table
// has increasing positive radii and rows inside their axis' range; a slice's values are finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace {
void check(bool ok) {
  if (!ok) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hydrolux;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  io::LeeSidecarAxes axes;
  try {
    axes = io::parse_lee_sidecar(text);
  } catch (const Error&) {
    return 0;
  }
  const std::size_t n = axes.radius_um.size() * axes.rows.size();
  if (axes.rows.size() != 0 && n / axes.rows.size() != axes.radius_um.size()) return 0;
  if (n > (std::size_t(1) << 16)) return 0;  // the pixels would come from the EXR; keep runs fast
  std::vector<float> rgb(n * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i % 7) * 0.01f;
  scene::BowTable t;
  try {
    t = scene::bow_table(axes.kind, axes.axis, axes.radius_um, axes.rows, rgb);
  } catch (const Error&) {
    return 0;
  }
  for (std::size_t i = 1; i < t.radius_um.size(); ++i) check(t.radius_um[i] > t.radius_um[i - 1]);
  check(t.radius_um.front() > 0);
  const auto range = t.angle_range_deg();
  check(range[0] >= 0 && range[1] <= 180 && range[0] <= range[1]);
  for (double r : {t.radius_um.front(), std::sqrt(t.radius_um.front() * t.radius_um.back()), t.radius_um.back() * 2}) {
    const scene::BowSlice s = scene::slice_at_radius(t, r);
    for (int deg = 0; deg <= 180; deg += 3) {
      float out[3];
      const float theta = float(deg);
      s.lookup(std::cos(theta * 0.0174532925f), theta, out);
      for (float v : out) check(std::isfinite(v));
    }
  }
  return 0;
}
