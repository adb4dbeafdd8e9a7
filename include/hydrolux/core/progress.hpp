#pragma once
// Progress of a long job: the library reports, the caller (the CLI) shows it. `fraction` rises
// from 0 to 1; `label` names the step in progress.
#include <functional>
#include <string_view>

namespace hydrolux {

using ProgressFn = std::function<void(double fraction, std::string_view label)>;

}  // namespace hydrolux
