#include "command.hpp"

#include <algorithm>
#include <stdexcept>

namespace tigris {
namespace {

// A function-local list: registrations in other files run before main() in any order.
std::vector<CommandInfo>& registry() {
  static std::vector<CommandInfo> list;
  return list;
}

}  // namespace

CommandRegistration::CommandRegistration(CommandInfo info) {
  for (const CommandInfo& c : registry())
    if (c.name == info.name) throw std::logic_error("tigris command '" + info.name + "' registered twice");
  registry().push_back(std::move(info));
}

std::vector<const CommandInfo*> commands() {
  std::vector<const CommandInfo*> out;
  for (const CommandInfo& c : registry()) out.push_back(&c);
  std::stable_sort(out.begin(), out.end(),
                   [](const CommandInfo* a, const CommandInfo* b) { return a->order < b->order; });
  return out;
}

}  // namespace tigris
