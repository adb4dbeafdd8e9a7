#include "hydrolux/jobs.hpp"

#include <string>

#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/drop/physics_params.hpp"
#include "hydrolux/optics/params.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/lens_drops.hpp"
#include "hydrolux/rain/params.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/renderer_export.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux {

const std::vector<JobSpec>& job_specs() {
  static const std::vector<JobSpec> specs = [] {
    std::vector<JobSpec> v;
    {
      JobSpec rain{"rain", "hydrolux rain", "Rain over a photograph, a folder of frames or a video", {}};
      rain.params = describe_fields(rain::rain_params());
      for (const auto& p : describe_fields(rain::rain_file_params())) rain.params.push_back(p);
      rain.python = "hydrolux.rain, hydrolux.RainRenderer and hydrolux.builtin_scene (its camera); the batch job python3 -m hydrolux.batch rain takes the flags";
      v.push_back(std::move(rain));
    }
    {
      JobSpec lens{"lens_drops", "hydrolux lens-drops", "Water drops on the lens or windshield over a photograph, a folder of frames or a video", {}};
      lens.params = describe_fields(rain::lens_drops_params());
      for (const auto& p : describe_fields(rain::lens_drops_file_params())) lens.params.push_back(p);
      lens.python = "hydrolux.lens_drops";
      v.push_back(std::move(lens));
    }
    {
      JobSpec fog{"fog", "hydrolux fog", "Fog, haze or mist over a photograph, a folder of frames or a video", {}};
      fog.params = describe_fields(rain::fog_params());
      for (const auto& p : describe_fields(rain::fog_file_params())) fog.params.push_back(p);
      fog.python = "hydrolux.fog";
      v.push_back(std::move(fog));
    }
    v.push_back({"fresnel", "hydrolux fresnel", "Fresnel reflectance and transmittance of one plane interface",
                 describe_fields(optics::fresnel_params())});
    v.push_back({"ior", "hydrolux ior", "A medium's refractive index n + ik at a wavelength",
                 describe_fields(optics::ior_params())});
    v.push_back({"drop_profile", "hydrolux drop profile", "Garg & Nayar's radiance profile across a drop's image",
                 describe_fields(drop::drop_profile_params())});
    v.push_back({"rainphys", "hydrolux rainphys", "A rain drop's terminal velocity, Marshall-Palmer density and shape",
                 describe_fields(drop::rainphys_params())});
    v.push_back({"drop_render", "hydrolux drop render", "A rain drop's picture from an environment (Garg & Nayar Figure 8)",
                 describe_fields(drop::drop_render_params()), "hydrolux.drop_render"});
    v.push_back({"mie", "hydrolux mie", "Lorenz-Mie scattering by one sphere", describe_fields(scatter::mie_params())});
    v.push_back({"phase", "hydrolux phase", "Scattered intensity against angle for one drop or a size distribution",
                 describe_fields(scatter::phase_params()), "hydrolux.phase"});
    v.push_back({"medium", "hydrolux medium",
                 "Drops as a renderer's participating medium: Mitsuba 3 tabphase or pbrt-v4 Henyey-Greenstein",
                 describe_fields(scatter::medium_params()), "hydrolux.renderer_medium"});
    v.push_back({"lee", "hydrolux lee", "A Lee diagram, corona or glory table, computed spectrally",
                 describe_fields(atmos::lee_params()), "hydrolux.lee"});
    v.push_back({"sky", "hydrolux sky", "A rainbow in a daylight scene, per pixel on the CPU",
                 describe_fields(scene::sky_params()), "hydrolux.sky"});
    v.push_back({"export", "hydrolux export", "Engine assets for rainbows: Lee tables, sky parameters and shaders",
                 describe_fields(scene::export_params())});
    return v;
  }();
  return specs;
}

const JobSpec& job_spec(std::string_view name) {
  std::string names;
  for (const auto& j : job_specs()) {
    if (j.name == name) return j;
    names += (names.empty() ? "" : ", ") + std::string(j.name);
  }
  throw UnknownNameError("no job '" + std::string(name) + "' (jobs: " + names + ")");
}

}  // namespace hydrolux
