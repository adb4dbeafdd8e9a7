#include "hydrolux/core/params.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"

namespace hydrolux {

namespace {
std::string with_unit(std::string text, std::string_view unit) {
  if (!unit.empty()) text += fmt::format(" {}", unit);
  return text;
}

// "a, b or c".
template <class Words>
std::string alternatives(const Words& words) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i)
    out += fmt::format("{}{}", i == 0 ? "" : i + 1 == words.size() ? " or " : ", ", words[i]);
  return out;
}
}  // namespace

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> out;
  while (!text.empty()) {
    const auto bar = text.find('|');
    out.push_back(text.substr(0, bar));
    if (bar == std::string_view::npos) break;
    text.remove_prefix(bar + 1);
  }
  return out;
}

std::string_view kind_name(ParamKind kind) {
  switch (kind) {
    case ParamKind::real: return "real";
    case ParamKind::integer: return "integer";
    case ParamKind::flag: return "flag";
    case ParamKind::choice: return "choice";
    case ParamKind::size: return "size";
    case ParamKind::span: return "span";
    case ParamKind::colour: return "colour";
    case ParamKind::path: return "path";
  }
  return "real";
}

std::string Param::range_text() const {
  if (kind == ParamKind::flag) return {};
  if (kind == ParamKind::path) return std::string(words);
  if (kind == ParamKind::choice) return alternatives(word_list());
  if (kind == ParamKind::integer || kind == ParamKind::size)
    return with_unit(fmt::format("[{}, {}]", (long long)lo, (long long)hi), unit);
  return with_unit(fmt::format("[{:g}, {:g}]", lo, hi), unit);
}

int Param::parts() const {
  switch (kind) {
    case ParamKind::size:
    case ParamKind::span:
      return 2;
    case ParamKind::colour:
      return 3;
    default:
      return 1;
  }
}

std::vector<std::string_view> Param::word_list() const { return split_words(words); }

int Param::choice_index(std::string_view word) const {
  const auto list = word_list();
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i] == word) return int(i);
  return -1;
}

namespace {
// The separator of a kind's parts in the CLI's text.
char separator_of(ParamKind kind) { return kind == ParamKind::size ? 'x' : kind == ParamKind::span ? ':' : ','; }

// The parts as `door` writes them: "1280x720" (the CLI's), "(1280, 720)" (Python's).
std::string joined(const std::vector<std::string>& parts, ParamKind kind, Door door) {
  std::string out = door == Door::python ? "(" : "";
  for (std::size_t i = 0; i < parts.size(); ++i)
    out += (i == 0 ? "" : door == Door::python ? ", " : std::string(1, separator_of(kind))) + parts[i];
  return door == Door::python ? out + ")" : out;
}
}  // namespace

std::string Param::form(Door door) const {
  if (parts() == 1) return range_text();
  const auto list = word_list();
  const std::vector<std::string> names(list.begin(), list.end());
  std::string out = fmt::format("{}, each {} {}", joined(names, kind, door),
                                kind == ParamKind::size ? "a whole number in" : "in", range_text());
  if (kind == ParamKind::span && list.size() == 2) out += fmt::format(", {} <= {}", list[0], list[1]);
  return out;
}

std::string Param::value_text(const ParamValue& value, Door door) const {
  const double v = value[0];
  switch (kind) {
    case ParamKind::flag:
      return v != 0 ? "on" : "off";
    case ParamKind::integer:
      return fmt::format("{}", (long long)v);
    case ParamKind::choice: {
      const auto list = word_list();
      if (v >= 0 && v < double(list.size()) && v == std::floor(v)) return std::string(list[std::size_t(v)]);
      return fmt::format("{:g}", v);
    }
    case ParamKind::real:
      return fmt::format("{:g}", v);
    case ParamKind::path:  // no number: its text is the request's (Field::text)
      return {};
    default:
      break;
  }
  std::vector<std::string> parts_text;
  for (int i = 0; i < parts(); ++i) parts_text.push_back(fmt::format("{:g}", value[std::size_t(i)]));
  return joined(parts_text, kind, door);
}

ParamValue Param::parse_text(std::string_view text, Door door) const {
  const auto refuse = [&] {
    return Error(fmt::format("{} '{}': expected {}", spelled(*this, door), printable(text), form(door)));
  };
  ParamValue v{};
  if (kind == ParamKind::choice) {
    const int i = choice_index(text);
    if (i < 0) throw UnknownNameError(fmt::format("{} '{}': expected {}", spelled(*this, door), printable(text), form(door)));
    v[0] = i;
    return v;
  }
  if (parts() == 1) throw std::logic_error("Param::parse_text: " + std::string(name) + " is a number, a switch or a path");
  // The parts, split at the kind's separator: exactly parts() numbers.
  int n = 0;
  std::string_view rest = text;
  while (true) {
    const auto at = rest.find(separator_of(kind));
    const auto x = parse::number(rest.substr(0, at));
    if (!x || n == parts()) throw refuse();
    v[std::size_t(n++)] = *x;
    if (at == std::string_view::npos) break;
    rest.remove_prefix(at + 1);
  }
  if (n != parts()) throw refuse();
  try {
    check(v, door);
  } catch (const Error&) {
    throw refuse();
  }
  return v;
}

void Param::check(double value) const {
  const bool whole = (kind != ParamKind::integer && kind != ParamKind::choice) || value == std::floor(value);
  if (value >= lo && value <= hi && whole) return;
  if (kind == ParamKind::choice)
    throw UnknownNameError(fmt::format("{} = {:g}: not the index of one of {}", name, value, range_text()));
  const std::string what = fmt::format("{} = {:g} is {} {}", name, value,
                                       whole ? "outside" : "not a whole number in", range_text());
  throw DomainError::with_message(what, std::string(name), value, lo, hi, std::string(unit));
}

void Param::check(const ParamValue& value, Door door) const {
  if (parts() == 1) return check(value[0]);
  // An Error in the door's words (not a DomainError, whose quantity a door would reword).
  const auto refuse = [&] {
    return Error(fmt::format("{} {}: expected {}", spelled(*this, door), value_text(value, door), form(door)));
  };
  for (int i = 0; i < parts(); ++i) {
    const double x = value[std::size_t(i)];
    if (!(x >= lo && x <= hi) || (kind == ParamKind::size && x != std::floor(x))) throw refuse();
  }
  if (kind == ParamKind::span && value[0] > value[1]) throw refuse();
}

std::string Param::flag_of(std::string_view name) {
  std::string flag = "--";
  for (const char c : name) flag += c == '_' ? '-' : c;
  return flag;
}

std::string Param::deprecation_warning(std::string_view old, std::string_view now) const {
  return fmt::format("{} is deprecated and will be removed in the next release: give {} (the same {})", old, now,
                     unit.empty() ? std::string("value") : fmt::format("value in {}", unit));
}

std::string_view spelled(const Param& param, Door door) { return door == Door::cli ? param.flag : param.name; }

// ---- ParamUse ----------------------------------------------------------------------------------

const ParamUse::Entry* ParamUse::find(std::string_view name) const {
  for (const auto& e : params_)
    if (e.param->name == name) return &e;
  return nullptr;
}
ParamUse::Entry* ParamUse::find(std::string_view name) {
  return const_cast<Entry*>(static_cast<const ParamUse*>(this)->find(name));
}

void ParamUse::declare(const Param& param, std::string value) {
  if (Entry* e = find(param.name)) e->value = std::move(value);
  else params_.push_back({&param, std::move(value)});
}

void ParamUse::give(const Param& param, std::string value) {
  Entry* e = find(param.name);
  if (!e) e = &params_.emplace_back(Entry{&param, {}});
  e->value = std::move(value);
  e->given = true;
}

void ParamUse::hold(std::string_view state, std::string value) { states_.emplace_back(state, std::move(value)); }
void ParamUse::note(std::string_view name, std::string value) { notes_.emplace_back(name, std::move(value)); }

void ParamUse::consume(std::string_view name) {
  if (Entry* e = find(name)) e->consumed = true;
}

bool ParamUse::given(std::string_view name) const {
  const Entry* e = find(name);
  return e && e->given;
}

bool ParamUse::holds(std::string_view word) const {
  if (given(word)) return true;
  if (const auto eq = word.find('='); eq != std::string_view::npos)
    if (const Entry* e = find(word.substr(0, eq)); e && e->value == word.substr(eq + 1)) return true;
  for (const auto& [state, value] : states_)
    if (state == word) return true;
  return false;
}

std::string ParamUse::spell(std::string_view word, bool with_value) const {
  // "mode=cube-map": the door's option with that value.
  if (const auto eq = word.find('='); eq != std::string_view::npos) {
    const std::string_view name = word.substr(0, eq), value = word.substr(eq + 1);
    const Entry* e = find(name);
    const std::string n = e ? std::string(spelled(*e->param, door_))
                            : door_ == Door::cli ? Param::flag_of(name) : std::string(name);
    return fmt::format("{} {}", n, value);
  }
  std::string value;
  std::string out;
  if (const Entry* e = find(word)) {
    out = spelled(*e->param, door_);
    value = e->value;
  } else {
    out = door_ == Door::cli ? Param::flag_of(word) : std::string(word);
  }
  for (const auto& [name, v] : notes_)
    if (name == word) value = v;
  for (const auto& [name, v] : states_)
    if (name == word && !v.empty()) value = v;
  if (with_value && !value.empty()) out += " " + value;
  return out;
}

std::string ParamUse::reason(const Entry& e, bool only_with_failed, std::string_view word) const {
  const Param& p = *e.param;
  if (p.why.empty()) {
    if (!only_with_failed) return fmt::format("not with {}", spell(word, true));
    std::vector<std::string> spelled_words;
    for (const auto w : split_words(p.only_with)) spelled_words.push_back(spell(w));
    const std::string alts = alternatives(spelled_words);
    return fmt::format("used only with {} (omit {})", alts, spell(p.name));
  }
  // {name} spelled, {name=} with its value.
  return spell_quantities(p.why, [this](std::string_view name) {
    const bool with_value = name.ends_with('=');
    return spell(with_value ? name.substr(0, name.size() - 1) : name, with_value);
  });
}

void ParamUse::report_unused() const {
  for (const auto& e : params_) {
    if (!e.given || e.consumed) continue;
    const Param& p = *e.param;
    const std::string head = e.value.empty() ? std::string(spelled(p, door_)) : spell(p.name, true);
    if (!p.only_with.empty()) {
      bool any = false;
      for (const auto w : split_words(p.only_with)) any = any || holds(w);
      if (!any) throw Error(fmt::format("{}: {}", head, reason(e, true, {})));
    }
    for (const auto w : split_words(p.not_with))
      if (holds(w)) throw Error(fmt::format("{}: {}", head, reason(e, false, w)));
  }
}

std::string ParamInfo::default_text() const {
  if (param->kind == ParamKind::path) return default_path;
  if (std::isnan(default_value)) return {};
  return param->parts() > 1 ? param->value_text(default_parts) : param->value_text(default_value);
}

}  // namespace hydrolux
