#include "params.hpp"

namespace hydrolux::cli {

CLI::Option* add_param(CLI::App& sub, const ParamInfo& info, std::function<void(double)> store) {
  const Param& p = *info.param;
  const std::string flag(p.flag), help(p.help), unit(p.unit);
  CLI::Option* opt = nullptr;
  switch (p.kind) {
    case ParamKind::real:
      opt = sub.add_option_function<double>(flag, std::move(store), help)->check(number_in(p.lo, p.hi, unit));
      break;
    case ParamKind::integer:
      opt = sub.add_option_function<long long>(
                   flag, [store = std::move(store)](long long v) { store(double(v)); }, help)
                ->transform(integer_in((long long)p.lo, (long long)p.hi, unit));
      break;
    case ParamKind::flag: {
      // The flag turns the default around: --no-unresolved for a parameter that is on by default.
      const double turned = info.default_value != 0 ? 0 : 1;
      return sub.add_flag_callback(flag, [store = std::move(store), turned] { store(turned); }, help);
    }
  }
  const std::string shown = info.default_text();
  if (!shown.empty()) opt->default_str(shown);
  return opt;
}

bool given(const CLI::App& sub, const Param& param) {
  const auto* opt = sub.get_option_no_throw(std::string(param.flag));
  return opt != nullptr && opt->count() > 0;
}

}  // namespace hydrolux::cli
