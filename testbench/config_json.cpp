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

namespace {
bool rtl_costs_hold(const hw::CostTable& c) {
  const hw::CostTable d;
  return c.ru_fetch_query == d.ru_fetch_query && c.ru_node == d.ru_node && c.ru_pi_rs_stall == d.ru_pi_rs_stall &&
         c.ru_prune_at_rn == d.ru_prune_at_rn && c.ru_prune_no_bypass == d.ru_prune_no_bypass &&
         c.ru_drain == d.ru_drain && c.result_writeback == d.result_writeback;
}
}  // namespace

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
      // The RTL RU's timing is its pipeline (rtl/README.md): the cost table's RU rows must be
      // the ones it was built to, or the cross-check compares different machines.
      {"fe.recursion_unit_model", cfg.fe.recursion_unit_model != "rtl" || rtl_costs_hold(cfg.cost),
       "'rtl' needs the cost table's RU rows at their defaults (cost.ru_*): its pipeline has that timing"},
      {"leader.width", cfg.leader.width == 0 || cfg.leader.scope == LeaderScope::EveryLeaf,
       "applies to leader.scope every_leaf (first_leaf leaders keep their final results): set it to 0"},
      {"result_buffer.leader_fraction", cfg.result_buffer.slot_fraction + cfg.result_buffer.leader_fraction < 1.0,
       "plus result_buffer.slot_fraction must stay below 1: the result stream needs the rest"},
  };
  for (const auto& r : rules)
    if (!r.ok) throw std::invalid_argument(source + ": '" + r.key + "' " + r.why);
}

}  // namespace tigris
