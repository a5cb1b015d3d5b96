// The one table of the 3D KD-tree back-ends a registration can search with (`--search`):
// what each is called, how a table labels it, whether its time is measured on the CPU or
// modeled by the accelerator in the loop, and which golden search it runs. register and
// odometry take their flag's choices from it, and their --compare rows pick from it.
#pragma once

#include <string>
#include <vector>

namespace tigris::registration {

struct SearchBackend {
  const char* search;  // --search
  const char* label;   // in the --compare tables
  bool cpu;            // measured on the CPU (--compare times it --repeat times); else modeled, run once
  bool approximate;    // the approximate search (exact otherwise; FLANN is exact)
  const char* golden;  // search.backend of the pipeline: flann, exact or approx (the loop's golden search)
  bool in_loop() const { return !cpu; }
};

inline constexpr SearchBackend kSearchBackends[] = {
    {"flann", "CPU, PCL's FLANN", true, false, "flann"},
    {"exact", "CPU, golden model (exact)", true, false, "exact"},
    {"approx", "CPU, golden model (approximate)", true, true, "approx"},
    {"accel", "accelerator, exact", false, false, "exact"},
    {"accel-approx", "accelerator, approximate", false, true, "approx"}};

// The back-end named `search`; std::invalid_argument naming the choices.
const SearchBackend& search_backend(const std::string& search);
// Whether `search` names a back-end of the accelerator in the loop ("" : no).
bool in_loop(const std::string& search);
// Every --search choice, in the table's order.
std::vector<std::string> search_backend_names();

}  // namespace tigris::registration
