// The two choices of approximate search (docs/model.md, approximate search), shared by the
// golden model and the accelerator's configuration.
#pragma once

#include <string>

namespace tigris {

// Where approximate search checks leaders.
// FirstLeaf: the authors' code: at the query's first leaf only; a follower takes its leader's
// final results and stops; a leader joins its first leaf when its search has finished.
// EveryLeaf: the earlier reading: at every leaf visit, a leader's list local to the leaf.
enum class LeaderScope { FirstLeaf, EveryLeaf };
LeaderScope parse_leader_scope(const std::string& name);  // "first_leaf" | "every_leaf"
const char* to_string(LeaderScope scope);

// first_leaf: what a query's Leader Check sees of leaders still searching.
// Wait: a query becomes a leader of its first leaf at its check (up to the capacity), so later
// queries see it at once; one that follows it waits for its final results. Only the order of
// the checks matters. FinishedOnly: a leader joins when its search has finished; until then
// nobody sees it (the schedule records the finishes).
enum class LeaderInFlight { Wait, FinishedOnly };
LeaderInFlight parse_leader_in_flight(const std::string& name);  // "wait" | "finished_only"
const char* to_string(LeaderInFlight policy);

}  // namespace tigris
