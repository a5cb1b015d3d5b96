// The accelerator's configuration through the one configuration mechanism (config/apply.hpp),
// plus its rules across keys.
#include <stdexcept>

#include "config.hpp"
#include "config/apply.hpp"

namespace tigris {

using hw::AcceleratorConfig;
using nlohmann::json;

void apply_config_json(AcceleratorConfig& cfg, const json& j, const std::string& source) {
  config::apply_json(cfg, j, source);
}

void apply_config_file(AcceleratorConfig& cfg, const std::string& path) { config::apply_file(cfg, path); }

void apply_config_text(AcceleratorConfig& cfg, const std::string& text, const std::string& source) {
  config::apply_text(cfg, text, source);
}

void apply_setting(AcceleratorConfig& cfg, const std::string& assignment, const std::string& source) {
  config::apply_setting(cfg, assignment, source);
}

json config_to_json(const AcceleratorConfig& cfg) { return config::to_json(cfg); }

std::string config_reference() { return config::reference_markdown(AcceleratorConfig{}); }

json config_reference_json() { return config::reference_json(AcceleratorConfig{}); }

std::vector<std::string> config_keys() {
  std::vector<std::string> names;
  for (const config::Key& k : config::keys<AcceleratorConfig>()) names.push_back(k.name);
  return names;
}

void validate_config(const AcceleratorConfig& cfg) {
  const std::string source = "invalid configuration";
  config::check_keys(cfg, source);  // per-key type and range
  // Cross-field rules: {key to blame, holds, explanation}. Whether a job fits the buffers (its
  // tree image, queries, stack and results) is hw::job_fit_error's to say, once.
  const auto holds_one = [&](const hw::SramConfig& b) { return b.bytes >= static_cast<std::uint64_t>(b.word_bytes); };
  const struct {
    const char* key;
    bool ok;
    std::string why;
  } rules[] = {
      {"sram.points.bytes", holds_one(cfg.sram.points), "holds no word of sram.points.word_bytes"},
      {"sram.queries.bytes", holds_one(cfg.sram.queries), "holds no word of sram.queries.word_bytes"},
      {"sram.query_stack.bytes", holds_one(cfg.sram.query_stack), "holds no word of sram.query_stack.word_bytes"},
      {"sram.results.bytes", holds_one(cfg.sram.results), "holds no word of sram.results.word_bytes"},
      {"result_buffer.leader_fraction", cfg.result_buffer.slot_fraction + cfg.result_buffer.leader_fraction < 1.0,
       "plus result_buffer.slot_fraction must stay below 1: the result stream needs the rest"},
  };
  for (const auto& r : rules)
    if (!r.ok) throw std::invalid_argument(source + ": '" + r.key + "' " + r.why);
}

}  // namespace tigris
