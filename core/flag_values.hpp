// Values of flags that are more than one number (frame pairs and ranges, radius shells), parsed
// with errors that name the flag and show the expected form: std::invalid_argument, which the
// commands report with exit 2.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

namespace tigris {

// --height: a whole number from 0 to 30, or "full" (-1).
int parse_height(const std::string& text);

// --kitti-frames SOURCE,TARGET: two frame numbers >= 0 ("1,0").
std::pair<int, int> parse_frame_pair(const std::string& text);

// --frames A:B of a sequence of `scans` frames: 0 <= A < B < scans; empty: every frame.
std::pair<std::size_t, std::size_t> parse_frame_range(const std::string& text, std::size_t scans);

// A distance in metres given to `flag`: a finite number >= 0, nothing after it.
double parse_number(const std::string& flag, const std::string& text);

// --inject-kth K: an integer in 1..100000 (1: the nearest, no error).
int parse_kth(const std::string& text);

// --inject-shell R1,R2 around the normal radius r: 0 <= R1 < r < R2.
std::pair<double, double> parse_shell(const std::string& text, double r);

}  // namespace tigris
