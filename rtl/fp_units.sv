`line 2 "rtl/fp_units.sv" 0  // messages name the file relative to the tree (no build path in the binary)
// The RU's float32 arithmetic units. In simulation they call the project's arithmetic through
// DPI-C (rtl/dpi_arith.cpp: sw_ref/arith.hpp, the numeric contract), so results are bit-exact
// with the golden model; in synthesis (SYNTHESIS defined) they are black boxes: a float
// adder/multiplier tree is a library macro, not this project's logic.

// ((ax-bx)^2 + (ay-by)^2) + (az-bz)^2 in float32, in this order.
`ifndef SYNTHESIS
module tigris_fp_dist2 (
    input  logic [31:0] ax, ay, az, bx, by, bz,
    output logic [31:0] d2
);
  import "DPI-C" pure function int unsigned tigris_fp_dist2_dpi(
      input int unsigned ax, input int unsigned ay, input int unsigned az,
      input int unsigned bx, input int unsigned by, input int unsigned bz);
  always_comb d2 = tigris_fp_dist2_dpi(ax, ay, az, bx, by, bz);
endmodule

// (a-b)^2 in float32: a query's squared distance to a split plane.
module tigris_fp_plane2 (
    input  logic [31:0] a, b,
    output logic [31:0] d2
);
  import "DPI-C" pure function int unsigned tigris_fp_plane2_dpi(input int unsigned a, input int unsigned b);
  always_comb d2 = tigris_fp_plane2_dpi(a, b);
endmodule
`else
(* blackbox *)
module tigris_fp_dist2 (
    input  logic [31:0] ax, ay, az, bx, by, bz,
    output logic [31:0] d2
);
endmodule

(* blackbox *)
module tigris_fp_plane2 (
    input  logic [31:0] a, b,
    output logic [31:0] d2
);
endmodule
`endif
