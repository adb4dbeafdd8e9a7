#include "drop_flags.hpp"

#include <fmt/format.h>

#include "hydrolux/core/params.hpp"

namespace hydrolux::cli {

void add_drop_size_flags(CLI::App& sub, DropFlags& drops, std::string_view rain_note,
                         std::map<std::string, std::string>& flags_for_quantity) {
  sub.add_option("--radius-um", drops.radius_um, "Drop radius (the mean radius with gamma or lognormal), micrometres")
      ->check(positive_number(1e6, "um"));
  sub.add_option("--size-distribution", drops.distribution,
                 fmt::format("mono, gamma:W or lognormal:W (relative width W in [0.0001, 1] around --radius-um), or "
                             "marshall-palmer:H (rain of H in [{:g}, {:g}] mm/h, radii 50-3000 um{})",
                             kMinDistributionRainRateMmh, kMaxRainRateMmh, rain_note))
      ->capture_default_str();
  flags_for_quantity.insert({{"x", "--radius-um (size parameter x)"},
                             {"m_real", "--medium/--surrounding (relative index, real part)"},
                             {"m_imag", "--medium/--surrounding (relative index, imaginary part)"},
                             {"r_max_m", "--radius-um (largest radius of the distribution, m)"},
                             {"r_min_m", "--radius-um (smallest radius of the distribution, m)"},
                             {"radius_um", "--radius-um"}});
}

void add_media_flags(CLI::App& sub, DropFlags& drops) {
  sub.add_option("--medium", drops.medium, "Drop medium (see hydrolux ior --list)")->capture_default_str();
  sub.add_option("--surrounding", drops.surrounding, "Surrounding medium")->capture_default_str();
}

}  // namespace hydrolux::cli
