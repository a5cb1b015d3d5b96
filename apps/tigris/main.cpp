// `tigris`: the command-line front end (docs/cli.md).
// Exit codes: 0 success, 1 golden mismatch (tigris run), 2 bad input or configuration, 3 a Slurm
// submission failed, 128 + the signal when stopped (130 SIGINT, 143 SIGTERM, 129 SIGHUP).
#include <iostream>

#include <CLI/CLI.hpp>
#include <systemc>

#include <malloc.h>
#include <unistd.h>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "command.hpp"
#include "core/arg_checks.hpp"
#include "core/build_info.hpp"
#include "core/children.hpp"
#include "core/out_folder.hpp"
#include "core/slurm_array.hpp"
#include "core/visible_text.hpp"
#include "options.hpp"
#include "python_tools.hpp"

#ifdef TIGRIS_SANITIZE
// The sanitizer build runs as it is: LeakSanitizer's tracer crashes on SystemC's coroutine
// stacks ("Tracer caught signal 11"), so leak checking is off there (ASan and UBSan stay on).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif

namespace {

// Every job runs in a fresh process that fills large arrays (results, visits, schedules) once;
// on a machine whose kernel gives transparent huge pages on request (Debian's default,
// "madvise"), asking glibc's malloc for them halves the page-fault time: replaying a trace's
// two normal-estimation jobs took 14.6 s with 4.8 s in the kernel, 7.4 s with huge pages. The
// setting is a glibc tunable, read at start-up, so tigris re-executes itself once with it.
// TIGRIS_NO_HUGE_PAGES=1 (e.g. under valgrind) or a GLIBC_TUNABLES naming hugetlb keeps
// the process as started.
void ask_for_huge_pages(char** argv) {
#ifdef TIGRIS_SANITIZE
  // ASan's allocator replaces glibc's malloc, so the tunable would change nothing there; the
  // second start-up (ASan's own initialisation included) would only cost time.
  (void)argv;
#else
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (std::getenv("TIGRIS_NO_HUGE_PAGES") || (tunables && std::strstr(tunables, "glibc.malloc.hugetlb"))) return;
  // Once only: a secure-execution process (setuid, capabilities) has the tunable dropped.
  if (std::getenv("TIGRIS_REEXECUTED")) return;
  setenv("TIGRIS_REEXECUTED", "1", 1);
  const std::string value =
      tunables && *tunables ? std::string(tunables) + ":glibc.malloc.hugetlb=1" : "glibc.malloc.hugetlb=1";
  setenv("GLIBC_TUNABLES", value.c_str(), 1);
  ::execv("/proc/self/exe", argv);  // returns only when it failed: go on as started
#endif
}

// A job's per-query arrays (visits, latencies, results, the golden schedule) are a few MB each
// and grow as the job runs: from mmap, each would fault in page by page, again at every
// doubling, and go back to the kernel when freed (10,900 faults in a KITTI NN run, a sixth of
// the simulation thread on a virtual machine). From a heap that grows 64 MB at a time, in
// huge pages (above), and keeps what it freed: 2,400 faults, the simulation 11% faster
// (docs/performance.md "Huge pages").
void keep_heap_memory() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest: bigger blocks are mapped anyway
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

}  // namespace

// SystemC's own main() would print its banner before we could silence it, so `tigris` has a
// plain main(); the library still needs an sc_main symbol to link.
extern "C" int sc_main(int, char**) { return 2; }

int main(int argc, char** argv) {
  ask_for_huge_pages(argv);
  keep_heap_memory();
  if (const int code = tigris::run_python_tool(argc, argv); code >= 0) return code;
  tigris::install_stop_handlers("tigris");
  tigris::record_command_line(argc, argv);
  setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1);
  // The host driver ends every run with sc_stop(); that is not news for the user.
  sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  CLI::App app{"tigris: the Tigris KD-tree search accelerator (MICRO 2019) and its golden model"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tigris 0.1.0 (commit ") + tigris::build_commit() + ")");

  // Every command registers itself (command.hpp); each keeps its own options and default folder
  // (a folder holds one command's output).
  std::vector<std::pair<CLI::App*, std::unique_ptr<tigris::Command>>> subcommands;
  for (const tigris::CommandInfo* info : tigris::commands()) {
    CLI::App* sub = app.add_subcommand(info->name, info->summary);
    std::unique_ptr<tigris::Command> command = info->make ? info->make() : nullptr;
    if (command) command->add_flags(*sub);
    subcommands.emplace_back(sub, std::move(command));
  }

  // `tigris COMMAND --list-flags`: before parsing, so a command's required flags need not be given.
  for (auto& [sub, command] : subcommands)
    if (command)
      sub->add_flag("--list-flags",
                    "Print this command's flags as JSON (flag, type, default, meaning) for tools, and exit");
  if (argc == 3 && std::string(argv[2]) == "--list-flags")
    for (auto& [sub, command] : subcommands)
      if (command && sub->get_name() == argv[1]) {
        std::cout << tigris::flags_json(*sub).dump(2) << '\n';
        return 0;
      }

  try {
    tigris::reject_empty_arguments(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "tigris: error: " << tigris::visible_message(e.what()) << '\n';
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::string hints = tigris::parse_suggestions(app, argc, argv, e.what());
    if (hints.rfind("'", 0) == 0)  // an unknown command: CLI11 would only say one is required
      std::cerr << "tigris: error: " << tigris::visible_message(hints);
    else if (!hints.empty())  // the project's words first, CLI11's after them
      std::cerr << "tigris: error: " << tigris::visible_message(hints) << "(" << tigris::visible_message(e.what())
                << ")\n";
    else
      std::cerr << "tigris: error: " << tigris::visible_message(e.what()) << '\n';
    std::cerr << "Run with --help for more information (tigris COMMAND --help for a command's flags).\n";
    return 2;
  }
  const tigris::CommandLine line{tigris::command_line(argc, argv), {argv, argv + argc}};
  try {
    for (auto& [sub, command] : subcommands)
      if (*sub && command) return command->run(*sub, line);
  } catch (const tigris::Interrupted& e) {
    std::cerr << "tigris: " << e.what() << ": child processes stopped\n";
    return 128 + e.signal;
  } catch (const tigris::SlurmError& e) {
    std::cerr << "tigris: error: " << tigris::visible_message(e.what()) << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "tigris: error: " << tigris::visible_message(e.what()) << '\n';
    return 2;
  }
  return 2;
}
