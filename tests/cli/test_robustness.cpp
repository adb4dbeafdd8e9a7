// The CLI against a generated set of bad inputs (issue #9): for every flag of every command, the bad
// values of its kind (tests/cli/robustness_cases.txt says which kind each flag takes) must give
// exit code 2 (1 for a system failure: a full disk), exactly one line on stderr naming the flag,
// nothing on stdout, no file left behind and the inputs unchanged. The command tree is walked from
// the CLI's own registration code, so a flag missing from the case list fails the test.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>

#include "common.hpp"
#include "hydrolux/jobs.hpp"
#include "support/asan.hpp"
#include "support/cli.hpp"
#include "support/crafted_images.hpp"

namespace {

namespace fs = std::filesystem;
using hydrolux::testing::lines;
using hydrolux::testing::run_argv;

using hydrolux::testing::slurp;
void spit(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string t; in >> t;) w.push_back(t);
  return w;
}

// ---- the case list ----

struct FlagCase {
  std::string flag, kind, valid;
  std::vector<std::string> base;  // empty: the command's
  bool own_base = false;
  std::vector<std::string> extras;
};
struct CommandCases {
  std::vector<std::string> base;
  std::vector<FlagCase> flags;
};

std::map<std::string, CommandCases> read_cases() {
  std::ifstream in(fs::path(HYDROLUX_SOURCE_DIR) / "tests" / "cli" / "robustness_cases.txt");
  std::map<std::string, CommandCases> all;
  std::string line, current;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    if (line.rfind("command ", 0) == 0) {
      const auto colon = line.find(':');
      current = trim(line.substr(8, colon - 8));
      all[current].base = words(line.substr(colon + 1));
      continue;
    }
    FlagCase f;
    std::string head = line;
    if (const auto c = line.find(": "); c != std::string::npos) {
      head = line.substr(0, c);
      std::string rest = line.substr(c + 2) + " |";
      for (std::size_t pos; (pos = rest.find(" |")) != std::string::npos; rest.erase(0, pos + 2)) {
        f.extras.push_back(trim(rest.substr(0, pos)));
        if (!rest.empty() && rest.size() > pos + 2 && rest[pos + 2] == ' ') rest.erase(pos + 2, 1);
      }
    }
    if (const auto at = head.find(" @ "); at != std::string::npos) {
      f.base = words(head.substr(at + 3));
      f.own_base = true;
      head = head.substr(0, at);
    }
    const auto w = words(head);
    f.flag = w.at(0);
    f.kind = w.at(1);
    if (w.size() > 2) f.valid = w[2];
    all[current].flags.push_back(f);
  }
  return all;
}

// ---- the CLI's own command tree ----

struct OptionInfo {
  std::vector<std::string> names;  // "--output", "-o"
  std::string type_name;           // "INT:[8, 16384] px"
};

std::map<std::string, std::map<std::string, OptionInfo>> cli_tree() {
  static CLI::App app;
  static const auto commands = hydrolux::cli::add_all_commands(app);
  std::map<std::string, std::map<std::string, OptionInfo>> tree;
  for (const auto& cmd : commands) {
    std::string path = cmd.app->get_name();
    for (auto* p = cmd.app->get_parent(); p && p != &app; p = p->get_parent()) path = p->get_name() + " " + path;
    auto& options = tree[path];
    for (const auto* opt : cmd.app->get_options()) {
      if (opt->get_lnames().empty() || opt->get_lnames().front() == "help") continue;
      if (opt->get_group().empty()) continue;  // a deprecated spelling: the same option as its new one
      OptionInfo info;
      for (const auto& l : opt->get_lnames()) info.names.push_back("--" + l);
      for (const auto& s : opt->get_snames()) info.names.push_back("-" + s);
      info.type_name = opt->get_type_name();
      options[info.names.front()] = info;
    }
  }
  return tree;
}

// ---- generating the cases ----

// Under AddressSanitizer and UndefinedBehaviorSanitizer (make test-sanitize, at -O1) each case is a
// process start of several hundred milliseconds, and the numeric flags' generic bad values (about
// 1200 of the 1600 cases) test CLI11's parsing through one validator each: there the sanitizers run
// a fixed subset of them ("abc", a control sequence, the values below and above the range, "1.5" for
// whole numbers) and every flag's listed cases; every file, path and text case runs in both suites,
// but for the nine files of bad content for the image decoders (truncated, huge headers, JPEG and TIFF
// bombs: one shared loader behind every image flag, and fuzz_image's target), which run for the first
// flag of each input kind only. The Release suite (make test) runs every case.
constexpr bool kSanitizerSubset = HYDROLUX_TEST_ASAN != 0;

struct Fixtures {
  fs::path root, png, exr;
  fs::path frames;  // three copies of png, f0.png to f2.png: a folder of frames
};

struct Case {
  std::string command, flag, label;
  std::vector<std::string> args;
  std::vector<std::string> names;                 // the flag's names; one must appear in the message
  std::function<void(const fs::path& dir)> setup;  // files the case needs in its folder
  int expected_code = 2;
  bool fsize_limit = false;
};

std::string substitute(std::string s, const fs::path& dir, const Fixtures& fx) {
  for (const auto& [key, value] :
       {std::pair{std::string("{dir}"), dir.string()}, {"{png}", fx.png.string()}, {"{exr}", fx.exr.string()},
        {"{frames}", fx.frames.string()}})
    for (std::size_t pos; (pos = s.find(key)) != std::string::npos;) s.replace(pos, key.size(), value);
  return s;
}

// The base arguments without the flag (under any of its names) and its value.
std::vector<std::string> without(const std::vector<std::string>& base, const std::vector<std::string>& names,
                                 bool takes_value) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < base.size(); ++i) {
    if (std::find(names.begin(), names.end(), base[i]) != names.end()) {
      if (takes_value) ++i;
      continue;
    }
    out.push_back(base[i]);
  }
  return out;
}

// Values below and above the range a validator states ("FLOAT:[0.001, 1000]", "INT:(0, 1e+06] um").
std::vector<std::string> outside_range(const std::string& type_name) {
  static const std::regex range(R"(([\[(])\s*([-+0-9.eE]+),\s*([-+0-9.eE]+)\])");
  std::smatch m;
  if (!std::regex_search(type_name, m, range)) return {};
  const double lo = std::stod(m[2]), hi = std::stod(m[3]);
  const bool open = m[1] == "(";
  const double below = open ? lo : lo - std::max(1.0, std::fabs(lo) * 0.5);
  const double above = hi + std::max(1.0, std::fabs(hi));
  const bool integer = type_name.rfind("INT", 0) == 0;
  const auto text = [&](double v) {
    std::ostringstream s;
    s.precision(17);
    if (integer) s << std::llround(v); else s << v;
    return s.str();
  };
  return {text(below), text(above)};
}

std::vector<Case> generate(const std::map<std::string, CommandCases>& cases,
                           const std::map<std::string, std::map<std::string, OptionInfo>>& tree) {
  std::vector<Case> out;
  std::set<std::string> decoders_for;  // the input kinds whose flag got the decoders' bad content
  for (const auto& [command, cc] : cases) {
    const auto& options = tree.at(command);
    const auto cmd_words = words(command);
    // The command's input, for "output is the same file as the input".
    const FlagCase* input = nullptr;
    for (const auto& f : cc.flags)
      if (f.kind.rfind("input-", 0) == 0) input = &f;
    for (const auto& f : cc.flags) {
      const auto& info = options.at(f.flag);
      const bool takes_value = f.kind != "switch";
      const auto base = without(f.own_base ? f.base : cc.base, info.names, takes_value);
      const auto add = [&](const std::string& label, const std::string& value, std::function<void(const fs::path&)> setup = {},
                           int code = 2, std::vector<std::string> more = {}) {
        Case c{command, f.flag, label, cmd_words, info.names, std::move(setup), code, false};
        auto b = base;
        if (!more.empty()) {  // extra flags replace their own occurrences in the base
          for (std::size_t i = 0; i + 1 < more.size(); i += 2) b = without(b, {more[i]}, true);
          b.insert(b.end(), more.begin(), more.end());
        }
        c.args.insert(c.args.end(), b.begin(), b.end());
        c.args.push_back(f.flag + "=" + value);
        out.push_back(std::move(c));
      };
      std::vector<std::string> values = f.extras;
      if (f.kind == "number" || f.kind == "integer") {
        // Under the sanitizers a fixed subset (see kSanitizerSubset): every flag's listed cases, text that
        // is no number, a control sequence and the values beyond its range; the Release suite runs all.
        for (const char* v : {"abc", "", "nan", "inf", "-inf", "1e999", "0x10", "1,5", " 1", "1\n2", "\x1b[2J"})
          if (!kSanitizerSubset || std::string_view(v) == "abc" || std::string_view(v) == "\x1b[2J") values.push_back(v);
        for (const auto& v : outside_range(info.type_name)) values.push_back(v);
        if (f.kind == "integer")
          for (const char* v : {"1.5", "1e30", "99999999999999999999"})
            if (!kSanitizerSubset || std::string_view(v) == "1.5") values.push_back(v);
      } else if (f.kind == "choice") {
        values.insert(values.end(), {"nope", ""});
      } else if (f.kind == "switch") {
        values.push_back("maybe");
      }
      for (const auto& v : values) add(v.empty() ? "(empty)" : v, v);

      if (f.kind == "input-image" || f.kind == "input-env") {
        const bool env = f.kind == "input-env";
        const std::string img = env ? ".exr" : ".png", hdr = env ? ".hdr" : ".hdr";
        const std::string good = f.valid;  // {png} or {exr}
        add("missing", "{dir}/missing" + img);
        add("control characters", "{dir}/no\nsuch\x1b[2J" + img);  // printed escaped, on one line
        add("folder", "{dir}/folder" + img, [img](const fs::path& d) { fs::create_directories(d / ("folder" + img)); });
        add("fifo", "{dir}/fifo" + img, [img](const fs::path& d) { ::mkfifo((d / ("fifo" + img)).c_str(), 0600); });
        add("/dev/zero", "/dev/zero");
        add("empty file", "{dir}/empty" + img, [img](const fs::path& d) { spit(d / ("empty" + img), ""); });
        add("text", "{dir}/text" + img, [img](const fs::path& d) { spit(d / ("text" + img), "not an image\n"); });
        // Bad content for the decoders (io::read_image behind every image flag, fuzzed by fuzz_image):
        // under the sanitizers for the first flag of each kind only (see kSanitizerSubset).
        if (!kSanitizerSubset || decoders_for.insert(f.kind).second) {
          add("truncated png", "{dir}/half" + img, [img](const fs::path& d) {
            const std::string png = slurp(d.parent_path() / "fixture.png");
            spit(d / ("half" + img), png.substr(0, png.size() / 2));
          });
          add("truncated exr", "{dir}/half-exr" + img, [img](const fs::path& d) {
            const std::string exr = slurp(d.parent_path() / "fixture.exr");
            spit(d / ("half-exr" + img), exr.substr(0, exr.size() * 2 / 3));
          });
          add("huge png header", "{dir}/huge" + img, [img](const fs::path& d) {
            spit(d / ("huge" + img), hydrolux::testing::png_claiming(100000, 100000));
          });
          add("huge hdr header", "{dir}/huge" + hdr, [hdr](const fs::path& d) {
            spit(d / ("huge" + hdr), hydrolux::testing::hdr_claiming(200000, 200000));
          });
          add("png claiming more than its bytes", "{dir}/big" + img, [img](const fs::path& d) {
            spit(d / ("big" + img), hydrolux::testing::png_claiming(12000, 9000));
          });
          // JPEG and TIFF content (told apart by its bytes, whatever the name).
          add("truncated jpeg", "{dir}/cut-jpeg" + img, [img](const fs::path& d) {
            spit(d / ("cut-jpeg" + img), hydrolux::testing::jpeg_with_scans(64, 64, 2, true));
          });
          add("jpeg with 500 scans", "{dir}/scans" + img, [img](const fs::path& d) {
            spit(d / ("scans" + img), hydrolux::testing::jpeg_with_scans(4096, 4096, 500));
          });
          add("tiff tile bomb", "{dir}/tiles" + img, [img](const fs::path& d) {
            spit(d / ("tiles" + img), hydrolux::testing::tiff_claiming(1, 1, 65536, 1, 1));
          });
          add("truncated tiff", "{dir}/cut-tiff" + img, [img](const fs::path& d) {
            spit(d / ("cut-tiff" + img), hydrolux::testing::tiff_claiming(64, 64, 0, 1000, 64 * 64));
          });
        }
        if (::geteuid() != 0)
          add("unreadable", "{dir}/locked" + img, [img, good](const fs::path& d) {
            spit(d / ("locked" + img), "x");
            fs::permissions(d / ("locked" + img), fs::perms::none);
          });
        (void)good;
      }
      if (f.kind == "output-image" || f.kind == "output-table" || f.kind == "output-data" || f.kind == "output-scene") {
        // output-table: the output must be .exr (hydrolux lee writes its .png and .json beside it);
        // output-data: .npy (or .csv, .json); output-scene: a renderer's scene file, .xml (or .pbrt).
        const std::string ext = f.kind == "output-table" ? ".exr"
                                : f.kind == "output-data" ? ".npy"
                                : f.kind == "output-scene" ? ".xml"
                                                           : ".png";
        add("missing folder", "{dir}/missing/out" + ext);
        add("control characters", "{dir}/no\nfolder\r/out" + ext);
        add("a folder", "{dir}/folder" + ext, [ext](const fs::path& d) { fs::create_directories(d / ("folder" + ext)); });
        add("file as folder", "{dir}/file/out" + ext, [](const fs::path& d) { spit(d / "file", "x"); });
        add("wrong extension", f.kind == "output-table" ? "{dir}/out.png"
                               : f.kind == "output-data" || f.kind == "output-scene" ? "{dir}/out.txt"
                                                                                     : "{dir}/out.jpg");
        add("/dev/null", "/dev/null");
        add("no name", "");
        if (input) add("same as input", input->valid, {}, 2, {input->flag, input->valid});
        // A full disk, by a file-size limit: the old file survives, exit 1.
        add("full disk", "{dir}/old" + ext, [ext](const fs::path& d) { spit(d / ("old" + ext), "old"); }, 1);
        out.back().fsize_limit = true;
      }
      if (f.kind == "output-dir") {
        add("a file", "{dir}/file", [](const fs::path& d) { spit(d / "file", "x"); });
        add("under a file", "{dir}/file/gallery", [](const fs::path& d) { spit(d / "file", "x"); });
        add("full disk", "{dir}/gallery", {}, 1);
        out.back().fsize_limit = true;
      }
    }
  }
  return out;
}

std::vector<std::string> listing(const fs::path& d) {
  std::vector<std::string> n;
  for (const auto& e : fs::recursive_directory_iterator(d)) n.push_back(fs::relative(e.path(), d).string());
  std::sort(n.begin(), n.end());
  return n;
}

class Robustness : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fx_.root = fs::temp_directory_path() / ("hydrolux_robustness_" + std::to_string(::getpid()));
    fs::remove_all(fx_.root);
    fs::create_directories(fx_.root);
    fx_.png = fx_.root / "fixture.png";
    fx_.exr = fx_.root / "fixture.exr";
    auto r = run_argv({"drop", "render", "-q", "--size", "32", "--samples", "1", "-o", fx_.png.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    // A 64 x 32 equirectangular map: the undistorted view of the drop picture is 2:1.
    r = run_argv({"drop", "undistort", "-q", "--image", fx_.png.string(), "--drop-center", "16,16",
                  "--drop-radius-px", "10", "--size", "64x32", "--fov-deg", "120", "-o", fx_.exr.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    fx_.frames = fx_.root / "frames";
    fs::create_directories(fx_.frames);
    for (const char* name : {"f0.png", "f1.png", "f2.png"}) fs::copy_file(fx_.png, fx_.frames / name);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(fx_.root, ec);
  }
  static Fixtures fx_;
};
Fixtures Robustness::fx_;

// Every flag of every command is in the case list, and every listed flag exists.
TEST_F(Robustness, CaseListCoversEveryFlag) {
  const auto cases = read_cases();
  const auto tree = cli_tree();
  for (const auto& [command, options] : tree) {
    if (options.empty()) continue;  // "drop" itself only groups subcommands
    ASSERT_TRUE(cases.count(command)) << "robustness_cases.txt lacks the command '" << command << "'";
    const auto& listed = cases.at(command).flags;
    for (const auto& [name, info] : options)
      EXPECT_TRUE(std::any_of(listed.begin(), listed.end(), [&](const FlagCase& f) { return f.flag == name; }))
          << "robustness_cases.txt lacks " << command << " " << name << " (" << info.type_name << ")";
    for (const auto& f : listed) EXPECT_TRUE(options.count(f.flag)) << command << " has no flag " << f.flag;
  }
  for (const auto& [command, cc] : cases) EXPECT_TRUE(tree.count(command)) << "no command " << command;
}

// Every declared parameter (hydrolux/jobs.hpp) is a flag of its command, listed with the cases of its
// kind: a real number's out-of-range, non-finite and non-numeric values; a whole number's fractions
// too; a switch's; a choice's; a size's, span's or colour's listed texts; a path's file cases. So a parameter added to a job's table gets its bad-input cases from the table.
TEST_F(Robustness, EveryDeclaredParameterHasItsCases) {
  const auto cases = read_cases();
  const auto tree = cli_tree();
  for (const auto& job : hydrolux::job_specs()) {
    const std::string command = std::string(job.command).substr(std::string("hydrolux ").size());
    ASSERT_TRUE(tree.count(command)) << job.name << ": no command " << command;
    ASSERT_TRUE(cases.count(command)) << "robustness_cases.txt lacks the command " << command;
    for (const auto& info : job.params) {
      const auto& p = *info.param;
      const std::string flag(p.flag);
      EXPECT_TRUE(tree.at(command).count(flag)) << command << " does not register the declared " << flag;
      const auto& listed = cases.at(command).flags;
      const auto it = std::find_if(listed.begin(), listed.end(), [&](const FlagCase& f) { return f.flag == flag; });
      ASSERT_NE(it, listed.end()) << "robustness_cases.txt lacks " << command << " " << flag;
      // A size, a span or a colour is a text of parts, listed with its own bad texts.
      const char* kind = p.kind == hydrolux::ParamKind::real      ? "number"
                         : p.kind == hydrolux::ParamKind::integer ? "integer"
                         : p.kind == hydrolux::ParamKind::flag    ? "switch"
                         : p.kind == hydrolux::ParamKind::choice  ? "choice"
                                                                  : "text";
      // A path is listed with the cases of the file it names: an input's or output's kind (an image, a
      // table, a folder), or a text with its own bad paths.
      if (p.kind == hydrolux::ParamKind::path) {
        const bool file_kind = it->kind == "text" || it->kind.rfind("input-", 0) == 0 || it->kind.rfind("output-", 0) == 0;
        EXPECT_TRUE(file_kind) << command << " " << flag << ": a path listed as " << it->kind;
        continue;
      }
      EXPECT_EQ(it->kind, kind) << command << " " << flag << ": listed as " << it->kind << ", declared " << kind;
    }
  }
}

// The base argument lines themselves succeed (else every case would prove nothing).
TEST_F(Robustness, BaseArgumentsSucceed) {
  const auto cases = read_cases();
  const fs::path dir = fx_.root / "base";
  for (const auto& [command, cc] : cases) {
    // The gallery's base run is its whole render (43 figures: 55 s in Release, ~390 s under the
    // sanitizers, measured 2026-11-28), which gallery.test_gallery already runs through the CLI in the
    // Release suite: not a second time here. Its bad inputs still run in both suites.
    if (command == "gallery") continue;
    fs::create_directories(dir);
    std::vector<std::string> args = words(command);
    for (const auto& a : cc.base) args.push_back(substitute(a, dir, fx_));
    const auto r = run_argv(args);
    EXPECT_EQ(r.code, 0) << command << ": " << r.err;
    fs::remove_all(dir);
  }
}

TEST_F(Robustness, BadInputsKeepTheContract) {
  const auto cases = generate(read_cases(), cli_tree());
  ASSERT_GT(cases.size(), 300u);
  std::vector<std::string> hashes_before = {slurp(fx_.png), slurp(fx_.exr)};
  std::mutex mutex;
  std::vector<std::string> failures;
  std::size_t next = 0;
  const auto worker = [&] {
    while (true) {
      std::size_t i;
      {
        std::lock_guard lock(mutex);
        if (next >= cases.size()) return;
        i = next++;
      }
      const Case& c = cases[i];
      const fs::path dir = fx_.root / ("case" + std::to_string(i));
      fs::create_directories(dir);
      if (c.setup) c.setup(dir);
      const auto before = listing(dir);
      std::vector<std::string> args;
      for (const auto& a : c.args) args.push_back(substitute(a, dir, fx_));
      const auto r = run_argv(args, c.fsize_limit ? std::function<void()>([] {
        const rlimit lim{400, 400};  // bytes: more than a message (stderr is a file), less than any output
        ::setrlimit(RLIMIT_FSIZE, &lim);
      })
                                                  : std::function<void()>());
      std::string why;
      if (r.code != c.expected_code) why += "exit code " + std::to_string(r.code) + "; ";
      if (lines(r.err) != 1) why += std::to_string(lines(r.err)) + " lines on stderr; ";
      if (std::any_of(r.err.begin(), r.err.end(), [](char ch) { return (ch >= 0 && ch < 0x20 && ch != '\n') || ch == 0x7f; }))
        why += "control characters on stderr; ";
      if (!std::any_of(c.names.begin(), c.names.end(), [&](const std::string& n) { return r.err.find(n) != std::string::npos; }))
        why += "the message does not name the flag; ";
      for (const char* bad : {"Could not convert", "internal error", "nan ", "-nan", "bad_alloc", "libpng"})
        if (r.err.find(bad) != std::string::npos) why += std::string("the message says '") + bad + "'; ";
      if (!r.out.empty()) why += "output on stdout; ";
      std::error_code ec;
      fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add, ec);
      if (listing(dir) != before) why += "files left behind or removed; ";
      for (const char* old_name : {"old.png", "old.exr", "old.npy", "old.xml"})
        if (c.fsize_limit && fs::exists(dir / old_name) && slurp(dir / old_name) != "old") why += "old output replaced; ";
      if (!why.empty()) {
        std::string cmd;
        for (const auto& a : args) cmd += " '" + a + "'";
        std::lock_guard lock(mutex);
        failures.push_back(c.command + " " + c.flag + " [" + c.label + "]: " + why + "\n   hydrolux" + cmd +
                           "\n   stderr: " + r.err);
      }
      for (const auto& e : fs::recursive_directory_iterator(dir, ec))
        fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
      fs::remove_all(dir, ec);
    }
  };
  std::vector<std::thread> pool;
  const unsigned n = std::max(2u, std::min(8u, std::thread::hardware_concurrency()));
  for (unsigned t = 0; t < n; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  for (const auto& f : failures) ADD_FAILURE() << f;
  EXPECT_EQ(slurp(fx_.png), hashes_before[0]) << "an input changed";
  EXPECT_EQ(slurp(fx_.exr), hashes_before[1]) << "an input changed";
  std::cout << cases.size() << " bad-input cases run, " << failures.size() << " failed\n";
}

}  // namespace
