// `tigris`: the command-line front end (DESIGN.md section 10).
// Exit codes: 0 success, 1 golden mismatch (tigris run), 2 bad input or configuration.
#include <iostream>

#include <CLI/CLI.hpp>

#include "ref_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"tigris: the Tigris KD-tree search accelerator (MICRO 2019) and its golden model"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "tigris 0.1.0");

  tigris::SearchOptions ref_options;
  CLI::App* ref = app.add_subcommand(
      "ref", "Run the golden software model only: KD-tree search with visit counts");
  tigris::add_search_options(*ref, ref_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*ref) return tigris::run_ref_command(*ref, ref_options);
  } catch (const std::exception& e) {
    std::cerr << "tigris: error: " << e.what() << '\n';
    return 2;
  }
  return 2;
}
