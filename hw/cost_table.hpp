// The one cost table of the timing model (DESIGN.md section 7): every cycle count a unit
// charges comes from here, so a reader can see the whole timing model at a glance.
#pragma once

namespace tigris::hw {

struct CostTable {
  // Recursion Unit, stages FQ RS RN CD PI CL (paper Fig. 8).
  int ru_fetch_query = 1;       // FQ: once per activation (a query taken from the FQQ)
  int ru_node = 1;              // one node through RS..PI when nothing stalls
  int ru_pi_rs_stall = 3;       // PI->RS dependency per visited node without forwarding
  int ru_prune_at_rn = 2;       // a pruned node with bypassing leaves at RN (RS, RN)
  int ru_prune_no_bypass = 4;   // a pruned node without bypassing goes down to PI: RS..PI
  int ru_drain = 2;             // CD..CL behind the last node before the query is sent on
  // Query Distribution Network.
  int qdn_latency = 1;          // FE -> BQB wire + arbitration
  int qdn_port_interval = 1;    // one query per cycle per SU port
  // Search Unit.
  int pe_pipeline_depth = 3;    // read, distance, insert (paper Fig. 9)
  int node_cache_hit = 0;       // a Node Set streamed from the Node Cache: cycles before its first word
  int issue_cycle = 1;          // issue logic per batch beyond the associative search
  int result_writeback = 1;     // a finished query's results leave the RU (after its last walk)
  int be_to_fe = 1;             // a scanned query re-enters the FQQ
  // Host interface (outside the job's cycles: loading before START, reading after done).
  int host_csr_access = 1;            // one CSR read or write
  int host_link_bytes_per_cycle = 32; // host reads of the result region in DRAM
};

}  // namespace tigris::hw
