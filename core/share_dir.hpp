// Where the binary's data lives: PREFIX/share/tigris beside PREFIX/bin/tigris, in the build tree
// (symbolic links to the source's folders) as in an install, so a prefix works wherever it is
// copied. No source path is compiled in.
#pragma once

#include <string>

namespace tigris {

// This process's executable ("" when /proc/self/exe cannot be read).
std::string self_path();
// PREFIX/share/tigris for the executable at PREFIX/bin/.
std::string share_dir();

}  // namespace tigris
