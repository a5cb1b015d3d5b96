#include "injection.hpp"

#include <algorithm>
#include <cstddef>

namespace tigris::registration {

KthInjection kth_injection(const SearchSettings& s, int k) {
  KthInjection kth;
  kth.skip = s.injects_kth() && k >= 1 ? s.inject_kth - 1 : 0;
  kth.want = k + kth.skip;
  return kth;
}

int drop_nearest(const KthInjection& kth, int k, int n, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances) {
  if (kth.skip <= 0 || n <= 0) return n;
  const int drop = std::min(kth.skip, n - 1);
  const int keep = std::min(n - drop, k);
  k_indices.erase(k_indices.begin(), k_indices.begin() + drop);
  k_sqr_distances.erase(k_sqr_distances.begin(), k_sqr_distances.begin() + drop);
  k_indices.resize(static_cast<std::size_t>(keep));
  k_sqr_distances.resize(static_cast<std::size_t>(keep));
  return keep;
}

ShellInjection shell_injection(const SearchSettings& s, double radius, unsigned int max_nn) {
  ShellInjection shell;
  shell.shell = s.injects_shell();
  shell.radius = shell.shell ? static_cast<double>(s.shell_outer) : radius;
  shell.max_nn = shell.shell ? 0u : max_nn;
  return shell;
}

int keep_shell(const SearchSettings& s, unsigned int max_nn, int n, pcl::Indices& k_indices,
               std::vector<float>& k_sqr_distances) {
  const float r1_2 = s.shell_inner * s.shell_inner;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
    if (!(k_sqr_distances[i] >= r1_2)) continue;
    if (max_nn > 0 && kept == max_nn) break;
    k_indices[kept] = k_indices[i];
    k_sqr_distances[kept] = k_sqr_distances[i];
    ++kept;
  }
  k_indices.resize(kept);
  k_sqr_distances.resize(kept);
  return static_cast<int>(kept);
}

}  // namespace tigris::registration
