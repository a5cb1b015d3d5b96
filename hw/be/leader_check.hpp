// The Leader Check of one Search Unit (paper section 5.3; docs/model.md), between the BE
// Query Buffer and the PEs: for a query at leaf L (its first leaf under first_leaf, every leaf
// under every_leaf) it computes the squared distance to
// each of L's leaders (on the PEs: the leaders stream past the batch's PEs like a Node Set),
// picks the closest (the first of equal distances, i.e. (dist2, arrival) order) and compares it
// with thd^2. Decisions are made one query at a time in the order they are recorded, so a query
// sees every leader appended before it, also by an earlier query of its own batch.
#pragma once

#include <cstdint>

#include "hw/observer.hpp"
#include "leader_buffer.hpp"

namespace tigris::hw {

class LeaderCheck {
 public:
  struct Decision {
    LeafVisit::Kind kind = LeafVisit::Kind::Leader;
    std::size_t leader = 0;  // the leader followed (Follower)
    std::uint32_t checks = 0;
  };

  LeaderCheck(StatGroup& su_stats, EnergyMeter& meter)
      : checks_(su_stats, "leader_check.checks", "count", "leader distances computed by the Leader Checks"),
        followers_(su_stats, "leader_check.followers", "count", "queries that followed a leader"),
        leaders_(su_stats, "leader_check.leaders", "count", "queries that became leaders"),
        full_(su_stats, "leader_check.leader_buffer_full", "count", "exact scans that found their leaf's leaders full"),
        energy_(meter.line("pe.leader_check", EnergyMeter::Component::Pe, meter.table().leader_check_pj)) {}

  // Follower of the closest leader within thd, else Leader (or LeaderBufferFull when L cannot
  // take another leader: the query is searched exactly and not remembered). With
  // `join_later` (first_leaf) a query that follows nobody is Exact: it searches on and its
  // record arrives when it has finished (joined()).
  Decision decide(const LeaderBuffer& buffer, std::uint32_t leaf, const Point3& q, float thd2, bool join_later) {
    Decision d;
    const auto& leaders = buffer.leaders(leaf);
    float best = 0.0f;
    for (std::size_t i = 0; i < leaders.size(); ++i) {
      const float dist = dist2(q, leaders[i].point);
      if (i == 0 || dist < best) best = dist, d.leader = i;
    }
    d.checks = static_cast<std::uint32_t>(leaders.size());
    checks_ += d.checks;
    energy_ += d.checks;
    if (!leaders.empty() && best < thd2) {
      d.kind = LeafVisit::Kind::Follower;
      ++followers_;
    } else if (join_later) {
      d.kind = LeafVisit::Kind::Exact;
    } else if (buffer.full(leaf)) {
      d.kind = LeafVisit::Kind::LeaderBufferFull;
      ++full_;
    } else {
      ++leaders_;
    }
    return d;
  }
  // first_leaf: a finished leader's record reached the Leader Buffer, which took it or was full.
  void joined(bool taken) {
    if (taken)
      ++leaders_;
    else
      ++full_;
  }

 private:
  Counter checks_, followers_, leaders_, full_;
  Counter& energy_;
};

}  // namespace tigris::hw
