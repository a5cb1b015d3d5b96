// Fuzz target: the configuration readers (testbench/config_json.cpp): JSON files
// (apply_config_text, what apply_config_file runs on the file's text) and `--set key=value`
// (apply_setting). Input whose first byte is 0: the rest is --set assignments, one a line;
// otherwise it is a JSON configuration file. (Assignments end at a newline or a NUL byte: a
// command-line argument cannot hold a NUL.) Bad input must give a clean error naming its
// source (std::invalid_argument, as the CLI expects); an accepted configuration must survive
// config_to_json and re-applying it onto the defaults (the same JSON back), and validate_config
// either accepts it or gives a clean error.
//
// Linked without SystemC: hw/config.hpp includes <systemc> for one inline helper (period());
// the target compiles with SC_DISABLE_API_VERSION_CHECK and never calls it.
#include <stdexcept>
#include <string>

#include "fuzz_common.hpp"
#include "testbench/config.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "config";
const std::string kLabel = "fuzz.json";

void check_accepted(const tigris::hw::AcceleratorConfig& cfg) {
  const nlohmann::json j = tigris::config_to_json(cfg);
  tigris::hw::AcceleratorConfig again;
  try {
    tigris::apply_config_json(again, j, "round trip");
  } catch (const std::invalid_argument& e) {
    wrong_read(kTarget, std::string("its own dump rejected: ") + e.what());
  }
  if (tigris::config_to_json(again) != j) wrong_read(kTarget, "dump, re-apply and dump differ");
  try {
    tigris::validate_config(cfg);
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).rfind("invalid configuration: '", 0) != 0)
      wrong_read(kTarget, std::string("validate_config message: ") + e.what());
  }
}

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  tigris::hw::AcceleratorConfig cfg;
  if (size > 0 && data[0] == 0) {
    const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
    std::size_t pos = 0;
    while (pos <= text.size()) {
      std::size_t nl = text.find_first_of(std::string("\n\0", 2), pos);
      if (nl == std::string::npos) nl = text.size();
      const std::string assignment = text.substr(pos, nl - pos);
      pos = nl + 1;
      try {
        tigris::apply_setting(cfg, assignment);
      } catch (const std::invalid_argument& e) {
        const std::string source = "--set '" + assignment + "'";
        if (std::string(e.what()).compare(0, source.size(), source) != 0)
          wrong_read(kTarget, std::string("error without its source: ") + e.what());
        return 0;
      }
    }
    check_accepted(cfg);
    return 0;
  }
  try {
    tigris::apply_config_text(cfg, std::string(reinterpret_cast<const char*>(data), size), kLabel);
  } catch (const std::invalid_argument& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return 0;
  }
  check_accepted(cfg);
  return 0;
}
