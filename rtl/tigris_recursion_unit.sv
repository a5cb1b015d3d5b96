`line 2 "rtl/tigris_recursion_unit.sv" 0  // messages name the file relative to the tree (no build path in the binary)
// Recursion Unit (paper section 5.2, Fig. 8) in synthesizable SystemVerilog: walks one
// query's top-tree part of the depth-first search per activation, from taking its token out
// of the FE Query Queue to handing it to a leaf set (CL) or finishing it.
//
// Stages and what they do here (rtl/README.md has the timing diagram):
//   FQ  fetch the query record and, for a new query, write the root into its stack;
//   RS  pop the top of stack (the Query Stack Buffer);
//   RN  read the node (the Point Buffer, or the RU's own copy of the first levels); decode the
//       popped entry's plane distance: beyond the bound, the node is pruned (bypassing lets it
//       leave here, else it goes on down to PI);
//   CD  its distance to the query (float32, tigris_fp_dist2) and the side of the split;
//   PI  a distance within the bound is a result candidate (inserted into the slot, or a
//       radius hit); the far child is pushed with its plane distance;
//   CL  a leaf set is reached: its directory entry is read and the query leaves for the BE.
// With forwarding the near child goes straight from CD to RN (one node a cycle); without it,
// the next node waits for PI's stack update (3 cycles). A popped node's RS and RN share a
// cycle: the stack read's data selects the node read (the transaction-level RU's timing).
//
// Every buffer access is a request held until its grant (a bank or port busy stalls the unit);
// read data arrives with the grant. Float32 arithmetic is tigris_fp_* (rtl/fp_units.sv):
// DPI-C into the project's arithmetic in simulation, black boxes in synthesis. Comparisons are
// integer logic on the IEEE-754 encodings (tigris_fkey: -0 == +0; NaN never reaches the unit).
module tigris_recursion_unit (
    input  logic        clk,
    input  logic        rst,
    // Job configuration, fixed while a job runs.
    input  logic        cfg_forwarding,
    input  logic        cfg_bypassing,
    input  logic        cfg_root_nonempty,
    input  logic [31:0] cfg_top_nodes,          // heap nodes 0 .. top_nodes-1 are top-tree nodes
    input  logic [31:0] cfg_replicated_nodes,   // heap nodes below this are in the RU's own copy
    // A query token from the FE Query Queue.
    input  logic        tok_valid,
    output logic        tok_ready,
    input  logic [31:0] tok_query,
    input  logic [31:0] tok_stack_base,         // entry index of the query's first stack entry
    input  logic        tok_started,
    input  logic [15:0] tok_sp,
    // The pruning bound: the slot's k-th distance (NN/kNN) or r^2 (radius), held by the slot.
    input  logic [31:0] bound,
    // Query Buffer: the query record.
    output logic        qb_req,
    output logic [31:0] qb_index,
    input  logic        qb_gnt,
    input  logic [31:0] qb_x,
    input  logic [31:0] qb_y,
    input  logic [31:0] qb_z,
    // Point Buffer: a top-tree node, or a leaf directory entry (pb_dir); the RU's own copy of
    // the first levels answers on the same port (pb_replica), without a bank.
    output logic        pb_req,
    output logic        pb_dir,
    output logic        pb_replica,
    output logic [31:0] pb_index,
    input  logic        pb_gnt,
    input  logic [31:0] pb_x,
    input  logic [31:0] pb_y,
    input  logic [31:0] pb_z,
    input  logic [31:0] pb_tag,                 // index | axis << 30
    input  logic [1:0]  pb_child_nonempty,      // {right, left}: the node's metadata bits
    // Query Stack Buffer: a pop (read) and a push (write) port.
    output logic        qs_rd_req,
    output logic [31:0] qs_rd_index,
    input  logic        qs_rd_gnt,
    input  logic [31:0] qs_rd_node,
    input  logic [31:0] qs_rd_plane2,
    output logic        qs_wr_req,
    output logic [31:0] qs_wr_index,
    output logic [31:0] qs_wr_node,
    output logic [31:0] qs_wr_plane2,
    input  logic        qs_wr_gnt,
    // A node within the bound: the slot inserts it (NN/kNN) or it is a radius hit.
    output logic        cand_valid,
    output logic [31:0] cand_index,
    output logic [31:0] cand_dist2,
    // The activation ends: its last cycle.
    output logic        done_valid,
    output logic        done_finished,          // the stack is empty: the query's search is over
    output logic [31:0] done_leaf,              // else the leaf set it leaves for
    output logic [15:0] done_sp,
    // This cycle's step (or FQ) completes: every request it made was granted.
    output logic        advance,
    // Counters of the activation (read when done_valid).
    output logic [31:0] cnt_nodes,              // top-tree nodes visited
    output logic [31:0] cnt_pruned              // popped entries pruned
);
  `include "fp_compare.svh"

  typedef enum logic [2:0] {IDLE, FQ, WALK, WAIT, CL_DRAIN, FIN_DRAIN} state_t;
  state_t state;

  logic [31:0] q_x, q_y, q_z;                  // the query point (FQ)
  logic [31:0] query, stack_base;
  logic [15:0] sp;
  logic        fwd_valid;                       // a forwarded near child is the next node
  logic [31:0] fwd_node;
  logic        push_valid;                      // the far child PI pushes with the next step
  logic [31:0] push_node, push_plane2;
  logic [2:0]  wait_left;                       // stall cycles before the next step
  logic [1:0]  drain_left;
  logic [31:0] leaf;
  logic        root_written;
  logic        tok_started_q;

  // ---- The step of this cycle (WALK): the forwarded node, or a pop. ----
  // The far child pushed by the previous node is written with this step, so it counts.
  wire [15:0] sp_eff = sp + {15'd0, push_valid};
  wire        pop    = state == WALK && !fwd_valid && sp_eff != 16'd0;
  wire        finish = state == WALK && !fwd_valid && sp_eff == 16'd0;
  // Popping the entry this step pushes reads the push's data (write-to-read bypass).
  wire        pop_bypass = pop && push_valid;
  wire [31:0] popped_node   = pop_bypass ? push_node : qs_rd_node;
  wire [31:0] popped_plane2 = pop_bypass ? push_plane2 : qs_rd_plane2;
  wire        popped = pop && (pop_bypass || qs_rd_gnt);
  wire        pruned = popped && tigris_fgt(popped_plane2, bound);
  wire        step_node_valid = state == WALK && (fwd_valid || (popped && !pruned));
  wire [31:0] node = fwd_valid ? fwd_node : popped_node;
  wire        node_is_leaf = node >= cfg_top_nodes;

  // ---- RN / CD on the node read this cycle. ----
  wire        visit = step_node_valid && !node_is_leaf && pb_gnt;
  wire [1:0]  axis = pb_tag[31:30];
  wire [31:0] q_axis = axis == 2'd0 ? q_x : (axis == 2'd1 ? q_y : q_z);
  wire [31:0] p_axis = axis == 2'd0 ? pb_x : (axis == 2'd1 ? pb_y : pb_z);
  wire        go_left = tigris_flt(q_axis, p_axis);
  wire [31:0] left_child = {node[30:0], 1'b1};  // 2n + 1
  wire [31:0] near_child = go_left ? left_child : left_child + 32'd1;
  wire [31:0] far_child  = go_left ? left_child + 32'd1 : left_child;
  wire        near_nonempty = go_left ? pb_child_nonempty[0] : pb_child_nonempty[1];
  wire        far_nonempty  = go_left ? pb_child_nonempty[1] : pb_child_nonempty[0];
  logic [31:0] d2, plane2;
  tigris_fp_dist2 u_dist2 (.ax(q_x), .ay(q_y), .az(q_z), .bx(pb_x), .by(pb_y), .bz(pb_z), .d2(d2));
  tigris_fp_plane2 u_plane2 (.a(q_axis), .b(p_axis), .d2(plane2));

  // ---- Ports. ----
  assign tok_ready = state == IDLE;
  assign qb_req = state == FQ;
  assign qb_index = query;
  // FQ writes a new query's root; WALK writes the far child pushed by the previous node.
  wire fq_root = state == FQ && !root_written && cfg_root_nonempty && !tok_started_q;
  assign qs_wr_req = fq_root || (state == WALK && push_valid);
  assign qs_wr_index = stack_base + (fq_root ? 32'd0 : {16'd0, sp});
  assign qs_wr_node = fq_root ? 32'd0 : push_node;
  assign qs_wr_plane2 = fq_root ? 32'd0 : push_plane2;
  assign qs_rd_req = pop && !pop_bypass;
  assign qs_rd_index = stack_base + {16'd0, sp_eff} - 32'd1;
  assign pb_req = step_node_valid;
  assign pb_dir = node_is_leaf;
  assign pb_replica = !node_is_leaf && node < cfg_replicated_nodes;
  assign pb_index = node_is_leaf ? node - cfg_top_nodes : node;
  assign cand_valid = visit && step_done && tigris_fle(d2, bound);  // once, as the step completes
  assign cand_index = {2'b00, pb_tag[29:0]};
  assign cand_dist2 = d2;

  // A step is complete when every request it made was granted.
  wire qs_wr_done = !qs_wr_req || qs_wr_gnt;
  wire pop_done = !pop || popped;
  wire pb_done = !pb_req || pb_gnt;
  wire step_done = qs_wr_done && pop_done && pb_done;
  wire fq_done = qb_gnt && (!fq_root || qs_wr_gnt);

  assign advance = (state == WALK && step_done) || (state == FQ && fq_done);
  assign done_valid = (state == CL_DRAIN || state == FIN_DRAIN) && drain_left == 2'd0;
  assign done_finished = state == FIN_DRAIN;
  assign done_leaf = leaf;
  assign done_sp = sp;

  // Node stall: the PI->RS dependency without forwarding (cost.ru_pi_rs_stall = 3).
  localparam logic [2:0] kPiRsStall = 3'd3;
  // A pruned entry leaves at RN with bypassing (RS, RN: 2 cycles), else at PI (4 cycles).
  localparam logic [2:0] kPruneBypassed = 3'd1, kPruneFull = 3'd3;

  always_ff @(posedge clk) begin
    if (rst) begin
      state <= IDLE;
      fwd_valid <= 1'b0;
      push_valid <= 1'b0;
      cnt_nodes <= 32'd0;
      cnt_pruned <= 32'd0;
    end else begin
      case (state)
        IDLE: if (tok_valid) begin
          state <= FQ;
          query <= tok_query;
          stack_base <= tok_stack_base;
          tok_started_q <= tok_started;
          sp <= tok_sp;
          fwd_valid <= 1'b0;
          push_valid <= 1'b0;
          root_written <= 1'b0;
          cnt_nodes <= 32'd0;
          cnt_pruned <= 32'd0;
        end
        FQ: begin
          if (fq_root && qs_wr_gnt) root_written <= 1'b1;
          if (fq_done) begin
            q_x <= qb_x;
            q_y <= qb_y;
            q_z <= qb_z;
            if (!tok_started_q) sp <= cfg_root_nonempty ? 16'd1 : 16'd0;
            state <= WALK;
          end
        end
        WALK: if (step_done) begin
          // The push this step carried is in the stack now.
          push_valid <= 1'b0;
          if (finish) begin
            state <= FIN_DRAIN;
            drain_left <= 2'd1;  // CD..CL behind the last node, then the result write-back
          end else if (pop && pruned) begin
            sp <= sp_eff - 16'd1;
            cnt_pruned <= cnt_pruned + 32'd1;
            fwd_valid <= 1'b0;
            wait_left <= cfg_bypassing ? kPruneBypassed : kPruneFull;
            state <= WAIT;
          end else begin
            if (node_is_leaf) begin  // CL: the directory entry was read; the query leaves
              leaf <= node - cfg_top_nodes;
              sp <= pop ? sp_eff - 16'd1 : sp_eff;
              fwd_valid <= 1'b0;
              drain_left <= 2'd0;
              state <= CL_DRAIN;
            end else begin
              cnt_nodes <= cnt_nodes + 32'd1;
              sp <= pop ? sp_eff - 16'd1 : sp_eff;
              push_valid <= far_nonempty;
              push_node <= far_child;
              push_plane2 <= plane2;
              fwd_valid <= near_nonempty;
              fwd_node <= near_child;
              if (!cfg_forwarding) begin
                wait_left <= kPiRsStall;
                state <= WAIT;
              end
            end
          end
        end
        WAIT: begin
          wait_left <= wait_left - 3'd1;
          if (wait_left == 3'd1) state <= WALK;
        end
        CL_DRAIN, FIN_DRAIN: begin
          if (drain_left == 2'd0) state <= IDLE;
          else drain_left <= drain_left - 2'd1;
        end
        default: state <= IDLE;
      endcase
    end
  end
endmodule
