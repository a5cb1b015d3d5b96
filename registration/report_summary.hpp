// The registration's summary as `tigris register` prints it from its report (report.hpp):
// the stages' time and KD-tree work, the accelerator's modeled figures in the loop, the
// transform and its error against the ground truth.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "report.hpp"

namespace tigris::registration {

// The injected error as the summary lines say it (", RPCE returns ..."; "" when none).
std::string injection_text(const Report::Injection& i);

// `backend`: the golden back-end the searches used (exact or approx, in the loop too); `path`:
// where the report was written.
void print_summary(std::FILE* out, const Report& r, const std::string& backend, const std::string& path);

// An accelerator job's line as it ends (in the loop): stage, mode, size, verdict, modeled and
// simulated time, sampling; `rep` is the job's report (registration.json's row: job_row).
void print_job_line(std::FILE* out, std::uint64_t n, const AccelJob& job, const nlohmann::json& rep,
                    const std::string& stage);

}  // namespace tigris::registration
