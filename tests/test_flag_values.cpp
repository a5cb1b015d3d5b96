// The flag values the commands share (core/flag_values): each form accepted, and each wrong one
// refused with a message naming the flag and the form.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "core/flag_values.hpp"

using namespace tigris;
using Catch::Matchers::Contains;

TEST_CASE("flag values: --kitti-frames SOURCE,TARGET", "[flags]") {
  CHECK(parse_frame_pair("1,0") == std::pair<int, int>{1, 0});
  CHECK(parse_frame_pair("12,12") == std::pair<int, int>{12, 12});
  for (const char* bad : {"", "1", "1:0", "1,0,2", "1,0x", "-1,0", "1,-2", "a,b"})
    CHECK_THROWS_WITH(parse_frame_pair(bad), Contains("--kitti-frames must be SOURCE,TARGET") && Contains(bad));
}

TEST_CASE("flag values: --frames A:B within the sequence", "[flags]") {
  CHECK(parse_frame_range("", 10) == std::pair<std::size_t, std::size_t>{0, 9});
  CHECK(parse_frame_range("2:5", 10) == std::pair<std::size_t, std::size_t>{2, 5});
  CHECK(parse_frame_range("0:9", 10) == std::pair<std::size_t, std::size_t>{0, 9});
  for (const char* bad : {"5", "5:5", "6:5", "-1:3", "1,3", "1:3:4", "1:3x"})
    CHECK_THROWS_WITH(parse_frame_range(bad, 10), Contains("--frames must be A:B"));
  CHECK_THROWS_WITH(parse_frame_range("2:10", 10), Contains("the sequence has frames 0..9"));
}

TEST_CASE("flag values: a distance in metres", "[flags]") {
  CHECK(parse_number("--approx-thd", "1.2") == 1.2);
  CHECK(parse_number("--approx-thd", "0") == 0.0);
  for (const char* bad : {"", "x", "1.2m", "-0.5", "nan", "inf", "1e999"})
    CHECK_THROWS_WITH(parse_number("--approx-thd", bad), Contains("--approx-thd must be a number >= 0 (metres)"));
}

TEST_CASE("flag values: --inject-kth K", "[flags]") {
  CHECK(parse_kth("1") == 1);
  CHECK(parse_kth("100000") == 100000);
  for (const char* bad : {"", "0", "-3", "100001", "2.5", "3x", "99999999999999999999"})
    CHECK_THROWS_WITH(parse_kth(bad), Contains("--inject-kth must be an integer K in 1..100000"));
}

TEST_CASE("flag values: --inject-shell R1,R2 around the normal radius", "[flags]") {
  CHECK(parse_shell("0.1,0.4", 0.3) == std::pair<double, double>{0.1, 0.4});
  CHECK(parse_shell("0,0.5", 0.3) == std::pair<double, double>{0.0, 0.5});
  for (const char* bad : {"", "0.1", "0.1;0.4", "a,0.4", "0.1,nan", "0.1,0.4x"})
    CHECK_THROWS_WITH(parse_shell(bad, 0.3), Contains("--inject-shell must be R1,R2 in metres"));
  CHECK_THROWS_WITH(parse_shell("0.4,0.1", 0.3), Contains("needs 0 <= R1 < R2"));
  CHECK_THROWS_WITH(parse_shell("-0.1,0.4", 0.3), Contains("needs 0 <= R1 < R2"));
  CHECK_THROWS_WITH(parse_shell("0.3,0.4", 0.3), Contains("needs R1 < r < R2") && Contains("r = 0.3"));
  CHECK_THROWS_WITH(parse_shell("0.1,0.3", 0.3), Contains("needs R1 < r < R2"));
}
