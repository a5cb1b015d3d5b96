// The schedule trace (docs/cli.md, tigris ref): CSV `seq,query,leaf,event`, one row per non-empty
// leaf visit (`visit`) or first_leaf leader's finish (`finish`) in decision order, seq counting
// from 0. The golden model replays it (`--schedule`). Files of the earlier `seq,query,leaf`
// format (visits only) are read too.
#pragma once

#include <iosfwd>
#include <string>

#include "sw_ref/cloud.hpp"  // InputError
#include "sw_ref/schedule.hpp"

namespace tigris {

void write_schedule_csv(std::ostream& out, const Schedule& schedule);

// Throws InputError naming the file and line on a bad header, a malformed row, or a seq that
// does not count up from 0.
Schedule read_schedule_csv(const std::string& path);

// The same from a stream; `label` stands for the path in messages (the fuzz target uses it).
Schedule read_schedule_csv(std::istream& in, const std::string& label);

}  // namespace tigris
