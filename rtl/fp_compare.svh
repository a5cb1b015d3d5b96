// Comparisons of IEEE-754 binary32 encodings in integer logic (synthesizable), as C++'s float
// operators order them for every value the unit sees (finite or +inf, never NaN): -0 == +0.
// Included inside a module (Yosys 0.23 and Verilator both take functions there).

// A key whose unsigned order is the floats' order: negatives reversed below the positives.
function automatic [31:0] tigris_fkey(input [31:0] f);
  if (f[30:0] == 31'd0) tigris_fkey = 32'h8000_0000;  // both zeros
  else if (f[31]) tigris_fkey = ~f;
  else tigris_fkey = f | 32'h8000_0000;
endfunction
function automatic tigris_flt(input [31:0] a, input [31:0] b);
  tigris_flt = tigris_fkey(a) < tigris_fkey(b);
endfunction
function automatic tigris_fle(input [31:0] a, input [31:0] b);
  tigris_fle = tigris_fkey(a) <= tigris_fkey(b);
endfunction
function automatic tigris_fgt(input [31:0] a, input [31:0] b);
  tigris_fgt = tigris_fkey(a) > tigris_fkey(b);
endfunction
