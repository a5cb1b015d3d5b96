// Every NN/kNN scan runs at once, in scan(): the simple implementation of the scan service
// (hw/host/scan_service.hpp), and the reference the threaded one must match bit for bit.
#pragma once

#include "hw/be/pe_array.hpp"
#include "hw/host/scan_service.hpp"

namespace tigris::hw {

class InlineScans final : public ScanService {
 public:
  void scan(PeArray& pe, const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
            const LeafBounds::Box* box) override {
    pe.scan_nearest(token, set, count, box);
  }
  void ready(std::uint32_t) override {}
  void drain() override {}
  // The batch's issue reads the query's slot on this thread: warm it.
  void queued(const PeArray& pe, const QueryToken& token) override {
    if (!radius()) pe.prefetch_slot(token.slot);
    hint(token.query);
  }

 private:
  void begin(std::uint32_t) override {}
};

}  // namespace tigris::hw
