#include "corotate/fem/sweep_schedule.hpp"

#include <algorithm>

namespace corotate {

namespace {

struct Dissection {
  const int* cells;
  int per_element;
  Index num_elements, chunk_size;
  int depth;
  Index min_leaf;
  std::vector<Index> touched_by;  // per node: the last split that marked it
  Index split_id = 0;
  SweepSchedule* out;

  template <class F>
  void for_nodes(int chunk, const F& f) const {
    const Index first = Index(chunk) * chunk_size, last = std::min(num_elements, first + chunk_size);
    for (Index k = first * per_element; k < last * per_element; ++k) f(cells[k]);
  }

  // Places chunks (ascending) split `level` times from the top; returns nothing, fills out.
  void place(const std::vector<int>& chunks, int level) {
    if (chunks.empty()) return;
    if (level == depth || Index(chunks.size()) < 2 * min_leaf) {
      out->phases[0].push_back(chunks);
      return;
    }
    const size_t mid = chunks.size() / 2;
    const Index id = ++split_id;
    for (size_t i = 0; i < mid; ++i) for_nodes(chunks[i], [&](int v) { touched_by[v] = id; });
    std::vector<int> left(chunks.begin(), chunks.begin() + mid), right, separator;
    for (size_t i = mid; i < chunks.size(); ++i) {
      bool shares = false;
      for_nodes(chunks[i], [&](int v) { shares = shares || touched_by[v] == id; });
      (shares ? separator : right).push_back(chunks[i]);
    }
    place(left, level + 1);
    place(right, level + 1);
    // The deepest splits' separators run first (phase 1), the top one last (phase depth).
    if (!separator.empty()) out->phases[depth - level].push_back(separator);
  }
};

}  // namespace

SweepSchedule schedule_sweep(const int* cells, int nodes_per_element, Index num_elements, Index num_nodes,
                             Index chunk_size, int depth, Index min_leaf_chunks) {
  if (chunk_size < 1 || depth < 0 || min_leaf_chunks < 1)
    throw InvalidInput("schedule_sweep: chunk size, depth and leaf size must be positive");
  SweepSchedule s;
  s.num_chunks = (num_elements + chunk_size - 1) / chunk_size;
  s.phases.resize(depth + 1);
  Dissection d{
      cells, nodes_per_element, num_elements, chunk_size, depth, min_leaf_chunks, std::vector<Index>(num_nodes, 0), 0,
      &s};
  std::vector<int> all(s.num_chunks);
  for (Index c = 0; c < s.num_chunks; ++c) all[c] = static_cast<int>(c);
  d.place(all, 0);
  s.phases.erase(std::remove_if(s.phases.begin(), s.phases.end(), [](const auto& p) { return p.empty(); }),
                 s.phases.end());
  return s;
}

}  // namespace corotate
