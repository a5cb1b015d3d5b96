// What built this binary, for every output that says what made it: the source
// tree's commit, "-dirty" when tracked files differed from it, "unknown" without git.
#pragma once

namespace tigris {

const char* build_commit();

}  // namespace tigris
