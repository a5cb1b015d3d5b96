// A `tigris` command registers itself, as the hardware policies do (hw/policy_registry.hpp): its
// file defines a Command and a CommandRegistration, and main() finds it in commands(). So a new
// command is one new file (docs/extending.md, "A command").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tigris {

// The command line as typed: the report's text (quoted for a shell) and the words.
struct CommandLine {
  std::string text;
  std::vector<std::string> argv;
};

class Command {
 public:
  virtual ~Command() = default;
  // Declares the command's flags on its subcommand, bound to the command's own options.
  virtual void add_flags(CLI::App& app) = 0;
  // Runs the command once its flags have parsed; returns the exit code.
  virtual int run(const CLI::App& app, const CommandLine& line) = 0;
};

struct CommandInfo {
  std::string name;
  std::string summary;  // the line `tigris --help` shows
  int order = 0;        // the place in `tigris --help`
  std::function<std::unique_ptr<Command>()> make;
};

// Every registered command, in `order`.
std::vector<const CommandInfo*> commands();

// The usual command: its options of type Options, declared on its subcommand by `add`, and `run`
// once they have parsed.
template <class Options>
class OptionsCommand final : public Command {
 public:
  using Add = void (*)(CLI::App&, Options&);
  using Run = int (*)(const CLI::App&, Options&, const CommandLine&);
  OptionsCommand(Add add, Run run_fn) : add_(add), run_(run_fn) {}
  void add_flags(CLI::App& app) override { add_(app, options_); }
  int run(const CLI::App& app, const CommandLine& line) override { return run_(app, options_, line); }

 private:
  Add add_;
  Run run_;
  Options options_;
};

template <class Options>
CommandInfo options_command(std::string name, std::string summary, int order, typename OptionsCommand<Options>::Add add,
                            typename OptionsCommand<Options>::Run run) {
  return {std::move(name), std::move(summary), order,
          [add, run] { return std::make_unique<OptionsCommand<Options>>(add, run); }};
}

// A file-scope object of this type registers a command before main() runs.
struct CommandRegistration {
  explicit CommandRegistration(CommandInfo info);
};

}  // namespace tigris
