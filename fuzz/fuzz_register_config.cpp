// Fuzz target: the registration pipeline's configuration (registration/pipeline_config.cpp,
// `tigris register --config` and `--set`). Input whose first byte is 0: the rest chooses --set
// assignments, each a key of the key table (config/key_table.hpp) and a value drawn from the kinds
// that broke it before (in range, at a bound, beyond it, subnormal, 1e400, NaN, hex, a float for
// an integer, another type, empty); otherwise it is a JSON configuration file. Bad input must
// give std::invalid_argument starting with its source (the file name or "--set 'key=value'"); an
// accepted configuration must survive to_json and re-applying it onto a preset (the same JSON
// back), and validate() must accept it or give a clean error. No PCL: the target compiles only
// the configuration reader.
#include <stdexcept>
#include <string>
#include <vector>

#include "config/key_table.hpp"
#include "core/json_file.hpp"
#include "fuzz_common.hpp"
#include "registration/pipeline_config.hpp"

namespace {

using namespace tigris_fuzz;
namespace reg = tigris::registration;
const char* const kTarget = "register_config";
const std::string kLabel = "fuzz.json";

void check_accepted(const reg::PipelineConfig& c) {
  const nlohmann::json j = reg::to_json(c);
  reg::PipelineConfig again = reg::preset("dp7");
  try {
    reg::apply_json(again, j, "round trip");
  } catch (const std::invalid_argument& e) {
    wrong_read(kTarget, std::string("its own dump rejected: ") + e.what());
  }
  if (reg::to_json(again) != j) wrong_read(kTarget, "dump, re-apply and dump differ");
  try {
    reg::validate(c, "validate");
  } catch (const std::invalid_argument& e) {
    if (!names_source(e.what(), "validate")) wrong_read(kTarget, std::string("validate message: ") + e.what());
  }
}

// A value for `key` of the kind the next byte picks.
std::string value_for(const tigris::config::Key& key, ByteSource& in) {
  static const char* const kinds[] = {"0",     "1",      "-1",  "0.5",  "100",  "1e6",  "1e-320",
                                      "1e400", "nan",    "inf", "0x10", "10.0", "true", "off",
                                      "",      " 1",     "1 ",  "narf", "shot", "svd",  "99999999999999999999",
                                      "-0",    "1e-300", "lm"};
  const std::uint8_t pick = in.byte();
  if (pick < 200) return kinds[pick % (sizeof kinds / sizeof *kinds)];
  const nlohmann::json v = tigris::config::get(reg::preset("dp4"), key);  // the default, as --set takes it
  return v.is_string() ? v.get<std::string>() : v.dump();
}

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  reg::PipelineConfig c = reg::preset(size > 1 && (data[1] & 1) ? "dp7" : "dp4");
  if (size > 0 && data[0] == 0) {
    const std::vector<tigris::config::Key>& keys = tigris::config::keys<reg::PipelineConfig>();
    ByteSource in(data + 1, size - 1);
    for (int n = 1 + in.byte() % 8; n > 0; --n) {
      const tigris::config::Key& key = keys[in.byte() % keys.size()];
      const std::string assignment = key.name + "=" + value_for(key, in);
      try {
        reg::apply_set(c, assignment);
      } catch (const std::invalid_argument& e) {
        const std::string source = "--set '" + assignment + "'";
        if (std::string(e.what()).compare(0, source.size(), source) != 0)
          wrong_read(kTarget, std::string("error without its source: ") + e.what());
        return 0;
      }
    }
    check_accepted(c);
    return 0;
  }
  try {
    reg::apply_json(c, tigris::parse_json_text(std::string(reinterpret_cast<const char*>(data), size), kLabel, true),
                    kLabel);
  } catch (const std::invalid_argument& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return 0;
  }
  check_accepted(c);
  return 0;
}
