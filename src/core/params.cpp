#include "hydrolux/core/params.hpp"

#include <fmt/format.h>

#include "hydrolux/core/error.hpp"

namespace hydrolux {

namespace {
std::string with_unit(std::string text, std::string_view unit) {
  if (!unit.empty()) text += fmt::format(" {}", unit);
  return text;
}
}  // namespace

std::string Param::range_text() const {
  if (kind == ParamKind::flag) return {};
  if (kind == ParamKind::integer) return with_unit(fmt::format("[{}, {}]", (long long)lo, (long long)hi), unit);
  return with_unit(fmt::format("[{:g}, {:g}]", lo, hi), unit);
}

void Param::check(double value) const {
  const bool whole = kind != ParamKind::integer || value == std::floor(value);
  if (value >= lo && value <= hi && whole) return;
  const std::string what = fmt::format("{} = {:g} is {} {}", name, value,
                                       whole ? "outside" : "not a whole number in", range_text());
  throw DomainError::with_message(what, std::string(name), value, lo, hi);
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

namespace {
// The words of "a|b|c".
std::vector<std::string_view> words_of(std::string_view text) {
  std::vector<std::string_view> out;
  while (!text.empty()) {
    const auto bar = text.find('|');
    out.push_back(text.substr(0, bar));
    if (bar == std::string_view::npos) break;
    text.remove_prefix(bar + 1);
  }
  return out;
}
}  // namespace

const ParamUse::Entry* ParamUse::find(std::string_view name) const {
  for (const auto& e : params_)
    if (e.param->name == name) return &e;
  return nullptr;
}
ParamUse::Entry* ParamUse::find(std::string_view name) {
  return const_cast<Entry*>(static_cast<const ParamUse*>(this)->find(name));
}

void ParamUse::declare(const Param& param) {
  if (!find(param.name)) params_.push_back({&param, {}});
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
    std::string alts;
    const auto words = words_of(p.only_with);
    for (std::size_t i = 0; i < words.size(); ++i)
      alts += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + spell(words[i]);
    return fmt::format("used only with {} (omit {})", alts, spell(p.name));
  }
  // {name} spelled, {name=} with its value.
  std::string out;
  std::string_view rest = p.why;
  while (!rest.empty()) {
    const auto open = rest.find('{');
    const auto close = open == std::string_view::npos ? open : rest.find('}', open);
    if (close == std::string_view::npos) {
      out += rest;
      break;
    }
    out += rest.substr(0, open);
    std::string_view name = rest.substr(open + 1, close - open - 1);
    const bool with_value = name.ends_with('=');
    if (with_value) name.remove_suffix(1);
    out += spell(name, with_value);
    rest.remove_prefix(close + 1);
  }
  return out;
}

void ParamUse::report_unused() const {
  for (const auto& e : params_) {
    if (!e.given || e.consumed) continue;
    const Param& p = *e.param;
    const std::string head = e.value.empty() ? std::string(spelled(p, door_)) : spell(p.name, true);
    if (!p.only_with.empty()) {
      bool any = false;
      for (const auto w : words_of(p.only_with)) any = any || holds(w);
      if (!any) throw Error(fmt::format("{}: {}", head, reason(e, true, {})));
    }
    for (const auto w : words_of(p.not_with))
      if (holds(w)) throw Error(fmt::format("{}: {}", head, reason(e, false, w)));
  }
}

std::string ParamInfo::default_text() const {
  if (std::isnan(default_value)) return {};
  if (param->kind == ParamKind::flag) return default_value != 0 ? "on" : "off";
  if (param->kind == ParamKind::integer) return fmt::format("{}", (long long)default_value);
  return fmt::format("{:g}", default_value);
}

}  // namespace hydrolux
