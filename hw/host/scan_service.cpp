#include "hw/host/scan_service.hpp"

#include "hw/host/inline_scans.hpp"
#include "hw/host/threaded_scans.hpp"

namespace tigris::hw {

std::unique_ptr<ScanService> make_scan_service(bool threaded) {
  if (threaded) return std::make_unique<ThreadedScans>();
  return std::make_unique<InlineScans>();
}

}  // namespace tigris::hw
