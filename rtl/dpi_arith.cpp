// The RTL Recursion Unit's float32 units in simulation (rtl/fp_units.sv): DPI-C calls into the
// numeric contract (sw_ref/arith.hpp), so the RTL's distances are the golden model's bit for bit.
#include <cstring>

#include "Vtigris_ru__Dpi.h"
#include "sw_ref/arith.hpp"

namespace {
float as_float(unsigned int bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}
unsigned int as_bits(float f) {
  unsigned int bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}
}  // namespace

unsigned int tigris_fp_dist2_dpi(unsigned int ax, unsigned int ay, unsigned int az, unsigned int bx, unsigned int by,
                                 unsigned int bz) {
  const tigris::Point3 a{as_float(ax), as_float(ay), as_float(az)}, b{as_float(bx), as_float(by), as_float(bz)};
  return as_bits(tigris::dist2(a, b));
}

unsigned int tigris_fp_plane2_dpi(unsigned int a, unsigned int b) {
  return as_bits(
      tigris::plane_dist2(tigris::Point3{as_float(a), 0.0f, 0.0f}, tigris::Point3{as_float(b), 0.0f, 0.0f}, 0));
}
