#include "scan_service.hpp"

#include "hw/be/pe_array.hpp"
#include "inline_scans.hpp"
#include "threaded_scans.hpp"

namespace tigris::hw {

bool ScanService::fruitless(const PeArray& pe, const QueryToken& token, const LeafBounds::Box& b) const {
  return LeafBounds::min_dist2(token.point, b) > (radius_ ? r2_ : pe.bound(token.slot));
}

void ScanService::scan_now(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
                           std::uint32_t count, std::vector<tlm_if::ResultRecord>& hits) {
  if (!fruitless(pe, token, box(leaf))) pe.scan(token, set, count, hits);
}

std::unique_ptr<ScanService> make_scan_service(bool threaded) {
  if (threaded) return std::make_unique<ThreadedScans>();
  return std::make_unique<InlineScans>();
}

}  // namespace tigris::hw
