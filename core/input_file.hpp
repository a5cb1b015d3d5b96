// The one way every command opens a file it reads (DESIGN 23): clouds, configurations, traces,
// poses, calibrations, schedules and a command's own earlier JSON. Symbolic links are resolved
// (a broken link or a loop is an error naming the link), only a regular file is read (a folder,
// FIFO, socket or device is an error naming its kind; a FIFO is never opened, so nothing
// blocks), the size is bounded, and the file is read whole. Errors are InputError (an
// std::invalid_argument: exit 2) starting with the path as given.
#pragma once

#include <cstdint>
#include <string>

namespace tigris {

constexpr std::uint64_t kMaxInputBytes = 4ull << 30;      // clouds, traces: 4 GiB
constexpr std::uint64_t kMaxSettingsBytes = 64ull << 20;  // JSON, poses, calib, CSV settings: 64 MiB

// Throws unless `path` names (through any links) a regular file of at most `max_bytes`;
// returns its size. `what` says what the file is for ("--config", "poses.txt").
std::uint64_t check_input(const std::string& path, const std::string& what, std::uint64_t max_bytes = kMaxInputBytes);

// check_input, then the whole file.
std::string read_input(const std::string& path, const std::string& what, std::uint64_t max_bytes = kMaxInputBytes);

}  // namespace tigris
