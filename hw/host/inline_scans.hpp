// Every NN/kNN scan runs at once, in scan(): the simple implementation of the scan service
// (hw/host/scan_service.hpp), and the reference the threaded one must match bit for bit.
#pragma once

#include "hw/be/pe_array.hpp"
#include "scan_service.hpp"

namespace tigris::hw {

class InlineScans final : public ScanService {
 public:
  void scan(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
            std::uint32_t count) override {
    if (!fruitless(pe, token, box(leaf))) pe.scan_nearest(token, set, count);
  }
  void ready(std::uint32_t) override {}
  void drain() override {}
  // The batch's issue reads the query's slot on this thread: warm it.
  void queued(const PeArray& pe, const QueryToken& token) override {
    if (!radius()) write_soon(pe.slots().address(token.slot), pe.slots().bytes());
    hint(token.query);
  }

 private:
  void begin(std::uint32_t) override {}
};

}  // namespace tigris::hw
