#pragma once
// Declared parameters: what a user sets for a job (its name, unit, valid range, default and one
// line of help), written once in the library beside the settings it fills, and read by every door:
// the CLI registers its flags from it, the Python functions take its names as keywords, the batch
// jobs build their argparse options from it and docs/reference.md is generated from it (checked
// current by a test). The models are pbrt-v4's ParameterDictionary and Mitsuba 3's declared plugin
// parameters; here a job's table is a plain array the compiler checks.
//
// A parameter's default is not restated here: it is the value of the member it fills in a
// default-constructed request (`get(Request{})`), so the struct's initializer stays the one place.
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace hydrolux {

enum class ParamKind {
  real,     // a finite number in [lo, hi]
  integer,  // a whole number in [lo, hi] (exact up to 2^53)
  flag,     // on or off; the CLI's flag turns the default around (e.g. --no-unresolved)
  // One word of Param::words ("per-pixel|cube-map|half-dome"); its value is the word's index, so
  // the row fills an enum whose values are the words in their order (choice_param, shared_params.hpp).
  choice,
  // Values of several parts, each in [lo, hi], their names in Param::words ("W|H"), written as the
  // CLI's text (below) or as Python's tuple ((1280, 720)):
  size,    // two whole numbers, "WxH"
  span,    // two numbers, the first not above the second, "NEAR:FAR"
  colour,  // three numbers, "R,G,B"
  // A file's or a folder's name, taken as written (io/files.hpp checks it when the job declares its
  // files); Param::words names what it is in the help's type column, "FILE" or "DIR". Its row's
  // accessors are Field::get_text and set_text, and it has no range.
  path,
};

// The words of "a|b|c" (a choice's words, a condition's words); empty text: none.
std::vector<std::string_view> split_words(std::string_view text);

// "real", "integer", "flag", "choice", "size", "span", "colour", "path": the kind as the JSON spec and Python name it.
std::string_view kind_name(ParamKind kind);

// A parameter's value: its one number in [0], or its parts in order (a size, a span, a colour).
inline constexpr int kMaxParamParts = 3;
using ParamValue = std::array<double, kMaxParamParts>;

// The door a user came through, which spells a parameter its own way in every message: the
// library's name ("rain_rate_mmh"), the CLI's and the batch jobs' flag ("--rain-rate-mmh"), Python's keyword.
enum class Door { library, cli, python };

struct Param {
  std::string_view name;  // the Python keyword, the JSON key, the library's quantity: "rain_rate_mmh"
  std::string_view flag;  // the CLI's and the batch jobs' flag: "--rain-rate-mmh"
  // Which part of the job it sets ("rain", "camera", "files"): the docs group by it, and a door
  // that takes only a part (the Python functions take arrays, not files) selects by it.
  std::string_view group;
  ParamKind kind = ParamKind::real;
  std::string_view unit;  // "mm/h", "deg"; empty for a pure number
  double lo = 0, hi = 0;  // the valid range, both ends included
  std::string_view help;  // one line, as the CLI's --help shows it
  // Another parameter this one replaces (fov_deg for focal_mm): giving both is refused.
  std::string_view excludes = {};
  // Where the parameter has an effect, declared (ParamUse::report_unused reads them): `only_with`,
  // one or more words between '|', of which one must hold; `not_with`, words of which none may. A
  // word is another parameter's name (it holds when given), a choice's value ("mode=cube-map": the row
  // mode given or declared with that word), or a state the job declares it is in ("lut": tables given;
  // "many_radii"). `why` says it in the message, with {name}
  // spelled by the door ("--nodes", "nodes") and {name=} with its value ("--size-distribution
  // mono"); empty: "used only with A or B" / "not with A".
  std::string_view only_with = {};
  std::string_view not_with = {};
  std::string_view why = {};
  // The name this parameter had before (one per quantity: "rate_mmh" for rain_rate_mmh), kept for one
  // release: each door still takes it (the CLI as --rate-mmh, Python as the keyword) with one warning.
  std::string_view deprecated = {};
  // Words between '|': a choice's, in the order of their values (0, 1, ...), "physical|whitepaper"; a
  // size's, span's or colour's part names, "W|H", "NEAR|FAR", "R|G|B"; a path's "FILE" or "DIR".
  std::string_view words = {};
  // A one-letter flag besides `flag` ("-o" for --output), or empty.
  std::string_view short_flag = {};

  // "--rate-mmh" for "rate_mmh": the flag of a name, as the CLI spells names it has no row for.
  static std::string flag_of(std::string_view name);
  // The warning a door prints once when the deprecated spelling `old` of this parameter is used.
  std::string deprecation_warning(std::string_view old, std::string_view now) const;

  // "[0, 500] mm/h"; a choice's words: "per-pixel, cube-map or half-dome"; a size's "[1, 16384] px"; a
  // path's "FILE" or "DIR".
  std::string range_text() const;
  // The parts of its value: 2 for a size or a span, 3 for a colour, else 1.
  int parts() const;
  // Its words (Param::words), in order.
  std::vector<std::string_view> word_list() const;
  // The value of a choice's word `word`, or -1 for none of them.
  int choice_index(std::string_view word) const;
  // How a door writes a value of this kind: "WxH", "NEAR:FAR", "R,G,B" (Door::cli) or "(W, H)"
  // (Door::python); a choice's words; a number's range.
  std::string form(Door door) const;
  // A value as `door` writes it: a choice's word, "on"/"off" for a flag, "1280x720" or (1280, 720) for a
  // size, else the number ("25", "0.008").
  std::string value_text(const ParamValue& value, Door door = Door::cli) const;
  std::string value_text(double value) const { return value_text(ParamValue{value}); }
  // The value a user wrote as text (the CLI's flag): a choice's word or the parts of a size, span or
  // colour, checked. Throws Error "--size '12x': expected WxH, each a whole number in [1, 16384] px"
  // (UnknownNameError for a word not among a choice's), spelled by `door`; the numbers and switches
  // are each door's own to read (std::logic_error).
  ParamValue parse_text(std::string_view text, Door door) const;
  // Throws DomainError "rain_rate_mmh = 600 is outside [0, 500] mm/h" (quantity: the name) unless the
  // value lies in the range; for an integer also unless it is whole.
  void check(double value) const;
  // The same for every part of a value (a size's parts whole, a span's in order): throws Error (in the
  // door's words, which no door rewrites) "size (0, 720): expected (W, H), each a whole number in ...".
  void check(const ParamValue& value, Door door) const;
};

// `param` as `door` spells it.
std::string_view spelled(const Param& param, Door door);

// Ranges that several jobs' parameters share, stated once: a temperature before the medium's own
// range is checked (from absolute zero to 1000 C), and the worker threads (0: every core).
inline constexpr double kMinTemperatureC = -273.15, kMaxTemperatureC = 1000;
// The rain rate, mm/h: one name (rain_rate_mmh) and one upper limit for every job and call that takes
// one (the rain, the sky, rainphys, marshall-palmer:H, SizeDistribution::marshall_palmer).
// Marshall-Palmer is fitted to at most ~100 mm/h, and cloudbursts reach a few hundred. The lower end is
// 0 where a job takes no rain (the rain, the sky), and kMinDistributionRainRateMmh where a size
// distribution needs a positive rate (Lambda = 8200 h^-0.21 is infinite at 0 mm/h; 0.01 mm/h is a trace
// of drizzle).
inline constexpr double kMaxRainRateMmh = 500;
inline constexpr double kMinDistributionRainRateMmh = 0.01;
inline constexpr int kMaxThreads = 1024;
// The width or height in pixels that a size parameter (--size WxH) may ask for.
inline constexpr int kMaxImageSide = 16384;

// A parameter bound to the request it fills, part by part (a size's width is part 0, its height part
// 1; a single value is part 0). `get_part` reads (NaN where it has no value of its own until given, e.g.
// a field of view that replaces the focal length); `set_part` stores a checked value. A path's row has
// text accessors instead (get_text: empty while unset), and no number (NaN).
template <class Request>
struct Field {
  Param param;
  double (*get_part)(const Request&, int part) = nullptr;
  void (*set_part)(Request&, int part, double) = nullptr;
  std::string (*get_text)(const Request&) = nullptr;
  void (*set_text)(Request&, std::string) = nullptr;

  // A single value (part 0).
  double get(const Request& r) const { return get_part ? get_part(r, 0) : std::numeric_limits<double>::quiet_NaN(); }
  void set(Request& r, double v) const { set_part(r, 0, v); }
  // Every part.
  ParamValue value(const Request& r) const {
    ParamValue v{};
    if (!get_part) v.fill(std::numeric_limits<double>::quiet_NaN());
    else
      for (int i = 0; i < param.parts(); ++i) v[std::size_t(i)] = get_part(r, i);
    return v;
  }
  void set_value(Request& r, const ParamValue& v) const {
    for (int i = 0; i < param.parts(); ++i) set_part(r, i, v[std::size_t(i)]);
  }
  // A path's text (empty while unset, and for the other kinds).
  std::string text(const Request& r) const { return get_text ? get_text(r) : std::string(); }
};

// The accessors of a table row (a Field's get_part and set_part) for a member of the request:
// HYDROLUX_PARAM_MEMBER(settings.rain_rate_mmh) for a number, a bool or a choice's enum,
// HYDROLUX_PARAM_OPTIONAL(fov_deg) for a std::optional<double> (NaN while unset: no default of its own),
// HYDROLUX_PARAM_PARTS(camera.width, camera.height) for a size or a span of two members,
// HYDROLUX_PARAM_INDEXED(light_color) for a colour (a member indexed [0], [1], [2]) and
// HYDROLUX_PARAM_OPTIONAL_PARTS(size) for a std::optional<std::array<T, N>> (NaN parts while unset) and
// HYDROLUX_PARAM_PATH(output) for a path's std::string or std::optional<std::string> (empty while unset).
#define HYDROLUX_PARAM_MEMBER(path)                         \
  [](const auto& o, int) { return double(o.path); },        \
      [](auto& o, int, double v) { o.path = decltype(o.path)(v); }
#define HYDROLUX_PARAM_OPTIONAL(path)                                                                       \
  [](const auto& o, int) { return o.path ? double(*o.path) : std::numeric_limits<double>::quiet_NaN(); }, \
      [](auto& o, int, double v) { o.path = v; }
#define HYDROLUX_PARAM_PARTS(first, second)                                             \
  [](const auto& o, int i) { return i == 0 ? double(o.first) : double(o.second); },     \
      [](auto& o, int i, double v) {                                                   \
        if (i == 0) o.first = decltype(o.first)(v);                                    \
        else o.second = decltype(o.second)(v);                                         \
      }
#define HYDROLUX_PARAM_INDEXED(path)                                     \
  [](const auto& o, int i) { return double(o.path[i]); },               \
      [](auto& o, int i, double v) { o.path[i] = decltype(+o.path[i])(v); }
#define HYDROLUX_PARAM_OPTIONAL_PARTS(path)                                                             \
  [](const auto& o, int i) {                                                                           \
    return o.path ? double((*o.path)[std::size_t(i)]) : std::numeric_limits<double>::quiet_NaN();      \
  },                                                                                                   \
      [](auto& o, int i, double v) {                                                                   \
        if (!o.path) o.path.emplace();                                                                 \
        (*o.path)[std::size_t(i)] = std::remove_reference_t<decltype((*o.path)[0])>(v);                \
      }

namespace detail {
// A path member's text: a std::string's own, a std::optional<std::string>'s or empty while unset.
template <class T>
std::string path_text(const T& member) {
  if constexpr (requires { member.has_value(); }) return member.value_or(std::string());
  else return member;
}
}  // namespace detail
#define HYDROLUX_PARAM_PATH(path)                                                          \
  nullptr, nullptr, [](const auto& o) { return ::hydrolux::detail::path_text(o.path); }, \
      [](auto& o, std::string v) { o.path = std::move(v); }

// A parameter with its default, for the doors that list them (docs, Python signatures, argparse).
struct ParamInfo {
  const Param* param;
  double default_value;  // part 0; NaN: none (derived, or replaced by another parameter)
  ParamValue default_parts = {};  // every part (a size's width and height)
  std::string default_path = {};  // a path's default; empty for none
  // The default as the CLI's help shows it: "25", "0.008", "on", "1280x720", a path; empty for none.
  std::string default_text() const;
};

// A job's declared parameters.
struct JobSpec {
  std::string_view name;     // "rain"
  std::string_view command;  // "hydrolux rain"
  std::string_view summary;  // one line
  std::vector<ParamInfo> params;
  // The Python calls that take the parameters by name as keywords; empty where none does (then only
  // the CLI and the docs read the table).
  std::string_view python = {};
  // What the job does, in a paragraph: the CLI command's help (`hydrolux <command> --help`) and the
  // command reference read it.
  std::string_view description = {};
};

template <class Request>
std::vector<ParamInfo> describe_fields(std::span<const Field<Request>> fields) {
  const Request defaults{};
  std::vector<ParamInfo> out;
  out.reserve(fields.size());
  for (const auto& f : fields) out.push_back({&f.param, f.get(defaults), f.value(defaults), f.text(defaults)});
  return out;
}

// Every field of `fields` in its declared range (Param::check's message), in the table's order; a
// field without a value (NaN: an optional not given, a size's first part too) is skipped. The one validation over a table:
// the checks that follow from other values (far beyond near) stay with the job.
template <class Request>
void check_fields(std::span<const Field<Request>> fields, const Request& request, Door door = Door::library) {
  for (const auto& f : fields) {
    if (const double v = f.get(request); std::isnan(v)) continue;  // an optional not given
    if (f.param.parts() > 1) f.param.check(f.value(request), door);
    else f.param.check(f.get(request));
  }
}

// The parameters a user gave through a door, and where the job says they have an effect: pbrt-v4's
// ParameterDictionary::ReportUnused, Mitsuba 3's error for a property no plugin queried. The door
// records what was given (give) and the job the states it is in (hold) or the parameters it used
// whatever the conditions (consume); report_unused refuses, in one format for every door and job
// ("--sampling 2: used only with ..."), a parameter given whose declared conditions (Param::only_with,
// not_with) fail. No door lists its refusals by hand.
class ParamUse {
 public:
  explicit ParamUse(Door door = Door::library) : door_(door) {}
  Door door() const { return door_; }
  // The door: the user gave `param`, written `value` (as the message shows it).
  void give(const Param& param, std::string value);
  // A declared parameter that may be named in messages ({name}) though not given, with its value as
  // the door writes it where the job has one (a choice's word: "mode=cube-map" holds for mode's).
  void declare(const Param& param, std::string value = {});
  // The job: a state holds (a word of only_with / not_with); `value` shows it as {state=}.
  void hold(std::string_view state, std::string value = {});
  // A value shown for {name=} of a text the door reads itself (--size-distribution).
  void note(std::string_view name, std::string value);
  // The job used the parameter: no condition refuses it.
  void consume(std::string_view name);
  bool given(std::string_view name) const;
  // Whether `word` holds: a parameter given, a state held, or "name=value" where the parameter given or
  // declared has that value (a choice's word: "mode=cube-map").
  bool holds(std::string_view word) const;
  // Throws Error "{P} {value}: {why}" (P spelled by the door) for the first parameter given, in the
  // order declared, whose conditions fail.
  void report_unused() const;
  // A parameter's name or a state as the door spells it: "--nodes", "--mode cube-map" (for
  // "mode=cube-map"); with_value: followed by its value where one is known.
  std::string spell(std::string_view word, bool with_value = false) const;

 private:
  struct Entry {
    const Param* param;
    std::string value;
    bool given = false, consumed = false;
  };
  const Entry* find(std::string_view name) const;
  Entry* find(std::string_view name);
  std::string reason(const Entry& e, bool only_with_failed, std::string_view word) const;
  Door door_;
  std::vector<Entry> params_;
  std::vector<std::pair<std::string, std::string>> states_, notes_;
};

// The field of `name` in `fields`, or nullptr.
template <class Request>
const Field<Request>* find_field(std::span<const Field<Request>> fields, std::string_view name) {
  for (const auto& f : fields)
    if (f.param.name == name) return &f;
  return nullptr;
}

}  // namespace hydrolux
