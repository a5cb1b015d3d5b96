// Reading back a results dump (docs/cli.md; write_results_csv writes it): CSV header
// `query,rank,index,dist2`, one row per neighbour in canonical order, queries in index order,
// dist2 as %.9g (round-trips float32).
#pragma once

#include <cstddef>
#include <string>

#include "sw_ref/cloud.hpp"  // InputError
#include "sw_ref/results.hpp"

namespace tigris {

// Parses a results CSV held in memory. Rows must come as write_results_csv writes them: query
// numbers non-decreasing, rank 0, 1, ... within a query, index a uint32 below 2^32 - 1, dist2 a
// finite non-negative decimal number, each query's neighbours in canonical (dist2, index) order
// without a repeated index. Lines end in LF or CRLF; empty lines are skipped. A query with no
// row has no neighbour; `num_queries` (0: the last query's number + 1, at most 2^24) sets how
// many queries the result holds, and a row of a query beyond it is an error. Throws InputError naming `label` and
// the line.
Results parse_results_csv(const char* data, std::size_t size, const std::string& label, std::size_t num_queries = 0);

// Reads a results CSV file (as parse_results_csv).
Results read_results_csv(const std::string& path, std::size_t num_queries = 0);

}  // namespace tigris
