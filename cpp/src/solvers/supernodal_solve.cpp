#include "corotate/solvers/supernodal_solve.hpp"

#include <algorithm>

#include "corotate/parallel.hpp"

namespace corotate {

SupernodalSplit SupernodalSplit::of(const SupernodalFactor& L) {
  const Index S = L.nsuper;
  SupernodalSplit split;
  std::vector<Index> super_of_column(L.n);
  for (Index s = 0; s < S; ++s)
    for (int c = L.super[s]; c < L.super[s + 1]; ++c) super_of_column[c] = s;
  // Parent: the supernode of the first row below the panel's own columns (S: a virtual root
  // above the roots). Work: the panel's entries, each read once per sweep.
  std::vector<Index> parent(S), size(S + 1, 1);
  std::vector<double> work(S + 1, 0.0);
  std::vector<std::vector<Index>> children(S + 1);
  for (Index s = 0; s < S; ++s) {
    const int cols = L.super[s + 1] - L.super[s], height = L.pi[s + 1] - L.pi[s];
    split.max_below = std::max<Index>(split.max_below, height - cols);
    parent[s] = height > cols ? super_of_column[L.rows[L.pi[s] + cols]] : S;
    children[parent[s]].push_back(s);
    work[s] += static_cast<double>(height) * cols;
  }
  // The split needs postorder (CHOLMOD's default): children before their parent, each
  // subtree the range [root - size + 1, root]. Otherwise all of it is top: one thread.
  auto all_on_top = [&] {
    split.bins[0].clear();
    split.bins[1].clear();
    split.top.resize(S);
    for (Index s = 0; s < S; ++s) split.top[s] = s;
    split.row_on_top.assign(L.n, 1);
    return split;
  };
  for (Index s = 0; s < S; ++s) {
    if (parent[s] <= s) return all_on_top();
    size[parent[s]] += size[s];
    work[parent[s]] += work[s];  // work[v]: of v's whole subtree
  }
  for (Index s = 0; s < S; ++s)
    if (s - size[s] < parent[s] - size[parent[s]]) return all_on_top();

  // Frontier: start from the roots; while the heaviest subtree is more than the bins can
  // balance (over half the frontier's work), move its root to the top and its children to
  // the frontier. Then the subtrees go heaviest first to the lighter bin.
  std::vector<Index> frontier = children[S], top;
  auto heaviest_first = [&](Index a, Index b) { return work[a] > work[b] || (work[a] == work[b] && a < b); };
  for (int expansions = 0; expansions < 256 && !frontier.empty(); ++expansions) {
    std::sort(frontier.begin(), frontier.end(), heaviest_first);
    double total = 0;
    for (Index v : frontier) total += work[v];
    const Index heaviest = frontier.front();
    if (work[heaviest] <= 0.55 * total || children[heaviest].empty()) break;
    frontier.erase(frontier.begin());
    top.push_back(heaviest);
    frontier.insert(frontier.end(), children[heaviest].begin(), children[heaviest].end());
  }
  std::sort(frontier.begin(), frontier.end(), heaviest_first);
  double bin_work[2] = {0, 0};
  for (Index v : frontier) {
    const int bin = bin_work[1] < bin_work[0] ? 1 : 0;
    bin_work[bin] += work[v];
    split.bins[bin].emplace_back(v - size[v] + 1, v + 1);
  }
  for (auto& bin : split.bins) std::sort(bin.begin(), bin.end());
  // The top: every supernode in no frontier subtree (the expanded ones, and nothing else
  // when the frontier covers the rest), ascending.
  std::vector<char> in_frontier(S, 0);
  for (const auto& bin : split.bins)
    for (const auto& [first, last] : bin) std::fill(in_frontier.begin() + first, in_frontier.begin() + last, 1);
  split.row_on_top.assign(L.n, 0);
  for (Index s = 0; s < S; ++s)
    if (!in_frontier[s]) {
      split.top.push_back(s);
      std::fill(split.row_on_top.begin() + L.super[s], split.row_on_top.begin() + L.super[s + 1], 1);
    }
  return split;
}

namespace {

template <typename Scalar>
using Panel = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>, 0, Eigen::OuterStride<>>;

// L y' = y on supernode s; its updates of top rows go to top_updates when given.
template <typename Scalar, class Vector>
inline void forward_supernode(const SupernodalFactor& L, const Scalar* values, Index s, Vector& y, Vector& gathered,
                              const char* row_on_top, Vector* top_updates) {
  const int cols = L.super[s + 1] - L.super[s], height = L.pi[s + 1] - L.pi[s], below = height - cols;
  const Panel<Scalar> panel(values + L.px[s], height, cols, Eigen::OuterStride<>(height));
  auto ys = y.segment(L.super[s], cols);
  panel.topRows(cols).template triangularView<Eigen::Lower>().solveInPlace(ys);
  if (below == 0) return;
  auto update = gathered.head(below);
  update.noalias() = panel.bottomRows(below) * ys;
  const int* below_rows = L.rows + L.pi[s] + cols;
  if (top_updates == nullptr) {
    for (int r = 0; r < below; ++r) y[below_rows[r]] -= update[r];
    return;
  }
  for (int r = 0; r < below; ++r) {
    const int row = below_rows[r];
    if (row_on_top[row]) (*top_updates)[row] += update[r];
    else y[row] -= update[r];
  }
}

// L^T y' = y on supernode s.
template <typename Scalar, class Vector>
inline void backward_supernode(const SupernodalFactor& L, const Scalar* values, Index s, Vector& y, Vector& gathered) {
  const int cols = L.super[s + 1] - L.super[s], height = L.pi[s + 1] - L.pi[s], below = height - cols;
  const Panel<Scalar> panel(values + L.px[s], height, cols, Eigen::OuterStride<>(height));
  auto ys = y.segment(L.super[s], cols);
  if (below > 0) {
    auto known = gathered.head(below);
    const int* below_rows = L.rows + L.pi[s] + cols;
    for (int r = 0; r < below; ++r) known[r] = y[below_rows[r]];
    ys.noalias() -= panel.bottomRows(below).transpose() * known;
  }
  panel.topRows(cols).template triangularView<Eigen::Lower>().transpose().solveInPlace(ys);
}

}  // namespace

template <typename Scalar>
void supernodal_solve(const SupernodalFactor& L, const SupernodalSplit& split, const Scalar* values, const Vec& b,
                      Vec& x, SupernodalWork<Scalar>& work) {
  const Index n = L.n;
  auto& y = work.y;
  y.resize(n);
  for (int g = 0; g < 2; ++g) {
    work.gathered[g].resize(split.max_below);
    work.top_updates[g].setZero(n);
  }
  for (Index k = 0; k < n; ++k) y[k] = static_cast<Scalar>(b[L.perm[k]]);
  const char* on_top = split.row_on_top.data();
  // The two bins on two threads: worth the fork from a few thousand unknowns on.
  COROTATE_PARALLEL_FOR(n >= 2000)
  for (int g = 0; g < 2; ++g)
    for (const auto& [first, last] : split.bins[g])
      for (Index s = first; s < last; ++s)
        forward_supernode(L, values, s, y, work.gathered[g], on_top, &work.top_updates[g]);
  for (int g = 0; g < 2; ++g) y -= work.top_updates[g];  // zero off the top rows
  for (Index s : split.top)
    forward_supernode(L, values, s, y, work.gathered[0], on_top, static_cast<decltype(&y)>(nullptr));
  for (auto s = split.top.rbegin(); s != split.top.rend(); ++s) backward_supernode(L, values, *s, y, work.gathered[0]);
  COROTATE_PARALLEL_FOR(n >= 2000)
  for (int g = 0; g < 2; ++g)
    for (auto range = split.bins[g].rbegin(); range != split.bins[g].rend(); ++range)
      for (Index s = range->second - 1; s >= range->first; --s) backward_supernode(L, values, s, y, work.gathered[g]);
  x.resize(n);
  for (Index k = 0; k < n; ++k) x[L.perm[k]] = y[k];
}

template void supernodal_solve<float>(const SupernodalFactor&, const SupernodalSplit&, const float*, const Vec&, Vec&,
                                      SupernodalWork<float>&);
template void supernodal_solve<double>(const SupernodalFactor&, const SupernodalSplit&, const double*, const Vec&, Vec&,
                                       SupernodalWork<double>&);

}  // namespace corotate
