// `tigris`: the command-line front end (docs/cli.md).
// Exit codes: 0 success, 1 golden mismatch (tigris run), 2 bad input or configuration, 3 a Slurm
// submission failed, 128 + the signal when stopped (130 SIGINT, 143 SIGTERM, 129 SIGHUP).
#include <iostream>

#include <CLI/CLI.hpp>
#include <systemc>

#include <cstdlib>
#include <cstring>
#include <unistd.h>
#include <string>

#include "build_info.hpp"
#include "arg_checks.hpp"
#include "children.hpp"
#include "out_folder.hpp"
#include "slurm_array.hpp"
#include "python_tools.hpp"
#include "ref_command.hpp"
#include "odometry_command.hpp"
#include "synth_command.hpp"
#include "register_command.hpp"
#include "run_command.hpp"

#ifdef TIGRIS_SANITIZE
// The sanitizer build runs as it is: LeakSanitizer's tracer crashes on SystemC's coroutine
// stacks ("Tracer caught signal 11"), so leak checking is off there (ASan and UBSan stay on).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif


namespace {

// An error message as the terminal should show it: a path or file line the user gave may hold
// control characters (escape sequences would act on the terminal) or be a megabyte long, so
// control bytes are shown as \xNN and each line is cut at 400 bytes, saying how much is left.
std::string printable(const std::string& message) {
  constexpr std::size_t kLine = 400;
  std::string out;
  std::size_t line = 0;
  for (std::size_t i = 0; i < message.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(message[i]);
    if (c == '\n') {
      out += '\n';
      line = 0;
      continue;
    }
    if (line == kLine) {
      const std::size_t end = message.find('\n', i);
      const std::size_t rest = (end == std::string::npos ? message.size() : end) - i;
      out += "... (" + std::to_string(rest) + " more bytes)";
      if (end == std::string::npos) break;
      i = end - 1;
      continue;
    }
    if (c < 0x20 || c == 0x7f) {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
    ++line;
  }
  return out;
}

// Every job runs in a fresh process that fills large arrays (results, visits, schedules) once;
// on a machine whose kernel gives transparent huge pages on request (Debian's default,
// "madvise"), asking glibc's malloc for them halves the page-fault time: replaying a trace's
// two normal-estimation jobs took 14.6 s with 4.8 s in the kernel, 7.4 s with huge pages. The
// setting is a glibc tunable, read at start-up, so tigris re-executes itself once with it.
// TIGRIS_NO_HUGE_PAGES=1 (e.g. under valgrind) or a GLIBC_TUNABLES naming hugetlb keeps
// the process as started.
void ask_for_huge_pages(char** argv) {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (std::getenv("TIGRIS_NO_HUGE_PAGES") || (tunables && std::strstr(tunables, "glibc.malloc.hugetlb"))) return;
  // Once only: a secure-execution process (setuid, capabilities) has the tunable dropped.
  if (std::getenv("TIGRIS_REEXECUTED")) return;
  setenv("TIGRIS_REEXECUTED", "1", 1);
  const std::string value =
      tunables && *tunables ? std::string(tunables) + ":glibc.malloc.hugetlb=1" : "glibc.malloc.hugetlb=1";
  setenv("GLIBC_TUNABLES", value.c_str(), 1);
  ::execv("/proc/self/exe", argv);  // returns only when it failed: go on as started
}

}  // namespace

// SystemC's own main() would print its banner before we could silence it, so `tigris` has a
// plain main(); the library still needs an sc_main symbol to link.
extern "C" int sc_main(int, char**) { return 2; }

int main(int argc, char** argv) {
  ask_for_huge_pages(argv);
  if (const int code = tigris::run_python_tool(argc, argv); code >= 0) return code;
  tigris::install_stop_handlers("tigris");
  tigris::record_command_line(argc, argv);
  setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1);
  // The host driver ends every run with sc_stop(); that is not news for the user.
  sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  CLI::App app{"tigris: the Tigris KD-tree search accelerator (MICRO 2019) and its golden model"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tigris 0.1.0 (commit ") + tigris::build_commit() + ")");

  // Each command's default folder is its own (a folder holds one command's output: a `tigris
  // ref` after a `tigris run` must not find run's folder in its way).
  tigris::SearchOptions ref_options;
  ref_options.out = "tigris-out/ref";
  CLI::App* ref = app.add_subcommand(
      "ref", "Run the golden software model only: KD-tree search with visit counts");
  tigris::add_search_options(*ref, ref_options, true);

  tigris::RunOptions run_options;
  run_options.search.out = "tigris-out/run";
  CLI::App* run = app.add_subcommand(
      "run", "Run the accelerator model; every query is checked against the golden model "
             "(exit 0 only when all match, 1 on a mismatch or deadlock)");
  tigris::add_run_options(*run, run_options);

  tigris::RegisterOptions register_options;
  register_options.out = "tigris-out/register";
  CLI::App* reg = app.add_subcommand(
      "register", "Run the registration pipeline (outlier removal, normals, key points, descriptors, "
                  "KPCE, rejection, ICP) with its KD-tree searches on the golden model, FLANN or the accelerator "
                  "model in the loop; --compare: the four side by side");
  tigris::add_register_options(*reg, register_options);

  tigris::OdometryOptions odometry_options;
  CLI::App* odo = app.add_subcommand(
      "odometry", "Register each frame of a KITTI-layout sequence into the previous one (tigris register per "
                  "pair, --jobs at a time), chain the poses, KITTI's error metrics");
  tigris::add_odometry_options(*odo, odometry_options);

  tigris::SynthOptions synth_options;
  CLI::App* syn = app.add_subcommand(
      "synth", "Write a synthetic drive (seeded town, 10 Hz trajectory, HDL-64E-like scans, exact poses) in "
               "KITTI's odometry layout");
  tigris::add_synth_options(*syn, synth_options);

  // Listed for --help only: run_python_tool() has already taken these.
  app.add_subcommand("sweep", "Design-space sweep from a JSON spec, locally (--jobs) or as a Slurm job array "
                              "(--slurm); CSV, JSON and resume (sweep/tigris_sweep.py; tigris sweep --help)");
  app.add_subcommand("reproduce", "The paper's section 6 experiments as sweeps, with figures and REPORT.md "
                                  "(sweep/reproduce.py; tigris reproduce --help)");
  app.add_subcommand("diff", "Compare runs (stats.json files, run folders, sweep points): configuration "
                             "differences, headline figures side by side with ratios, every other differing "
                             "leaf (sweep/tigris_diff.py; tigris diff --help)");
  app.add_subcommand("plot", "Figures of a sweep folder or CSV: headline figures against each swept key, and "
                             "the paper's figures the sweep covers (sweep/tigris_plot.py; tigris plot --help)");
  app.add_subcommand("pipeline-dse", "The paper's section 3: sample the registration pipeline's design space, "
                                     "run each point over a sequence (locally or on Slurm), Pareto frontiers of "
                                     "error against time, stage and KD-tree shares of the Pareto points "
                                     "(sweep/pipeline_dse.py; tigris pipeline-dse --help)");

  // `tigris COMMAND --list-flags`: before parsing, so a command's required flags need not be given.
  for (CLI::App* c : {ref, run, reg, odo, syn})
    c->add_flag("--list-flags", "Print this command's flags as JSON (flag, type, default, meaning) for tools, and exit");
  if (argc == 3 && std::string(argv[2]) == "--list-flags")
    for (CLI::App* c : {ref, run, reg, odo, syn})
      if (c->get_name() == argv[1]) {
        std::cout << tigris::flags_json(*c).dump(2) << '\n';
        return 0;
      }

  try {
    tigris::reject_empty_arguments(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "tigris: error: " << printable(e.what()) << '\n';
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::string hints = tigris::parse_suggestions(app, argc, argv, e.what());
    if (hints.rfind("'", 0) == 0)  // an unknown command: CLI11 would only say one is required
      std::cerr << "tigris: error: " << printable(hints);
    else if (!hints.empty())  // the project's words first, CLI11's after them
      std::cerr << "tigris: error: " << printable(hints) << "(" << printable(e.what()) << ")\n";
    else
      std::cerr << "tigris: error: " << printable(e.what()) << '\n';
    std::cerr << "Run with --help for more information (tigris COMMAND --help for a command's flags).\n";
    return 2;
  }
  ref_options.command_line = tigris::command_line(argc, argv);
  run_options.search.command_line = ref_options.command_line;
  try {
    if (*ref) return tigris::run_ref_command(*ref, ref_options);
    if (*run) return tigris::run_run_command(*run, run_options);
    register_options.command_line = tigris::command_line(argc, argv);
    register_options.argv.assign(argv, argv + argc);
    if (*reg) return tigris::run_register_command(*reg, register_options);
    odometry_options.command_line = register_options.command_line;
    odometry_options.argv = register_options.argv;
    if (*odo) return tigris::run_odometry_command(*odo, odometry_options);
    if (*syn) return tigris::run_synth_command(*syn, synth_options);
  } catch (const tigris::Interrupted& e) {
    std::cerr << "tigris: " << e.what() << ": child processes stopped\n";
    return 128 + e.signal;
  } catch (const tigris::SlurmError& e) {
    std::cerr << "tigris: error: " << printable(e.what()) << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "tigris: error: " << printable(e.what()) << '\n';
    return 2;
  }
  return 2;
}
