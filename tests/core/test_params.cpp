// The declared parameters (core/params.hpp, hydrolux/jobs.hpp): the messages a door shows, and the
// invariants every job's table keeps so that each door can be generated from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <span>
#include <set>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/shared_params.hpp"
#include "hydrolux/jobs.hpp"
#include "hydrolux/rain/frame_paths.hpp"
#include "hydrolux/rain/params.hpp"

namespace {

using hydrolux::Param;
using hydrolux::ParamKind;

TEST(Params, CheckNamesTheValueAndTheRangeWithItsUnit) {
  const Param p{"rain_rate_mmh", "--rain-rate-mmh", "rain", ParamKind::real, "mm/h", 0, 500, "Rain rate"};
  EXPECT_NO_THROW(p.check(0));
  EXPECT_NO_THROW(p.check(500));
  try {
    p.check(600);
    FAIL() << "600 accepted";
  } catch (const hydrolux::DomainError& e) {
    EXPECT_STREQ(e.what(), "rain_rate_mmh = 600 is outside [0, 500] mm/h");
    EXPECT_EQ(e.quantity(), "rain_rate_mmh");
    EXPECT_EQ(e.lo(), 0);
    EXPECT_EQ(e.hi(), 500);
  }
  EXPECT_THROW(p.check(std::nan("")), hydrolux::DomainError);
  const Param n{"crf", "--crf", "files", ParamKind::integer, "", 0, 51, "quality"};
  EXPECT_NO_THROW(n.check(18));
  try {
    n.check(1.5);
    FAIL() << "1.5 accepted as a whole number";
  } catch (const hydrolux::DomainError& e) {
    EXPECT_STREQ(e.what(), "crf = 1.5 is not a whole number in [0, 51]");
  }
}

// The rain job's defaults are its structs' initializers, not a second copy.
TEST(Params, RainDefaultsAreTheStructsInitializers) {
  const hydrolux::rain::RainSettings s;
  const hydrolux::rain::RainCamera c;
  const auto infos = hydrolux::describe_fields(hydrolux::rain::rain_params());
  const auto value = [&](std::string_view name) {
    for (const auto& i : infos)
      if (i.param->name == name) return i.default_value;
    ADD_FAILURE() << "no parameter " << name;
    return 0.0;
  };
  EXPECT_EQ(value("rain_rate_mmh"), s.rain_rate_mmh);
  EXPECT_EQ(value("near_m"), s.near_m);
  EXPECT_EQ(value("seed"), double(s.seed));
  EXPECT_EQ(value("unresolved"), s.unresolved ? 1.0 : 0.0);
  EXPECT_EQ(value("focal_mm"), c.focal_mm);
  EXPECT_EQ(value("camera_height_m"), c.height_m);
  EXPECT_EQ(value("fps"), c.fps);
  EXPECT_TRUE(std::isnan(value("fov_deg")));  // none: it replaces focal_mm when given
}

// The kinds of more than one number: a choice (its words, stored as the word's index), a size, a span
// and a colour (their parts), each read from the CLI's text and refused in each door's words; the
// values and messages are written out here, not taken from the code under test.
TEST(Params, ChoicesAndPartsReadAndRefuseInTheDoorsWords) {
  using hydrolux::Door;
  using hydrolux::ParamValue;
  const Param mode = hydrolux::choice_param("mode", "--mode", "mode", "per-pixel|cube-map|half-dome", "Mode");
  EXPECT_EQ(mode.lo, 0);
  EXPECT_EQ(mode.hi, 2);
  EXPECT_EQ(mode.parse_text("cube-map", Door::cli)[0], 1);
  EXPECT_EQ(mode.value_text(2), "half-dome");
  EXPECT_EQ(mode.range_text(), "per-pixel, cube-map or half-dome");
  try {
    (void)mode.parse_text("dome", Door::cli);
    FAIL() << "dome accepted";
  } catch (const hydrolux::UnknownNameError& e) {
    EXPECT_STREQ(e.what(), "--mode 'dome': expected per-pixel, cube-map or half-dome");
  }
  EXPECT_THROW((void)mode.parse_text("Cube-Map", Door::python), hydrolux::UnknownNameError);
  EXPECT_THROW(mode.check(3), hydrolux::Error);
  EXPECT_THROW(mode.check(0.5), hydrolux::Error);

  const Param size = hydrolux::parts_param("size", "--size", "camera", ParamKind::size, "W|H", "px", 1, 16384, "Size");
  EXPECT_EQ(size.parts(), 2);
  const ParamValue wh = size.parse_text("640x480", Door::cli);
  EXPECT_EQ(wh[0], 640);
  EXPECT_EQ(wh[1], 480);
  EXPECT_EQ(size.value_text(wh, Door::cli), "640x480");
  EXPECT_EQ(size.value_text(wh, Door::python), "(640, 480)");
  const auto refused = [](const Param& p, std::string_view text) {
    try {
      (void)p.parse_text(text, Door::cli);
    } catch (const hydrolux::Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  for (const char* bad : {"640", "640x480x2", "0x480", "640x16385", "640.5x480", "axb", "640x", "x480", "640,480"})
    EXPECT_EQ(refused(size, bad), "--size '" + std::string(bad) + "': expected WxH, each a whole number in [1, 16384] px")
        << bad;
  try {
    size.check(ParamValue{0, 720}, Door::python);
    FAIL() << "(0, 720) accepted";
  } catch (const hydrolux::Error& e) {
    EXPECT_STREQ(e.what(), "size (0, 720): expected (W, H), each a whole number in [1, 16384] px");
  }

  const Param curtain = hydrolux::parts_param("curtain_distance_m", "--curtain-distance-m", "rain", ParamKind::span,
                                              "NEAR|FAR", "m", 0, 1e6, "Curtain");
  EXPECT_EQ(curtain.parse_text("1000:1000", Door::cli)[1], 1000);  // an empty curtain is allowed
  EXPECT_EQ(refused(curtain, "3000:1000"), "--curtain-distance-m '3000:1000': expected NEAR:FAR, each in [0, 1e+06] m, "
                                           "NEAR <= FAR");
  EXPECT_EQ(refused(curtain, "-1:10"), "--curtain-distance-m '-1:10': expected NEAR:FAR, each in [0, 1e+06] m, NEAR <= FAR");
  EXPECT_NE(refused(curtain, "1:nan"), "accepted");

  const Param colour =
      hydrolux::parts_param("light_color", "--light-color", "sun", ParamKind::colour, "R|G|B", "", 0, 1000, "Colour");
  const ParamValue rgb = colour.parse_text("1,0.5,2", Door::cli);
  EXPECT_EQ(rgb[1], 0.5);
  EXPECT_EQ(colour.value_text(rgb, Door::cli), "1,0.5,2");
  EXPECT_EQ(refused(colour, "1,1"), "--light-color '1,1': expected R,G,B, each in [0, 1000]");
  for (const char* bad : {"1,1,1,1", "1,,1", "-1,1,1", "1,1,1001", "a,b,c"}) EXPECT_NE(refused(colour, bad), "accepted") << bad;
}

// A row's setter and getter touch the member the row names, and a given field of view or pixel
// pitch is turned into the camera the CLI and Python make.
TEST(Params, RainRowsSetWhatTheyName) {
  hydrolux::rain::RainOptions o;
  for (const auto& f : hydrolux::rain::rain_params()) {
    const double v = f.param.kind == ParamKind::flag ? 0 : f.param.kind == ParamKind::integer ? f.param.lo + 1
                                                                                               : 0.5 * (f.param.lo + f.param.hi);
    f.set(o, v);
    EXPECT_EQ(f.get(o), v) << f.param.name;
  }
  hydrolux::rain::RainOptions q;
  q.fov_deg = 90;
  q.pixel_pitch_um = 5;
  const auto cam = hydrolux::rain::camera_for(q, 1000, 500);
  EXPECT_DOUBLE_EQ(cam.sensor_width_mm, 5.0);
  EXPECT_NEAR(cam.focal_mm, 2.5, 1e-12);  // 90 degrees across 5 mm: f = w / 2
}

std::string kebab(std::string_view name) {
  std::string s(name);
  for (auto& ch : s)
    if (ch == '_') ch = '-';
  return s;
}

// Every job's table: names snake_case and unique, the flag the name in kebab case (a switch whose
// default is on: --no-<name>), ranges ordered, defaults inside them, help given, exclusive pairs
// naming a parameter of the same table, a unit for every name that states one.
TEST(Params, EveryTableIsConsistent) {
  ASSERT_FALSE(hydrolux::job_specs().empty());
  for (const auto& job : hydrolux::job_specs()) {
    std::set<std::string_view> names;
    for (const auto& info : job.params) names.insert(info.param->name);
    EXPECT_EQ(names.size(), job.params.size()) << job.name << ": a name twice";
    for (const auto& info : job.params) {
      const Param& p = *info.param;
      const std::string where = std::string(job.name) + " " + std::string(p.name);
      for (char ch : p.name) EXPECT_TRUE(std::islower((unsigned char)ch) || std::isdigit((unsigned char)ch) || ch == '_') << where;
      const bool on_by_default = p.kind == ParamKind::flag && info.default_value != 0;
      EXPECT_EQ(p.flag, (on_by_default ? "--no-" : "--") + kebab(p.name)) << where;
      EXPECT_FALSE(p.help.empty()) << where;
      EXPECT_FALSE(p.group.empty()) << where;
      if (p.kind == ParamKind::path) {  // no range: FILE or DIR names what it is
        EXPECT_TRUE(p.words == "FILE" || p.words == "DIR") << where;
        EXPECT_TRUE(std::isnan(info.default_value)) << where;
      } else if (p.kind != ParamKind::flag) {
        EXPECT_LT(p.lo, p.hi) << where;
        if (!std::isnan(info.default_value)) {
          if (p.parts() > 1) EXPECT_NO_THROW(p.check(info.default_parts, hydrolux::Door::library)) << where;
          else EXPECT_NO_THROW(p.check(info.default_value)) << where << ": default outside its range";
        }
        // A choice's range is its words' values; a size's, span's or colour's parts are named.
        if (p.kind == ParamKind::choice) {
          EXPECT_EQ(p.lo, 0) << where;
          EXPECT_EQ(p.hi + 1, double(p.word_list().size())) << where;
        }
        if (p.parts() > 1) {
          EXPECT_EQ(p.word_list().size(), std::size_t(p.parts())) << where;
        }
      }
      if (!p.excludes.empty()) {
        EXPECT_TRUE(names.count(p.excludes)) << where << " excludes an unknown " << p.excludes;
      }
      // A reason's placeholders are closed: {name} or {name=}.
      EXPECT_EQ(std::count(p.why.begin(), p.why.end(), '{'), std::count(p.why.begin(), p.why.end(), '}')) << where;
      if (!p.deprecated.empty()) {
        EXPECT_FALSE(names.count(p.deprecated)) << where << ": its old name is another parameter's";
      }
      for (const char* suffix : {"_mm", "_m", "_deg", "_s", "_um", "_nm", "_mmh", "_mps"}) {
        const std::string n(p.name), sfx(suffix);
        if (n.size() > sfx.size() && n.compare(n.size() - sfx.size(), sfx.size(), sfx) == 0) {
          EXPECT_FALSE(p.unit.empty()) << where << ": the name states a unit the row does not";
        }
      }
    }
  }
  EXPECT_THROW(hydrolux::job_spec("no such job"), hydrolux::UnknownNameError);
}

// The usage tracker: a parameter given where its declared conditions fail is refused in one format,
// spelled by the door; one whose condition holds, or that the job consumed, is not.
TEST(ParamUse, ReportsGivenAndUnusedInTheDoorsSpelling) {
  const Param nodes{"nodes", "--nodes", "sizes", ParamKind::integer, "", 1, 100, "Radii", {}, "many_radii", {},
                    "{size_distribution=} is one radius; {nodes} sets the radii (omit {nodes})"};
  const Param dolp{"sky_max_dolp", "--sky-max-dolp", "sun", ParamKind::real, "", 0, 1, "Degree", {},
                   "polarizer_deg|stokes"};
  const Param stokes{"stokes", "--stokes", "camera", ParamKind::flag, "", 0, 1, "Stokes", {}, {}, "polarizer_deg"};
  const Param pol{"polarizer_deg", "--polarizer-deg", "camera", ParamKind::real, "deg", -180, 180, "Filter"};
  const auto message = [](const hydrolux::ParamUse& use) {
    try {
      use.report_unused();
    } catch (const hydrolux::Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  hydrolux::ParamUse cli(hydrolux::Door::cli), py(hydrolux::Door::python);
  for (auto* use : {&cli, &py}) {
    use->give(nodes, "16");
    use->note("size_distribution", "mono");
  }
  EXPECT_EQ(message(cli), "--nodes 16: --size-distribution mono is one radius; --nodes sets the radii (omit --nodes)");
  EXPECT_EQ(message(py), "nodes 16: size_distribution mono is one radius; nodes sets the radii (omit nodes)");
  cli.hold("many_radii");
  EXPECT_EQ(message(cli), "(accepted)");
  py.consume("nodes");
  EXPECT_EQ(message(py), "(accepted)");

  hydrolux::ParamUse sky(hydrolux::Door::cli);
  sky.give(dolp, "0.5");
  sky.declare(pol);
  EXPECT_EQ(message(sky), "--sky-max-dolp 0.5: used only with --polarizer-deg or --stokes (omit --sky-max-dolp)");
  sky.give(stokes, "");
  EXPECT_EQ(message(sky), "(accepted)");
  sky.give(pol, "90");
  EXPECT_EQ(message(sky), "--stokes: not with --polarizer-deg 90");
  EXPECT_TRUE(sky.given("stokes"));
  EXPECT_FALSE(sky.given("no_such"));
  EXPECT_EQ(sky.spell("mode=cube-map"), "--mode cube-map");

  // A choice's value is the state its word names, given or only declared with the job's value.
  const Param mode{"mode", "--mode", "camera", ParamKind::choice, "", 0, 1, "Lookup", {}, {}, {}, {}, {},
                   "per-pixel|cube-map"};
  const Param face{"cube_face_size", "--cube-face-size", "camera", ParamKind::integer, "", 4, 4096, "Face", {},
                   "mode=cube-map", {}, "used by {mode} cube-map only (this run is {mode=})"};
  hydrolux::ParamUse cube(hydrolux::Door::cli);
  cube.give(face, "64");
  cube.declare(mode, "per-pixel");
  EXPECT_FALSE(cube.holds("mode=cube-map"));
  EXPECT_EQ(message(cube), "--cube-face-size 64: used by --mode cube-map only (this run is --mode per-pixel)");
  cube.declare(mode, "cube-map");
  EXPECT_TRUE(cube.holds("mode=cube-map"));
  EXPECT_EQ(message(cube), "(accepted)");
}

// The one validation over a table: every row's range, an unset optional skipped.
TEST(Params, CheckFieldsChecksEveryRow) {
  hydrolux::rain::RainOptions o;
  EXPECT_NO_THROW(hydrolux::check_fields(hydrolux::rain::rain_params(), o));
  o.settings.wind_mps = 51;
  try {
    hydrolux::check_fields(hydrolux::rain::rain_params(), o);
    FAIL() << "wind 51 m/s accepted";
  } catch (const hydrolux::DomainError& e) {
    EXPECT_STREQ(e.what(), "wind_mps = 51 is outside [0, 50] m/s");
  }
  o.settings.wind_mps = 0;
  o.fov_deg = 171;
  EXPECT_THROW(hydrolux::check_fields(hydrolux::rain::rain_params(), o), hydrolux::DomainError);
}

// A path is a row too: text in and out through its accessors, no number, no range to check, its
// default the request's own; the frame jobs declare theirs (rain/frame_paths.hpp), each effect only
// the ones it takes.
struct PathRequest {
  std::string output = "out.exr";
  std::optional<std::string> input;
};

TEST(Params, PathRowsHoldTextAndTheirDefault) {
  static const hydrolux::Field<PathRequest> fields[] = {
      {Param{"output", "--output", "files", ParamKind::path, "", 0, 0, "Output"}, HYDROLUX_PARAM_PATH(output)},
      {Param{"input", "--input", "files", ParamKind::path, "", 0, 0, "Input"}, HYDROLUX_PARAM_PATH(input)},
  };
  const auto infos = hydrolux::describe_fields(std::span<const hydrolux::Field<PathRequest>>(fields));
  EXPECT_EQ(infos[0].default_text(), "out.exr");
  EXPECT_EQ(infos[1].default_text(), "");
  EXPECT_TRUE(std::isnan(infos[0].default_value));
  PathRequest r;
  fields[1].set_text(r, "frames/a.png");
  fields[0].set_text(r, "b.png");
  EXPECT_EQ(r.input, std::optional<std::string>("frames/a.png"));
  EXPECT_EQ(fields[0].text(r), "b.png");
  EXPECT_TRUE(std::isnan(fields[0].get(r)));
  EXPECT_NO_THROW(hydrolux::check_fields(std::span<const hydrolux::Field<PathRequest>>(fields), r));
  EXPECT_EQ(hydrolux::kind_name(ParamKind::path), "path");
  const Param dir{"input_dir", "--input-dir", "paths", ParamKind::path, "", 0, 0, "Frames", {}, {}, {}, {}, {}, "DIR"};
  EXPECT_EQ(dir.range_text(), "DIR");

  const auto names = [](auto table) {
    std::set<std::string_view> out;
    for (const auto& f : table) out.insert(f.param.name);
    return out;
  };
  const auto rain = names(hydrolux::rain::rain_path_params()), fog = names(hydrolux::rain::fog_path_params()),
             lens = names(hydrolux::rain::lens_drops_path_params());
  for (const auto* n : {"image", "input_dir", "video", "output", "output_dir", "mask_out", "mask_dir", "stats_json"}) {
    EXPECT_TRUE(rain.count(n) && fog.count(n) && lens.count(n)) << n;
  }
  EXPECT_TRUE(rain.count("layer_out") && !fog.count("layer_out") && !lens.count("layer_out"));
  EXPECT_TRUE(fog.count("depth_dir") && !lens.count("depth") && !lens.count("depth_dir"));
  // -o is --output's short flag in every frame job.
  for (const auto& f : hydrolux::rain::fog_path_params())
    EXPECT_EQ(f.param.short_flag, f.param.name == "output" ? "-o" : "") << f.param.name;
}

}  // namespace
