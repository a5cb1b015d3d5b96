// Checks on a command line that hold for every `tigris` command: no flag given an
// empty value, and no output that is an input or another output. Both run before any work, so
// a mistyped path costs nothing and overwrites nothing.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tigris {

// Throws std::invalid_argument naming the first flag given an empty value ("--cloud ''" would
// otherwise mean "the default", "--out ''" the root folder), before CLI11 parses: its own
// checks would report some of them as something else. `tigris` takes no positional argument,
// so an empty argument is always some flag's value.
void reject_empty_arguments(int argc, const char* const* argv);

// A file a command reads or writes, and the flag (or rule) that named it.
struct PathUse {
  std::string flag, path;
};

// Throws std::invalid_argument when two outputs are one file, or an output is an input. Paths
// are compared after resolving symbolic links and "..", and existing files also by identity
// (hard links); empty paths are skipped.
void check_distinct_paths(const std::vector<PathUse>& inputs, const std::vector<PathUse>& outputs);

// The candidate closest to `word` by edit distance, when it is close enough to be a typo (at
// most 2 edits, and fewer than the word has letters); empty otherwise.
std::string closest(const std::string& word, const std::vector<std::string>& candidates);

// For a parse error of `app` (CLI11's message `error`): "did you mean" lines for an unknown
// subcommand, for each flag of argv that the chosen subcommand does not take (naming the
// subcommand that does take it), for a bare word where a flag was wanted (`odometry seq`: did
// you mean --sequence seq?) and for a value outside a flag's list (`--search acel`: accel).
std::string parse_suggestions(CLI::App& app, int argc, const char* const* argv, const std::string& error = "");

// The command line as a shell would take it back (arguments with spaces or quotes quoted).
std::string command_line(int argc, const char* const* argv);

// Validators shared by the commands: a whole number 0 .. 2^64-1 (CLI11 alone wraps "-1" and
// rounds "1e23"); a finite number in [lo, hi] (CLI::Range lets NaN through); a whole number in
// [lo, hi] with a readable message.
CLI::Validator uint64_text();
CLI::Validator finite_range(double lo, double hi);
CLI::Validator whole_range(long long lo, long long hi);

}  // namespace tigris
