// The specs `hydrolux lee` and `hydrolux export` compute from their flags' texts (io/lee_job.hpp,
// io/export_job.hpp), before any file or work: the values the texts state, the defaults
// docs/lee.md and docs/sky.md give (a rainbow table of 512 x 1024 over 5-800 um, the corona's rows
// twice the rainbow's, no corona for drops over 50 um), and the refusals in the flags' words. And
// `hydrolux sky`'s job (io/sky_job.hpp) run through a stand-in codec: what it writes, the order of
// its hooks, and its refusals before any file.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/export_job.hpp"
#include "hydrolux/io/lee_job.hpp"
#include "hydrolux/io/sky_job.hpp"
#include "support/cli.hpp"

namespace hydrolux::io {
namespace {

std::string error_of(const auto& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(LeeJobSpec, TheTextsSetTheSpec) {
  LeeJob job;
  job.radius_um = "100:500";
  job.request.angle_deg = std::array<double, 2>{120, 150};
  job.request.size = std::array<int, 2>{8, 32};
  job.wavelengths = "400:700:16";
  job.medium = "ice";
  const atmos::LeeSpec s = lee_job_spec(job);
  EXPECT_EQ(s.radius_min_um, 100);
  EXPECT_EQ(s.radius_max_um, 500);
  EXPECT_EQ(s.columns, 8);
  EXPECT_EQ(s.rows, 32);
  EXPECT_EQ(s.wavelength_min_nm, 400);
  EXPECT_EQ(s.wavelength_max_nm, 700);
  EXPECT_EQ(s.wavelengths, 16);
  EXPECT_EQ(s.drop_medium, "ice");
  EXPECT_EQ(s.table, atmos::LeeTableKind::rainbow);
}

TEST(LeeJobSpec, RefusalsNameTheFlags) {
  LeeJob job;
  job.radius_um = "500:100";
  EXPECT_EQ(error_of([&] { (void)lee_job_spec(job); }),
            "--radius-um '500:100': expected A:B (micrometres in [0.1, 5000], A <= B) or one value");
  job = LeeJob{};
  job.wavelengths = "300";
  EXPECT_EQ(error_of([&] { (void)lee_job_spec(job); }),
            "--wavelengths-nm '300': expected A:B or A:B:N (nanometres in [360, 830], A <= B; N samples in [1, 2000])");
  job = LeeJob{};
  job.given.insert("canting_deg");
  job.request.canting_deg = 5;
  EXPECT_EQ(error_of([&] { (void)lee_job_spec(job); }),
            "--canting-deg 5: sets the canting of the non-spherical drops' table (--shape); the spheres' tables do not "
            "depend on it (omit it or give --shape)");
}

// --json prints one radius's profile, and nothing else is written without -o: refused before any work.
TEST(LeeJob, JsonNeedsOneRadius) {
  LeeJob job;
  job.radius_um = "100:500";
  job.request.size = std::array<int, 2>{8, 32};
  job.json = true;
  EXPECT_EQ(error_of([&] { (void)run_lee_job(job, lee_job_spec(job), {}); }),
            "--json prints one radius's profile: give a single --radius-um R");
  job.json = false;
  EXPECT_EQ(error_of([&] { (void)run_lee_job(job, lee_job_spec(job), {}); }),
            "-o is required (a .exr path, or .nc for NetCDF), unless --json prints a profile");
}

TEST(ExportTables, DefaultsAndOneRadius) {
  ExportJob job;
  ExportTables t = export_tables(job);
  EXPECT_EQ(t.rainbow.columns, 512);
  EXPECT_EQ(t.rainbow.rows, 1024);
  EXPECT_EQ(t.corona.rows, 2048);
  EXPECT_TRUE(t.with_corona);
  EXPECT_TRUE(t.rainbow.stokes);
  EXPECT_FALSE(t.shaped);

  job.options.radius_um = 100;  // over 50 um: no corona
  job.options.size = std::array<int, 2>{1, 16};
  t = export_tables(job);
  EXPECT_FALSE(t.with_corona);
  EXPECT_EQ(t.rainbow.columns, 1);
  EXPECT_EQ(t.rainbow.rows, 16);
  EXPECT_EQ(t.rainbow.radius_min_um, 100);

  job.options.size = std::array<int, 2>{4, 16};
  EXPECT_EQ(error_of([&] { (void)export_tables(job); }),
            "--size 4x16: one --radius-um makes one column; give --size 1x16");
}

TEST(ExportTables, ShapeAndSunElevation) {
  ExportJob job;
  job.given.insert("sun_elevation_deg");
  job.options.sun_elevation_deg = 30;
  EXPECT_EQ(error_of([&] { (void)export_tables(job); }),
            "--sun-elevation-deg 30: sets the sun of the non-spherical drops' table (--shape); the spheres' tables do "
            "not depend on it (omit it or give --shape)");
  job.options.shape = "spheroid:0.9";
  job.options.size = std::array<int, 2>{4, 16};
  const ExportTables t = export_tables(job);
  ASSERT_TRUE(t.shaped);
  EXPECT_FALSE(t.shape.spherical());
}

// The sky job with a codec that writes what it was given as text: the frame reaches the codec at the
// requested size in the output's format, the codec is readied before the tables' work (whose progress
// rises to 1), and a refused request leaves an existing output as it was.
TEST(SkyJob, RendersThroughItsCodecAndRefusesBeforeAnyFile) {
  const auto dir = testing::temp_dir("hydrolux_sky_job");
  SkyJob job;
  job.options.settings.camera.width = 24;
  job.options.settings.camera.height = 12;
  job.options.settings.radius_um = 10;  // a fogbow: small tables
  job.options.sampling = 0.25;
  job.output = (dir / "sky.png").string();
  SkyJobHooks h;
  h.codec.encode = [](const Image& image, ImageFormat format, PngOptions) {
    return fmt::format("{} {}x{}x{}", format == ImageFormat::png ? "png" : "other", image.width, image.height,
                       image.channels);
  };
  bool ready = false, ready_first = true, rising = true;
  double last = 0;
  h.codec_ready = [&] { ready = true; };
  h.progress = [&](double f, std::string_view) {
    ready_first = ready_first && ready;
    rising = rising && f >= last;
    last = f;
  };
  const SkyJobResult r = run_sky_job(job, h);
  EXPECT_EQ(testing::slurp(dir / "sky.png"), "png 24x12x3");
  EXPECT_TRUE(ready_first) << "the tables' work began before the codec was ready";
  EXPECT_TRUE(rising);
  EXPECT_NEAR(last, 1, 1e-9);
  EXPECT_EQ(r.output, job.output);
  EXPECT_EQ(sky_summary(r).rfind("sky: wrote ", 0), 0u) << sky_summary(r);

  // Refused before anything is written: a parameter of another mode, the Stokes images as a PNG.
  std::ofstream(dir / "sky.png") << "before";
  SkyJob other = job;
  other.options.settings.mode = scene::BowMode::cube_map;
  other.options.settings.dome_rings = 40;
  other.given.insert("dome_rings");
  EXPECT_EQ(error_of([&] { (void)run_sky_job(other, h); }),
            "--dome-rings 40: used by --mode half-dome only (this run is --mode cube-map)");
  other = job;
  other.options.settings.stokes = true;
  EXPECT_EQ(error_of([&] { (void)run_sky_job(other, h); }).rfind("--stokes: the Stokes images are linear and signed", 0),
            0u);
  EXPECT_EQ(testing::slurp(dir / "sky.png"), "before");
}

}  // namespace
}  // namespace hydrolux::io
