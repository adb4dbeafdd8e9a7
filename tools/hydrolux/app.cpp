// The hydrolux CLI as a function: the command tree, parsing, dispatch, exit codes and signals.
// Exit codes: 0 success; 2 bad input (one line on stderr naming the flag, the value and the valid
// range; nothing written); 1 the system failed midway (a full disk: one line naming the path and the
// OS error; no output replaced) or an internal error; 130 / 143 / 129 cancelled by SIGINT / SIGTERM /
// SIGHUP (unfinished outputs removed, existing files unchanged).
#include <fmt/format.h>
#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::cli {

namespace {

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
  }
  return "a signal";
}

// The signal that cancelled the run (0: none yet), set by the signal thread before it cancels the
// outputs, so that a failure the cancellation causes in the main thread (a write refused as
// cancelled) is never reported as a failure of its own: the main thread checks it on every way
// out and leaves the exit to the signal thread.
std::atomic<int> g_cancelled_by{0};
// A copy of standard error taken at start-up: while a codec runs, descriptor 2 points into a
// capture buffer (io/image_io.cpp), and the cancellation message must still reach the terminal.
int g_stderr_copy = STDERR_FILENO;

// Called on every way out of run_cli: after a cancellation the signal thread owns the exit.
void wait_if_cancelled() {
  if (g_cancelled_by.load() == 0) return;
  // The signal thread prints its line and calls _Exit(128 + signal). Should it be stuck (its
  // write blocked on a full pipe), a second Ctrl-C or SIGTERM ends the process by the default
  // action: unblocked here, in the one thread that waits.
  sigset_t set;
  sigemptyset(&set);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  for (;;) ::pause();
}

// Ctrl-C, SIGTERM and SIGHUP are blocked in every thread (the worker threads TBB and OpenImageIO
// start later inherit the mask) and taken by one thread waiting in sigwait, which runs ordinary
// code: it removes every pending temporary output through the library's registry and exits with
// 128 + the signal. A signal the process was started with ignored (nohup, a background job)
// stays ignored. SIGXFSZ is ignored so that a file-size limit is a write error (EFBIG) we report,
// not a crash that leaves a temporary file. If no thread can be started, the default actions stay
// (a signal then kills the process; temporary files may be left, never a half-written output).
void install_signal_handling() {
  std::signal(SIGXFSZ, SIG_IGN);
  if (const int copy = ::fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3); copy >= 0) g_stderr_copy = copy;
  sigset_t set;
  sigemptyset(&set);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaddset(&set, sig);
  }
  sigset_t before;
  ::pthread_sigmask(SIG_BLOCK, &set, &before);
  try {
    std::thread([set] {
      int sig = 0;
      while (::sigwait(&set, &sig) != 0) {
      }
      g_cancelled_by.store(sig);
      const std::size_t removed = io::cancel_pending_outputs();
      const std::string line =
          fmt::format("{}{}: cancelled by {}; {}\n", ::isatty(g_stderr_copy) ? "\n" : "", program_name(),
                      signal_name(sig), removed ? "unfinished outputs removed, existing files unchanged"
                                                : "no unfinished output to remove");
      for (std::size_t done = 0; done < line.size();) {
        const ssize_t n = ::write(g_stderr_copy, line.data() + done, line.size() - done);
        if (n <= 0 && errno != EINTR) break;
        if (n > 0) done += std::size_t(n);
      }
      std::_Exit(128 + sig);
    }).detach();
  } catch (const std::system_error&) {
    ::pthread_sigmask(SIG_SETMASK, &before, nullptr);
  }
}

// "hydrolux drop render" for the subcommands named at the start of argv (for parse errors, which
// arrive before CLI11 says which subcommand was parsed).
std::string program_from_argv(const CLI::App& app, int argc, const char* const* argv) {
  std::string prog = "hydrolux";
  const CLI::App* current = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.empty() || arg.front() == '-') continue;
    const CLI::App* next = nullptr;
    for (const auto* sub : current->get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == arg) next = sub;
    if (!next) break;
    prog += " " + next->get_name();
    current = next;
  }
  return prog;
}

}  // namespace

namespace {

// Each top-level command: the name it registers and how, in the order of `hydrolux --help`.
struct TopCommand {
  std::string_view name;
  void (*add)(CLI::App& app, std::vector<Command>& out);
};
constexpr TopCommand kTopCommands[] = {
    {"fresnel", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_fresnel(app)); }},
    {"ior", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_ior(app)); }},
    {"mie", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_mie(app)); }},
    {"phase", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_phase(app)); }},
    {"drop",
     [](CLI::App& app, std::vector<Command>& out) {
       for (auto& c : add_drop(app)) out.push_back(std::move(c));
     }},
    {"rainphys", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_rainphys(app)); }},
    {"lee", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_lee(app)); }},
    {"sky", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_sky(app)); }},
    {"export", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_export(app)); }},
    {"rain", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_rain(app)); }},
    {"fog", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_fog(app)); }},
    {"lens-drops", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_lens_drops(app)); }},
    {"detect-rain", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_detect_rain(app)); }},
    {"remove-rain", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_remove_rain(app)); }},
    {"rain-eval", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_rain_eval(app)); }},
    {"medium", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_medium(app)); }},
    {"gallery", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_gallery(app)); }},
    {"spec", [](CLI::App& app, std::vector<Command>& out) { out.push_back(add_spec(app)); }},
};

}  // namespace

std::string Command::flag(std::string_view quantity) const {
  const auto it = flags_for_quantity.find(std::string(quantity));
  return it == flags_for_quantity.end() ? Param::flag_of(quantity) : it->second;
}

std::vector<Command> add_all_commands(CLI::App& app) {
  std::vector<Command> commands;
  for (const auto& top : kTopCommands) top.add(app, commands);
  return commands;
}

namespace {

// The top-level app, before any command is registered.
std::unique_ptr<CLI::App> new_app() {
  auto app = std::make_unique<CLI::App>(
      "hydrolux: physically based light transport through water drops.\n"
      "Units: angles in degrees, wavelengths in vacuum nanometres, temperatures in Celsius.\n"
      "Exit codes: 0 done; 2 bad input (nothing written); 1 a system failure such as a full disk "
      "(no output replaced); 130/143 cancelled by Ctrl-C/SIGTERM (unfinished outputs removed).",
      "hydrolux");
  app->set_version_flag("--version", fmt::format("hydrolux {}", kVersion));
  app->require_subcommand(1);
  app->allow_extras(false);
  app->get_formatter()->column_width(34);
  return app;
}

// Runs the command that parsed, turning its failures into messages and exit codes.
int run_command(const CLI::App& app, const std::vector<Command>& commands) {
  for (const auto& cmd : commands) {
    if (!cmd.app->parsed()) continue;
    std::string prog = cmd.app->get_name();
    for (auto* p = cmd.app->get_parent(); p && p != &app; p = p->get_parent()) prog = p->get_name() + " " + prog;
    prog = "hydrolux " + prog;
    set_program_name(prog);
    try {
      const int code = cmd.run();
      wait_if_cancelled();
      std::cout.flush();
      errno = 0;
      if (std::fflush(stdout) != 0 || std::ferror(stdout) || std::cout.fail()) {
        fmt::print(stderr, "{}: cannot write to standard output{}\n", prog,
                   errno ? fmt::format(": {}", std::strerror(errno)) : std::string());
        return kExitFailure;
      }
      return code;
    } catch (const DomainError& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      if (cmd.flags_for_quantity.contains(e.quantity())) {
        // Said with the flags: the quantity refused and those its range follows from ("beyond --near-m").
        fmt::print(stderr, "{}: {}\n", prog, printable(e.said([&](std::string_view q) { return cmd.flag(q); })));
      } else
        fmt::print(stderr, "{}: {}\n", prog, printable(e.what()));
      return kExitUsage;
    } catch (const ParamError& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      fmt::print(stderr, "{}: {}\n", prog, printable(e.said([&](std::string_view q) { return cmd.flag(q); })));
      return kExitUsage;
    } catch (const IoFailure& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      fmt::print(stderr, "{}: {}\n", prog, printable(e.what()));
      return kExitFailure;
    } catch (const Error& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      fmt::print(stderr, "{}: {}\n", prog, printable(e.what()));
      return kExitUsage;
    } catch (const std::bad_alloc&) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      fmt::print(stderr, "{}: out of memory\n", prog);
      return kExitFailure;
    } catch (const std::system_error& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      // A table printed to a full disk or a closed pipe: fmt::print's write to stdout failed midway.
      if (std::ferror(stdout)) {
        fmt::print(stderr, "{}: cannot write to standard output: {}\n", prog, printable(e.code().message()));
        return kExitFailure;
      }
      fmt::print(stderr, "{}: internal error: {}\n", prog, printable(e.what()));
      return kExitFailure;
    } catch (const std::exception& e) {
      wait_if_cancelled();  // a failure the cancellation caused is not reported
      fmt::print(stderr, "{}: internal error: {}\n", prog, printable(e.what()));
      return kExitFailure;
    }
  }
  return kExitFailure;  // unreachable: require_subcommand(1)
}

// The one line a command line that does not parse gets (exit 2): CLI11's message, but for a value it
// cannot convert ("Could not convert: --json = maybe"), which says what the option takes instead.
int report_parse_error(const CLI::App& app, const std::vector<Command>& commands,
                       const std::vector<const char*>& args, const CLI::ParseError& e) {
  const std::string prog = program_from_argv(app, int(args.size()), args.data());
  std::string msg = e.what();
  if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr) {
    const auto colon = msg.find(": "), eq = msg.find(" = ");
    if (colon != std::string::npos && eq != std::string::npos && eq > colon) {
      const std::string name = msg.substr(colon + 2, eq - colon - 2), value = msg.substr(eq + 3);
      msg = fmt::format("{} '{}': not a value this option takes", name, value);
      for (const auto& cmd : commands)
        if (prog == "hydrolux " + cmd.app->get_name() || prog.ends_with(" " + cmd.app->get_name()))
          if (const auto* opt = cmd.app->get_option_no_throw(name); opt && opt->get_expected_max() == 0)
            msg = fmt::format("{} '{}': {} is a switch and takes no value; give {} alone", name, value, name, name);
    }
  }
  if (msg.empty()) msg = "invalid arguments";
  for (char& c : msg)
    if (c == '\n') c = ' ';
  fmt::print(stderr, "{}: {} (see {} --help)\n", prog, printable(msg), prog);
  return kExitUsage;
}

// A run that parses with part of the command tree (issue 24: registering all the commands, with
// their ~300 options and the defaults some compute, was most of a short command's start-up).
// `hydrolux NAME ...` registers only NAME: once a top-level command is parsed, CLI11 matches no
// other top-level name (require_subcommand(1)), so the other commands cannot change how the rest of
// the line parses, nor the message of a line that does not parse (reported here, as the whole tree
// would: most of the robustness sweep's thousand bad lines start no faster than a good one otherwise).
// `hydrolux --version` alone registers none. Anything else, and a line asking for help, returns
// nullopt: the whole tree then parses it again, so that every help text is the whole tree's.
std::optional<int> run_with_part_of_tree(const std::vector<const char*>& args) {
  if (args.size() < 2) return std::nullopt;
  const std::string_view first = args[1];
  const TopCommand* only = nullptr;
  for (const auto& top : kTopCommands)
    if (top.name == first) only = &top;
  const bool version_only = args.size() == 2 && first == "--version";
  if (!only && !version_only) return std::nullopt;

  const auto app = new_app();
  std::vector<Command> commands;
  if (only) {
    only->add(*app, commands);
    const auto subs = app->get_subcommands([](const CLI::App*) { return true; });
    if (subs.size() != 1 || subs.front()->get_name() != first) return std::nullopt;  // not as registered
  }
  set_program_name(program_from_argv(*app, int(args.size()), args.data()));
  try {
    app->parse(int(args.size()), args.data());
  } catch (const CLI::CallForVersion& e) {
    if (version_only) return app->exit(e);
    return std::nullopt;
  } catch (const CLI::Success&) {  // --help, --help-all
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    return report_parse_error(*app, commands, args, e);
  }
  return run_command(*app, commands);
}

int run_parsed(int argc, char** argv) {
  // A provisional name for messages (the leading words of argv, "hydrolux drop render"), set before
  // the signal handling starts: a Ctrl-C may come before the command tree is even built.
  std::string provisional = "hydrolux";
  for (int i = 1; i < argc && i <= 2 && argv[i][0] != '-' && argv[i][0] != '\0'; ++i) provisional += std::string(" ") + argv[i];
  set_program_name(provisional);
  set_command_line(argc, argv);
  install_signal_handling();

  // "--flag=" (an empty value after '=') becomes "--flag" "": CLI11 would otherwise take the next
  // argument, another flag, as the value and report a confusing error about something else.
  std::vector<std::string> split_args;
  std::vector<const char*> args{argv[0]};
  split_args.reserve(2 * std::size_t(argc));
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a.size() > 3 && a.substr(0, 2) == "--" && a.find('=') == a.size() - 1) {
      split_args.emplace_back(a.substr(0, a.size() - 1));
      split_args.emplace_back();
    } else {
      split_args.emplace_back(a);
    }
  }
  for (const auto& a : split_args) args.push_back(a.c_str());

  if (const std::optional<int> code = run_with_part_of_tree(args)) return *code;

  const auto app_owner = new_app();
  CLI::App& app = *app_owner;
  const std::vector<Command> commands = add_all_commands(app);
  // Named from argv at once: a signal may arrive while the arguments are still being parsed.
  set_program_name(program_from_argv(app, int(args.size()), args.data()));
  try {
    app.parse(int(args.size()), args.data());
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return report_parse_error(app, commands, args, e);
  }
  return run_command(app, commands);
}

}  // namespace

int run_cli(int argc, char** argv) {
  int code = kExitFailure;
  try {
    code = run_parsed(argc, argv);
  } catch (...) {
    wait_if_cancelled();
    throw;
  }
  wait_if_cancelled();
  return code;
}

}  // namespace hydrolux::cli
