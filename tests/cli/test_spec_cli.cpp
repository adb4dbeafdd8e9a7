// hydrolux spec --json: the library's declared parameters (hydrolux/jobs.hpp) as JSON, which the web
// demo builds its ranges and defaults from. The dump parses, holds every job and parameter in the
// tables' order with the ranges, kinds, defaults and conditions the library declares (compared with
// the tables themselves), and the CLI prints exactly the library's text, the same on every run.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "hydrolux/jobs.hpp"
#include "hydrolux/scene/sky_params.hpp"
#include "support/cli.hpp"

namespace {

using hydrolux::testing::run;
using Json = nlohmann::json;

// "a|b" as the dump lists it, split here with getline (not the library's splitter).
Json words(std::string_view text) {
  Json out = Json::array();
  std::istringstream in{std::string(text)};
  for (std::string w; std::getline(in, w, '|');) out.push_back(w);
  return out;
}

Json optional_text(std::string_view text) { return text.empty() ? Json(nullptr) : Json(std::string(text)); }

// One parameter's row against the library's declaration.
void expect_row(const Json& row, const hydrolux::ParamInfo& info, const std::string& job) {
  const hydrolux::Param& p = *info.param;
  const std::string where = job + "." + std::string(p.name);
  EXPECT_EQ(row.at("name"), p.name) << where;
  EXPECT_EQ(row.at("flag"), p.flag) << where;
  EXPECT_EQ(row.at("group"), p.group) << where;
  using K = hydrolux::ParamKind;
  const char* kind = p.kind == K::real      ? "real"
                     : p.kind == K::integer ? "integer"
                     : p.kind == K::flag    ? "flag"
                     : p.kind == K::choice  ? "choice"
                     : p.kind == K::size    ? "size"
                     : p.kind == K::span    ? "span"
                     : p.kind == K::colour  ? "colour"
                                            : "path";
  EXPECT_EQ(row.at("kind"), kind) << where;
  EXPECT_EQ(row.at("words"), words(p.words)) << where;
  EXPECT_EQ(row.at("unit"), p.unit) << where;
  EXPECT_EQ(row.value("short_flag", Json(nullptr)), optional_text(p.short_flag)) << where;
  if (p.kind == K::path) {  // a file's or a folder's name: no range, its default a text or none
    EXPECT_TRUE(row.at("lo").is_null() && row.at("hi").is_null()) << where;
    EXPECT_EQ(row.at("default"), optional_text(info.default_path)) << where;
    EXPECT_EQ(row.at("help"), p.help) << where;
    return;
  }
  EXPECT_EQ(row.at("lo").get<double>(), p.lo) << where;
  EXPECT_EQ(row.at("hi").get<double>(), p.hi) << where;
  if (p.kind != K::real && p.kind != K::span && p.kind != K::colour) {
    EXPECT_TRUE(row.at("lo").is_number_integer()) << where;
    EXPECT_TRUE(row.at("hi").is_number_integer()) << where;
  }
  const Json& def = row.at("default");
  if (std::isnan(info.default_value))
    EXPECT_TRUE(def.is_null()) << where;
  else if (p.kind == K::flag)
    EXPECT_EQ(def, info.default_value != 0) << where;
  else if (p.kind == K::choice)  // the word, as a door takes it
    EXPECT_EQ(def, words(p.words).at(std::size_t(info.default_value))) << where;
  else if (p.parts() > 1) {  // the parts, as a list
    ASSERT_EQ(def.size(), std::size_t(p.parts())) << where;
    for (int i = 0; i < p.parts(); ++i) EXPECT_EQ(def.at(std::size_t(i)).get<double>(), info.default_parts[std::size_t(i)]) << where;
  } else
    EXPECT_EQ(def.get<double>(), info.default_value) << where;
  EXPECT_EQ(row.at("help"), p.help) << where;
  EXPECT_EQ(row.at("excludes"), optional_text(p.excludes)) << where;
  EXPECT_EQ(row.at("only_with"), words(p.only_with)) << where;
  EXPECT_EQ(row.at("not_with"), words(p.not_with)) << where;
  EXPECT_EQ(row.at("why"), optional_text(p.why)) << where;
  EXPECT_EQ(row.at("deprecated"), optional_text(p.deprecated)) << where;
}

TEST(SpecCli, JsonHoldsEveryJobAsTheLibraryDeclaresIt) {
  const auto r = run("spec --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Json dump = Json::parse(r.out);  // throws (fails the test) unless it is JSON
  EXPECT_EQ(dump.at("format"), "hydrolux-spec");
  EXPECT_EQ(dump.at("format_version"), 1);
  const auto& specs = hydrolux::job_specs();
  ASSERT_EQ(dump.at("jobs").size(), specs.size());
  for (std::size_t j = 0; j < specs.size(); ++j) {
    const Json& job = dump["jobs"][j];
    EXPECT_EQ(job.at("name"), specs[j].name);
    EXPECT_EQ(job.at("command"), specs[j].command);
    EXPECT_EQ(job.at("summary"), specs[j].summary);
    EXPECT_EQ(job.at("python"), optional_text(specs[j].python));
    ASSERT_EQ(job.at("params").size(), specs[j].params.size()) << specs[j].name;
    for (std::size_t i = 0; i < specs[j].params.size(); ++i)
      expect_row(job["params"][i], specs[j].params[i], std::string(specs[j].name));
  }
}

// The sky's rows, which the web demo reads: the library's own table (scene::sky_params), field by
// field, with the defaults of a default request; the CLI's text is the library's dump, byte for byte,
// and the same on a second run.
TEST(SpecCli, SkyRowsAreTheSkyTableAndTheOutputIsStable) {
  const auto r = run("spec --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, hydrolux::job_specs_json());
  EXPECT_EQ(run("spec --json").out, r.out);
  const Json dump = Json::parse(r.out);
  const Json* sky = nullptr;
  for (const auto& job : dump.at("jobs"))
    if (job.at("name") == "sky") sky = &job;
  ASSERT_NE(sky, nullptr);
  const auto fields = hydrolux::scene::sky_params();
  const auto infos = hydrolux::describe_fields(fields);
  ASSERT_EQ(sky->at("params").size(), fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) expect_row(sky->at("params")[i], infos[i], "sky");
  // A quantity whose default the request leaves unset has none in the dump.
  const auto* polarizer = hydrolux::find_field(fields, "polarizer_deg");
  ASSERT_NE(polarizer, nullptr);
  EXPECT_TRUE(sky->at("params")[std::size_t(polarizer - fields.data())].at("default").is_null());
}

// Strings the JSON must escape come through intact, and every job's table of text is listed too.
TEST(SpecCli, TableListsEveryFlagAndJsonEscapesText) {
  const auto r = run("spec");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& job : hydrolux::job_specs()) {
    EXPECT_NE(r.out.find(std::string(job.command) + ": "), std::string::npos) << job.command;
    for (const auto& info : job.params) EXPECT_NE(r.out.find(info.param->flag), std::string::npos) << info.param->flag;
  }
  static const hydrolux::Param odd{"odd", "--odd", "g", hydrolux::ParamKind::real, "\"q\\\n\t\x01", 0, 1, "a \"b\" c"};
  const hydrolux::JobSpec job{"j", "hydrolux j", "s", {{&odd, 0.5}}};
  const Json parsed = Json::parse(hydrolux::job_spec_json(job));
  EXPECT_EQ(parsed.at("params")[0].at("unit"), "\"q\\\n\t\x01");
  EXPECT_EQ(parsed.at("params")[0].at("help"), "a \"b\" c");
  EXPECT_EQ(parsed.at("params")[0].at("default"), 0.5);
  EXPECT_TRUE(parsed.at("python").is_null());
}

}  // namespace
