// register's flags to a pipeline configuration (registration/pipeline_flags.hpp) and the one
// table of search back-ends (registration/search_backends.hpp), without the binary.
#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>

#include "registration/pipeline_flags.hpp"
#include "registration/search_backends.hpp"

using namespace tigris::registration;

namespace {

// The message of the std::invalid_argument config_from_flags throws ("" when it does not).
std::string refusal(const PipelineFlags& f) {
  try {
    config_from_flags(f);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("register's flags set their keys over the preset", "[flags]") {
  PipelineFlags f;
  CHECK(config_from_flags(f).search.backend == preset("dp4").search.backend);
  f.search = "accel";  // the loop searches with the golden model's exact search
  CHECK(config_from_flags(f).search.backend == Backend::Exact);
  f.search = "accel-approx";
  f.approx_thd = "0.6";
  PipelineConfig c = config_from_flags(f);
  CHECK(c.search.backend == Backend::Approx);
  CHECK(c.search.nn_thd == Approx(0.6));
  CHECK(c.search.radius_thd == Approx(0.4 * 0.6 / 1.2));
  f = PipelineFlags{};
  f.approx_thd = "0.3";  // implies approx
  CHECK(config_from_flags(f).search.backend == Backend::Approx);
  f = PipelineFlags{};
  f.height = "full";
  CHECK(config_from_flags(f).search.top_height == 30);
  f.height = "4";
  f.inject_kth = "3";
  f.sets = {"icp.max_iterations=7"};
  c = config_from_flags(f);
  CHECK(c.search.top_height == 4);
  CHECK(c.inject.rpce_kth == 3);
  CHECK(c.icp.max_iterations == 7);
}

TEST_CASE("register's flags that do not hold are refused naming the flag", "[flags]") {
  PipelineFlags f;
  f.search = "exact";
  f.approx_thd = "0.6";
  CHECK(refusal(f).find("--approx-thd needs --search approx or accel-approx (got --search exact)") == 0);
  f = PipelineFlags{};
  f.approx_thd = "-1";
  CHECK(refusal(f).find("--approx-thd") != std::string::npos);
  f = PipelineFlags{};
  f.search = "approx";
  f.inject_kth = "2";
  CHECK(refusal(f).find("--inject-kth needs --search exact, flann or accel") == 0);
  f.search = "accel-approx";
  CHECK(refusal(f).find("got search accel-approx") != std::string::npos);
  f = PipelineFlags{};
  f.height = "31";
  CHECK(refusal(f).find("--height must be 'full' or a whole number from 0 to 30, got '31'") == 0);
  f = PipelineFlags{};
  f.preset = "dp5";
  CHECK(refusal(f).find("dp5") != std::string::npos);
  f = PipelineFlags{};
  f.search = "kdtree";
  CHECK(refusal(f) == "--search must be one of flann, exact, approx, accel, accel-approx, got 'kdtree'");
}

TEST_CASE("one table of search back-ends", "[flags]") {
  CHECK(search_backend_names() == std::vector<std::string>{"flann", "exact", "approx", "accel", "accel-approx"});
  for (const SearchBackend& b : kSearchBackends) {
    CHECK(std::string(to_string(parse_backend(b.golden))) == b.golden);  // a pipeline back-end
    CHECK(b.in_loop() == (std::string(b.search).rfind("accel", 0) == 0));
    CHECK(b.approximate == (std::string(b.golden) == "approx"));
    CHECK(&search_backend(b.search) == &b);
  }
  CHECK(in_loop("accel-approx"));
  CHECK_FALSE(in_loop("approx"));
  CHECK_FALSE(in_loop(""));
}
