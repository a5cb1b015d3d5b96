// Error injection in the plug-in's searches (the paper's section "Quantifying the
// error-tolerance", Figure 5), off by default and exact on the exact back-ends (golden exact,
// FLANN):
//  - inject_kth = K > 1: a k-nearest search returns the neighbours of rank K .. K+k-1 in the
//    canonical (dist2, index) order instead of ranks 1 .. k, so an NN search (k = 1) returns the
//    K-th nearest neighbour. It searches k+K-1 neighbours and drops the first K-1; a cloud with
//    fewer than K points gives its farthest point (an NN search never comes back empty, which
//    PCL's CorrespondenceEstimation relies on).
//  - shell_outer > 0: a radius search returns every point with R1^2 <= dist2 <= R2^2 (R1 =
//    shell_inner, R2 = shell_outer, squared in float32 as r2 in docs/model.md's numeric contract), in
//    canonical order, then max_nn truncation, instead of the ball of the requested radius
//    (which is ignored). It searches the ball of R2 and drops the points closer than R1.
// On the approx back-end both would apply to the approximate results; the pipeline rejects that
// combination (pipeline_config.hpp, validate).
//
// Apart from the plug-in because the rules are the same whatever the point type and back-end:
// each widens the search before it runs and transforms one query's results after (the trace
// records the widened search, as issued).
#pragma once

#include <vector>

#include <pcl/types.h>

#include "search_settings.hpp"

namespace tigris::registration {

// A k-nearest search under inject_kth.
struct KthInjection {
  int skip = 0;  // the nearest ranks dropped (K - 1; 0: none)
  int want = 0;  // the neighbours searched: k + skip
};
KthInjection kth_injection(const SearchSettings& s, int k);

// Keeps ranks skip+1 .. skip+k of the `n` neighbours found (the farthest alone when there are
// no more than `skip`); returns how many are left.
int drop_nearest(const KthInjection& kth, int k, int n, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances);

// A radius search under the shell: what is searched instead of (radius, max_nn).
struct ShellInjection {
  bool shell = false;
  double radius = 0.0;      // R2 with the shell, else the requested radius
  unsigned int max_nn = 0;  // 0 (all of the ball) with the shell, else the requested max_nn
};
ShellInjection shell_injection(const SearchSettings& s, double radius, unsigned int max_nn);

// Keeps the `n` neighbours found with dist2 >= R1^2, at most `max_nn` of them (0: all), in
// order; returns how many are left.
int keep_shell(const SearchSettings& s, unsigned int max_nn, int n, pcl::Indices& k_indices,
               std::vector<float>& k_sqr_distances);

}  // namespace tigris::registration
