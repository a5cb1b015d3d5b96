// One registration as `tigris register` runs it: the pipeline with its progress on stderr
// (stage by stage, the work bound's), the work bound, the trace recorder (--record-trace) and
// the accelerator in the loop plugged in; and the recorded trace written.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "accelerator_port.hpp"
#include "pipeline.hpp"
#include "report.hpp"
#include "trace_recorder.hpp"

namespace tigris::registration {

struct RegisterRun {
  RegistrationResult result;
  double work_spent = 0;                    // distances and neighbours, against max_work
  std::shared_ptr<TraceRecorder> recorder;  // when recording
  bool mismatch = false;  // an accelerator job's results differed from the golden model's (reported; exit 1)
};

// Runs the pipeline; `stage` names the stage running, for the caller's own lines (the
// accelerator's jobs). A mismatch is reported on stderr and returned; a work bound exceeded is
// std::invalid_argument naming the stage.
RegisterRun run_registration(const PointCloud& source, const PointCloud& target, const PipelineConfig& config,
                             double max_work, bool record, std::shared_ptr<AcceleratorPort> accelerator,
                             std::string& stage);

// Writes the recorded trace to `path` (its meta: the report without its stages, the command line;
// its times without the recording's); returns registration.json's "trace".
nlohmann::ordered_json write_trace(const std::string& path, TraceRecorder& recorder, const Report& report,
                                   const std::string& command_line);

}  // namespace tigris::registration
