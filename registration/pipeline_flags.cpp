#include "pipeline_flags.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/flag_values.hpp"
#include "search_backends.hpp"

namespace tigris::registration {

PipelineConfig config_from_flags(const PipelineFlags& o) {
  PipelineConfig config = preset(o.preset);
  if (!o.config.empty()) apply_file(config, o.config);
  for (const std::string& s : o.sets) apply_set(config, s);
  // accel / accel-approx: the golden back-end's searches (exact / approx) on the model.
  if (!o.search.empty()) config.search.backend = parse_backend(search_backend(o.search).golden);
  if (!o.height.empty()) {
    const int h = parse_height(o.height);
    config.search.top_height = h < 0 ? 30 : h;  // 'full': the plug-in clamps to each cloud's
  }
  if (!o.approx_thd.empty()) {
    if (!o.search.empty() && !search_backend(o.search).approximate)
      throw std::invalid_argument("--approx-thd needs --search approx or accel-approx (got --search " + o.search + ")");
    const double t = parse_number("--approx-thd", o.approx_thd);
    config.search.backend = Backend::Approx;
    // Through the keys, so the flag has the key's range and registration.json reads back.
    apply_set(config, "search.nn_thd=" + o.approx_thd, "--approx-thd");
    config.search.radius_thd = std::min(1.0, 0.4 * t / 1.2);
  }
  const bool injecting = !o.inject_kth.empty() || !o.inject_shell.empty();
  if (!o.inject_kth.empty()) config.inject.rpce_kth = parse_kth(o.inject_kth);
  if (!o.inject_shell.empty()) {
    parse_shell(o.inject_shell, config.normals.radius);  // the form R1,R2 and R1 < r < R2
    const std::size_t at = o.inject_shell.find(',');
    apply_set(config, "inject.normals_shell_inner=" + o.inject_shell.substr(0, at), "--inject-shell");
    apply_set(config, "inject.normals_shell_outer=" + o.inject_shell.substr(at + 1), "--inject-shell");
  }
  if (injecting && config.search.backend == Backend::Approx)
    throw std::invalid_argument(std::string(!o.inject_kth.empty() ? "--inject-kth" : "--inject-shell") +
                                " needs --search exact, flann or accel (error injection measures exact search; "
                                "got search " +
                                (in_loop(o.search) ? o.search : std::string("approx")) + ")");
  validate(config, "tigris register");
  return config;
}

}  // namespace tigris::registration
