#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "sw_ref/results.hpp"
#include "traces/schedule_csv.hpp"
#include "traces/vcd_writer.hpp"

using namespace tigris;

namespace {

std::string temp_file(const std::string& name, const std::string& text) {
  const auto path =
      std::filesystem::temp_directory_path() / ("tigris_traces_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace

TEST_CASE("schedule CSV round-trips", "[traces]") {
  using Event = ScheduleEntry::Event;
  const Schedule s = {{0, 5}, {0, 6}, {3, 5}, {0, 5, Event::Finish}, {4294967294u, 0}};
  std::ostringstream csv;
  write_schedule_csv(csv, s);
  CHECK(csv.str().rfind("seq,query,leaf,event\n0,0,5,visit\n1,0,6,visit\n2,3,5,visit\n3,0,5,finish\n", 0) == 0);
  const std::string path = temp_file("ok.csv", csv.str());
  CHECK(read_schedule_csv(path) == s);
  std::filesystem::remove(path);
  // The earlier format without events: every row a visit.
  const std::string old = temp_file("old.csv", "seq,query,leaf\n0,0,5\n1,0,6\r\n");
  CHECK(read_schedule_csv(old) == Schedule{{0, 5}, {0, 6}});
  std::filesystem::remove(old);
}

TEST_CASE("bad schedule files name the file and line", "[traces]") {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"", ":1: expected the header"},
      {"seq,leaf,query\n0,1,2\n", ":1: expected the header"},
      {"seq,query,leaf\n0,1,2\n2,1,3\n", ":3: seq 2 out of order"},
      {"seq,query,leaf\n0,1\n", ":2: expected 'seq,query,leaf'"},
      {"seq,query,leaf\n0,-1,2\n", ":2:"},
      {"seq,query,leaf\n0,1,2,3\n", ":2:"},
      {"seq,query,leaf\n0,1,x\n", ":2:"},
      {"seq,query,leaf\n0,1,99999999999\n", "out of range"},
      {"seq,query,leaf,event\n0,1,2\n", ":2: expected 'seq,query,leaf,event'"},
      {"seq,query,leaf,event\n0,1,2,join\n", ":2:"},
      {"seq,query,leaf,event\n0,1,2,visit,\n", ":2:"},
      {"seq,query,leaf,event\n0,1,2,visit\n1,1,2,finish\n3,1,2,visit\n", ":4: seq 3 out of order"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string path = temp_file("bad" + std::to_string(i++) + ".csv", c.text);
    INFO(c.text);
    CHECK_THROWS_AS(read_schedule_csv(path), InputError);
    CHECK_THROWS_WITH(read_schedule_csv(path), Catch::Contains(path) && Catch::Contains(c.message));
    std::filesystem::remove(path);
  }
  CHECK_THROWS_WITH(read_schedule_csv("/nonexistent/schedule.csv"), Catch::Contains("/nonexistent/schedule.csv"));
}

TEST_CASE("results CSV prints dist2 so that it round-trips float32", "[results]") {
  Results r;
  const float awkward[] = {0.1f, 1.0f / 3.0f, 16777217.0f, 1e-30f, 0.0f};
  std::vector<Neighbor> q0;
  for (std::uint32_t i = 0; i < 5; ++i) q0.push_back({i * 7, awkward[i]});
  r.append_query(q0.data(), q0.data() + q0.size());
  r.append_query(nullptr, nullptr);  // a query with no neighbour has no row
  r.append_query(q0.data(), q0.data() + 1);
  std::ostringstream csv;
  write_results_csv(csv, r);
  std::istringstream in(csv.str());
  std::string line;
  std::getline(in, line);
  CHECK(line == "query,rank,index,dist2");
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  REQUIRE(rows.size() == 6);
  CHECK(rows[5].rfind("2,0,0,", 0) == 0);
  for (std::size_t i = 0; i < 5; ++i) {
    const std::string value = rows[i].substr(rows[i].rfind(',') + 1);
    const float back = std::strtof(value.c_str(), nullptr);
    CHECK(std::memcmp(&back, &awkward[i], sizeof back) == 0);
  }
}

TEST_CASE("first_difference names the first differing query", "[results]") {
  Results a, b;
  const Neighbor n1{3, 1.0f}, n2{4, 1.0f}, n3{3, std::nextafter(1.0f, 2.0f)};
  a.append_query(&n1, &n1 + 1);
  b.append_query(&n1, &n1 + 1);
  CHECK_FALSE(first_difference(a, b));
  a.append_query(&n1, &n1 + 1);
  b.append_query(&n2, &n2 + 1);
  REQUIRE(first_difference(a, b));
  CHECK_THAT(*first_difference(a, b), Catch::StartsWith("query 1:"));
  Results c = a;
  c.neighbors.back() = n3;  // same index, dist2 one ulp off
  CHECK(first_difference(a, c));
  Results d;
  d.append_query(&n1, &n1 + 1);
  CHECK_THAT(*first_difference(a, d), Catch::Contains("query counts differ"));
}

// Waveform changes booked ahead (an RU's SRAM stall after its pipeline cycles) and sums over
// units booked in any order come out in time order with the right values.
TEST_CASE("VcdWriter: booked changes and sums are written in time order", "[traces][vcd]") {
  const std::string path = "test_traces_booked.vcd";
  {
    tigris::VcdWriter vcd(path);
    const int a = vcd.add("top.a", 1), sum = vcd.add("top.sum", 8);
    vcd.change(a, 10, 1);         // now 10
    vcd.change_at(a, 30, 0, 10);  // booked for 30
    vcd.add_at(sum, 50, -2, 10);  // booked out of order
    vcd.add_at(sum, 20, 2, 10);
    vcd.add_at(sum, 40, 1, 10);
    vcd.change_at(a, 60, 1, 35);  // now 35: 30 may be written
    vcd.close();
  }
  std::ifstream f(path);
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::remove(path.c_str());
  const std::string body = text.substr(text.find("$end\n", text.find("$dumpvars")) + 5);
  // a is "!", sum is "\"": 10 a=1, 20 sum=2, 30 a=0, 40 sum=3, 50 sum=1, 60 a=1.
  CHECK(body == "#10\n1!\n#20\nb10 \"\n#30\n0!\n#40\nb11 \"\n#50\nb1 \"\n#60\n1!\n");
}
