#include "hydrolux/jobs.hpp"

#include <string>

#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/params.hpp"
#include "hydrolux/drop/physics_params.hpp"
#include "hydrolux/drop/undistort.hpp"
#include "hydrolux/optics/params.hpp"
#include "hydrolux/rain/detect.hpp"
#include "hydrolux/rain/fog.hpp"
#include "hydrolux/rain/frame_paths.hpp"
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
      rain.params = describe_fields(rain::rain_path_params());
      for (const auto& p : describe_fields(rain::rain_params())) rain.params.push_back(p);
      for (const auto& p : describe_fields(rain::rain_file_params())) rain.params.push_back(p);
      rain.python = "hydrolux.rain, hydrolux.RainRenderer and hydrolux.builtin_scene (its camera); the batch job python3 -m hydrolux.batch rain takes the flags";
      rain.description =
          "Rain over a photograph, a folder of frames or a video: drops drawn from Marshall-Palmer for the rain rate, "
          "falling at their terminal velocity with the wind, each seen through Garg & Nayar's drop model lit by the frame "
          "itself and smeared by the exposure into a streak; hidden behind nearer scene geometry (--depth, else a ground "
          "plane); unresolved distant rain as extinction and airlight. Deterministic for a --seed (docs/rain.md).";
      v.push_back(std::move(rain));
    }
    {
      JobSpec lens{"lens_drops", "hydrolux lens-drops", "Water drops on the lens or windshield over a photograph, a folder of frames or a video", {}};
      lens.params = describe_fields(rain::lens_drops_path_params());
      for (const auto& p : describe_fields(rain::lens_drops_params())) lens.params.push_back(p);
      for (const auto& p : describe_fields(rain::lens_drops_file_params())) lens.params.push_back(p);
      lens.python = "hydrolux.lens_drops";
      lens.description =
          "Water drops on the lens or windshield over a photograph, a folder of frames or a video: spherical caps on a "
          "glass plane in front of the camera, each refracting the scene behind it (Snell and Fresnel at the exact cap), defocused by "
          "the aperture's circle of confusion, with their coverage mask. Deterministic for a --seed (docs/lens-drops.md).";
      v.push_back(std::move(lens));
    }
    {
      JobSpec detect{"detect_rain", "hydrolux detect-rain", "Rain found in a folder of frames: one mask per frame", {}};
      detect.params = describe_fields(rain::detect_path_params());
      for (const auto& p : describe_fields(rain::detect_params())) detect.params.push_back(p);
      detect.python = "hydrolux.detect_rain";
      detect.description =
          "Rain found in a folder of frames (Garg & Nayar 2004): candidates brighter than both neighbouring frames by "
          "--min-change-grey, each connected streak's photometric test (its change against its background has slope "
          "beta <= --drop-time-s / --exposure-s), and the spatio-temporal correlation over --window-px x "
          "--window-frames, kept where it is elongated along the rain's common direction; one 8-bit PNG mask per frame, "
          "each stage's on request. Baselines: --method candidates, median (docs/rain-detection.md).";
      v.push_back(std::move(detect));
      JobSpec remove{"remove_rain", "hydrolux remove-rain", "Rain removed from a folder of frames", {}};
      remove.params = describe_fields(rain::remove_path_params());
      for (const auto& p : describe_fields(rain::remove_params())) remove.params.push_back(p);
      remove.python = "hydrolux.remove_rain";
      remove.description =
          "Rain removed from a folder of frames: garg-nayar replaces the pixels of each frame's mask (detect-rain's) "
          "by the mean of the neighbouring frames (Garg & Nayar 2004), median takes every pixel's temporal median, "
          "and oracle inverts the rain layers that hydrolux rain --layer-dir wrote, the upper bound of any removal; "
          "rain-eval scores the result against the clean frames (docs/rain-detection.md).";
      v.push_back(std::move(remove));
      JobSpec eval{"rain_eval", "hydrolux rain-eval", "Rain masks scored against the true ones", {}};
      eval.params = describe_fields(rain::eval_path_params());
      for (const auto& p : describe_fields(rain::eval_params())) eval.params.push_back(p);
      for (const auto& p : describe_fields(rain::eval_detector_params())) eval.params.push_back(p);
      eval.python = "hydrolux.eval.score";
      eval.description =
          "Predicted rain masks (detect-rain's, or any detector's: nonzero = rain) scored against the true ones that "
          "hydrolux rain --mask-dir writes (rain where the alpha reaches --rain-alpha; faint streaks between "
          "--ignore-alpha and it not scored): precision, recall, F1 and IoU per frame and overall, and with "
          "--clean-dir and --derained-dir the removal's PSNR in and out of the rain, as text or JSON "
          "(docs/rain-detection.md).";
      v.push_back(std::move(eval));
    }
    {
      JobSpec fog{"fog", "hydrolux fog", "Fog, haze or mist over a photograph, a folder of frames or a video", {}};
      fog.params = describe_fields(rain::fog_path_params());
      for (const auto& p : describe_fields(rain::fog_params())) fog.params.push_back(p);
      for (const auto& p : describe_fields(rain::fog_file_params())) fog.params.push_back(p);
      fog.python = "hydrolux.fog";
      fog.description =
          "Fog, haze or mist over a photograph, a folder of frames or a video: extinction from a visibility (Koschmieder, 3.912 / V) "
          "or from Lorenz-Mie over the droplets for a liquid water content; transmittance exp(-beta d) per pixel from "
          "--depth (else a ground plane), airlight of the sky's colour, and the forward-scattered glow around lights "
          "(docs/fog.md).";
      v.push_back(std::move(fog));
    }
    v.push_back({"fresnel", "hydrolux fresnel", "Fresnel reflectance and transmittance of one plane interface",
                 describe_fields(optics::fresnel_params()),
                 "",
                 "Fresnel reflectance and transmittance of a plane interface from a transparent medium (n1) "
                 "into a dielectric (n2) or an absorbing medium (n2 + i k2). Exact equations, unpolarised "
                 "R = (R_s + R_p) / 2, T = 1 - R for dielectrics."});
    v.push_back({"ior", "hydrolux ior", "A medium's refractive index n + ik at a wavelength",
                 describe_fields(optics::ior_params()),
                 "",
                 "Complex refractive index n + i k of a medium at a vacuum wavelength."});
    v.push_back({"drop_profile", "hydrolux drop profile", "Garg & Nayar's radiance profile across a drop's image",
                 describe_fields(drop::drop_profile_params()),
                 "",
                 "Figure 4 of Garg & Nayar: the radiance of the refracted, reflected and internally reflected "
                 "paths across the drop's image (rho = 0 centre to 1 rim) for a uniform environment Le = 1, "
                 "drop on the optical axis; and the drop's field of view."});
    v.push_back({"rainphys", "hydrolux rainphys", "A rain drop's terminal velocity, Marshall-Palmer density and shape",
                 describe_fields(drop::rainphys_params()),
                 "",
                 "Physical properties of a rain drop (Garg & Nayar 2004, section 2): terminal velocity (the paper's "
                 "fit v = 200 sqrt(a) and Gunn & Kinzer's 1949 measurements), the Marshall-Palmer size density at "
                 "this radius, and the equilibrium shape r(theta) = a (1 + sum_n c_n cos(n theta)) with theta = 0 "
                 "along the fall (Chuang & Beard 1990 coefficients) and its axis ratio.\n"
                 "Density convention: N(a) = 8e6 exp(-8200 h^-0.21 a) m^-4, a the radius in metres, h the rain rate "
                 "in mm/h, as in the paper. It keeps Marshall & Palmer's N0 = 8e6 m^-4, which they defined per metre "
                 "of DIAMETER, with the radius: a strict per-radius density is twice this (and so is the number "
                 "density). number_density_per_m3 = N0 / Lambda counts all drops; mean_spacing_m = n^(-1/3)."});
    v.push_back({"drop_render", "hydrolux drop render", "A rain drop's picture from an environment (Garg & Nayar Figure 8)",
                 describe_fields(drop::drop_render_params()), "hydrolux.drop_render",
                 "Render a rain drop from an environment with Garg & Nayar's model (their Figure 8): a pinhole camera "
                 "looks along +z at a spherical drop on its axis; every pixel has its own viewing direction; the rim is "
                 "anti-aliased by supersampling. Output: linear EXR, or sRGB PNG (RGBA: alpha is the drop's coverage "
                 "when --no-background is given)."});
    v.push_back({"drop_undistort", "hydrolux drop undistort",
                 "A perspective view recovered from the picture inside a drop (Garg & Nayar Figure 9)",
                 // hydrolux.drop_undistort takes these but width and height as size=(width, height).
                 describe_fields(drop::undistort_params()), "",
                 "Undo a rain drop's distortion (Garg & Nayar Figure 9): the drop refracts a ~165 degree, inverted "
                 "view of the world into its image; inverting the refraction mapping gives the perspective view of a "
                 "pinhole camera at the drop. The drop is taken as a sphere seen head-on. Near the drop's rim the "
                 "view is packed ever tighter, so the result is sharp near the centre of the field only. Output RGBA: "
                 "alpha 0 where a direction lies outside the drop's field of view or its image point outside the "
                 "input image."});
    v.push_back({"mie", "hydrolux mie", "Lorenz-Mie scattering by one sphere", describe_fields(scatter::mie_params()),
                 "",
                 "Lorenz-Mie scattering by a homogeneous sphere: efficiencies and the amplitudes S1, S2 "
                 "(Bohren & Huffman conventions). Give --m and --x, or the physical form --radius-um, "
                 "--wavelength-nm, --medium."});
    v.push_back({"phase", "hydrolux phase", "Scattered intensity against angle for one drop or a size distribution",
                 describe_fields(scatter::phase_params()), "hydrolux.phase",
                 "Scattered intensity against scattering angle for one drop: i1 = |S1|^2, i2 = |S2|^2 and "
                 "their average, by Lorenz-Mie, one Debye order, Airy theory or geometric optics."});
    v.push_back({"medium", "hydrolux medium",
                 "Drops as a renderer's participating medium: Mitsuba 3 tabphase or pbrt-v4 Henyey-Greenstein",
                 describe_fields(scatter::medium_params()), "hydrolux.renderer_medium",
                 "A population of drops as a renderer's participating medium: the size-averaged Lorenz-Mie phase function as "
                 "Mitsuba 3's tabphase (.xml) or pbrt-v4's Henyey-Greenstein (.pbrt, with its error stated), with the "
                 "extinction and albedo spectra, 360-830 nm, per scene unit (docs/renderer-export.md)."});
    v.push_back({"lee", "hydrolux lee", "A Lee diagram, corona or glory table, computed spectrally",
                 describe_fields(atmos::lee_params()), "hydrolux.lee",
                 "Lee diagram: the colour of sunlight scattered by water drops over drop radius (columns) and scattering angle "
                 "(rows), spectral and absolute (sr^-1: radiance per unit irradiance per unit projected-area optical depth), "
                 "averaged over the sun's disk and a size spread. Writes a linear EXR (R,G,B gamut-mapped; XYZ unmapped), a "
                 "display PNG and a JSON sidecar with the exact axes (docs/lee.md). --table corona/glory: forward and backward "
                 "tables of cloud droplets. --json with one radius prints its profile."});
    v.push_back({"sky", "hydrolux sky", "A rainbow in a daylight scene, per pixel on the CPU",
                 describe_fields(scene::sky_params()), "hydrolux.sky",
                 "A rainbow in a daylight scene, per pixel on the CPU: the view ray's angle to the sun looked up in the Lee "
                 "tables, times the sun's light and the rain curtain's scattering (Marshall-Palmer rain at --rain-rate-mmh), over "
                 "Preetham's analytic sky and a ground plane. The EXR is linear Rec.709 in cd/m^2; the PNG is tone-mapped "
                 "(docs/sky.md). Without --lut the tables for --radius-um are computed first (Mie, with progress and an ETA): "
                 "about 12 s for 500 um drops on two cores at --sampling 1, growing as --sampling squared (50 s at 2, about an "
                 "hour at 16) and with the radius; for repeated or finer renders compute a table once (hydrolux lee or export) "
                 "and give it with --lut. Frames are refused up front when they would not fit in the memory available."});
    v.push_back({"export", "hydrolux export", "Engine assets for rainbows: Lee tables, sky parameters and shaders",
                 describe_fields(scene::export_params()),
                 "",
                 "Engine assets for rainbows in a scene: the rainbow (5-800 um, 90-180 deg) and corona (1-50 um, 0-90 deg) Lee "
                 "tables as EXR, PNG, raw float32 and JSON axes; the sun and sky parameters for every sun elevation (sky.json); "
                 "GLSL and HLSL that evaluate the sky, the bow, the secondary, the corona and the blend, and a linear polariser "
                 "in front of the camera (the tables carry the Stokes Q: EXR channels Q.X, Q.Y, Q.Z and <name>_q.f32); a "
                 "README for integrators. With --shape, also the bow of non-spherical drops as a 3-D table (radius x angle x 19 position "
                 "angles, for one sun elevation) that the shaders read instead. The folder appears complete or not at all."});
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
