// SupernodalCholesky::analyze: the symbolic factor (supernodal_cholesky.hpp).
#include <Eigen/OrderingMethods>
#include <algorithm>
#include <limits>

#include "corotate/solvers/supernodal_cholesky.hpp"

namespace corotate {

namespace {

// Relaxed amalgamation, CHOLMOD's defaults: a child merges into its parent when the merged
// supernode has at most kRelax[0] columns, or at most kRelax[1] with under kZeros[0] of its
// entries explicit zeros, or at most kRelax[2] with under kZeros[1], or any width under kZeros[2].
constexpr int kRelax[3] = {4, 16, 48};
constexpr double kZeros[3] = {0.8, 0.1, 0.05};

bool merge_pays(double columns, double zero_fraction) {
  return columns <= kRelax[0] || (columns <= kRelax[1] && zero_fraction < kZeros[0]) ||
         (columns <= kRelax[2] && zero_fraction < kZeros[1]) || zero_fraction < kZeros[2];
}

// Entries of a supernode's panel of `rows` rows and `cols` columns (its lower trapezoid).
double panel_entries(double rows, double cols) { return cols * rows - cols * (cols - 1) / 2; }

// Elimination tree of the matrix whose column j is A's column perm[j] (rows renumbered by
// inverse): Liu's algorithm with path compression. -1 marks a root.
std::vector<int> elimination_tree(const SupernodalCholesky::Matrix& A, const std::vector<int>& perm,
                                  const std::vector<int>& inverse) {
  const int n = static_cast<int>(perm.size());
  std::vector<int> parent(n, -1), ancestor(n, -1);
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (int k = 0; k < n; ++k)
    for (int p = outer[perm[k]]; p < outer[perm[k] + 1]; ++p)
      for (int i = inverse[inner[p]]; i != -1 && i < k;) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
  return parent;
}

// The nodes of a forest in postorder (children before parents, each subtree contiguous).
std::vector<int> postorder(const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  std::vector<int> head(n, -1), next(n, -1), order, stack;
  order.reserve(n);
  for (int j = n - 1; j >= 0; --j)  // children lists, ascending
    if (parent[j] >= 0) next[j] = head[parent[j]], head[parent[j]] = j;
  for (int root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int j = stack.back();
      if (head[j] >= 0) {  // descend into the next unvisited child
        const int child = head[j];
        head[j] = next[child];
        stack.push_back(child);
      } else {
        stack.pop_back();
        order.push_back(j);
      }
    }
  }
  return order;
}

// Whether A's pattern is made of whole 3 x 3 blocks (each node's three columns alike).
bool is_three_blocked(const SupernodalCholesky::Matrix& A) {
  const int n = static_cast<int>(A.rows());
  if (n % 3 != 0) return false;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (int c = 0; c < n; c += 3) {
    const int count = outer[c + 1] - outer[c];
    if (count % 3 != 0 || outer[c + 2] - outer[c + 1] != count || outer[c + 3] - outer[c + 2] != count) return false;
    for (int q = 0; q < 3; ++q)
      for (int p = outer[c + q], t = 0; p < outer[c + q + 1]; p += 3, t += 3)
        if (inner[p] % 3 != 0 || inner[p + 1] != inner[p] + 1 || inner[p + 2] != inner[p] + 2 ||
            inner[p] != inner[outer[c] + t])
          return false;
  }
  return true;
}

// AMD's order (new position -> column). On a matrix of 3 x 3 node blocks, AMD orders the node
// graph (a ninth of the entries: the 122,880-tet beam's analysis took 0.74 s on the scalar
// graph) and each node's three columns follow one another.
std::vector<int> amd_order_of(const SupernodalCholesky::Matrix& A) {
  const int n = static_cast<int>(A.rows());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> amd;
  if (!is_three_blocked(A)) {
    Eigen::AMDOrdering<int>()(A, amd);
    return std::vector<int>(amd.indices().data(), amd.indices().data() + n);
  }
  const int nodes = n / 3;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  std::vector<int> start(nodes + 1, 0), rows;
  rows.reserve(A.nonZeros() / 9);
  for (int v = 0; v < nodes; ++v) {
    for (int p = outer[3 * v]; p < outer[3 * v + 1]; p += 3) rows.push_back(inner[p] / 3);
    start[v + 1] = static_cast<int>(rows.size());
  }
  std::vector<double> ones(rows.size(), 1.0);
  const SupernodalCholesky::Matrix graph = Eigen::Map<const SupernodalCholesky::Matrix>(
      nodes, nodes, static_cast<int>(rows.size()), start.data(), rows.data(), ones.data());
  Eigen::AMDOrdering<int>()(graph, amd);
  std::vector<int> order;
  order.reserve(n);
  for (int k = 0; k < nodes; ++k)
    for (int c = 0; c < 3; ++c) order.push_back(3 * amd.indices()[k] + c);
  return order;
}

}  // namespace

void SupernodalCholesky::analyze(const Matrix& A) {
  if (!A.isCompressed() || A.rows() != A.cols())
    throw InvalidInput("supernodal Cholesky: A must be square, compressed");
  const int n = static_cast<int>(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();

  // 1. AMD, then the elimination tree's postorder on top of it (the same fill; each subtree
  // contiguous, so supernodes are column ranges and children come right before parents).
  {
    const std::vector<int> amd_order = amd_order_of(A);
    std::vector<int> amd_inverse(n);
    for (int k = 0; k < n; ++k) amd_inverse[amd_order[k]] = k;
    const std::vector<int> post = postorder(elimination_tree(A, amd_order, amd_inverse));
    perm_.resize(n);
    for (int k = 0; k < n; ++k) perm_[k] = amd_order[post[k]];
  }
  inverse_perm_.assign(n, 0);
  for (int k = 0; k < n; ++k) inverse_perm_[perm_[k]] = k;
  const std::vector<int> parent = elimination_tree(A, perm_, inverse_perm_);

  // 2. Column counts of L (diagonal included) by row subtrees: row i of L has its entries in
  // the columns on the tree paths from each k < i with A(i, k) != 0 up to i.
  std::vector<int> count(n, 1), mark(n, -1), children(n, 0);
  for (int i = 0; i < n; ++i) {
    mark[i] = i;
    for (int p = outer[perm_[i]]; p < outer[perm_[i] + 1]; ++p)
      for (int j = inverse_perm_[inner[p]]; j < i && mark[j] != i; j = parent[j]) {
        mark[j] = i;
        ++count[j];
      }
    if (parent[i] >= 0) ++children[parent[i]];
  }

  // 3. Fundamental supernodes (column j continues j - 1's when j - 1 is its only child and
  // has exactly j's rows besides itself), then relaxed amalgamation: a supernode merges into
  // its parent when it is the parent's last child (so the columns stay contiguous) and
  // merge_pays. Candidates ascend, so a merged supernode is judged whole by its own parent.
  std::vector<int> first;  // first column of each fundamental supernode
  for (int j = 0; j < n; ++j)
    if (j == 0 || parent[j - 1] != j || children[j] != 1 || count[j - 1] != count[j] + 1) first.push_back(j);
  const int nfund = static_cast<int>(first.size());
  first.push_back(n);
  std::vector<int> super_of(n);
  for (int s = 0; s < nfund; ++s)
    for (int j = first[s]; j < first[s + 1]; ++j) super_of[j] = s;
  // Per fundamental supernode (state of the merged supernode whose top it is): first column,
  // rows of its first column, entries and explicit zeros.
  std::vector<int> start(first.begin(), first.end() - 1), height(nfund);
  std::vector<double> zeros(nfund, 0.0);
  std::vector<char> absorbed(nfund, 0);
  for (int s = 0; s < nfund; ++s) height[s] = count[first[s]];
  for (int s = 0; s < nfund; ++s) {
    const int last = first[s + 1] - 1, up = parent[last];
    if (up < 0) continue;
    const int p = super_of[up];
    if (start[p] != last + 1) continue;  // not the parent's last child
    const double cols_s = last + 1 - start[s], cols_p = first[p + 1] - start[p];
    const double cols = cols_s + cols_p, rows = cols_s + height[p];
    const double real = panel_entries(height[s], cols_s) - zeros[s] + panel_entries(height[p], cols_p) - zeros[p];
    const double entries = panel_entries(rows, cols);
    if (!merge_pays(cols, (entries - real) / entries)) continue;
    absorbed[s] = 1;
    start[p] = start[s];
    height[p] = static_cast<int>(rows);
    zeros[p] = entries - real;
  }

  // 4. The supernodes (in column order, which is postorder), their parents and rows: their
  // own columns, then the rows below from A's columns and from the children's rows.
  super_.clear();
  std::vector<int> height_of;
  for (int s = 0; s < nfund; ++s)
    if (!absorbed[s]) super_.push_back(start[s]), height_of.push_back(height[s]);
  const int nsuper = static_cast<int>(super_.size());
  super_.push_back(n);
  for (int s = 0; s < nsuper; ++s)
    for (int j = super_[s]; j < super_[s + 1]; ++j) super_of[j] = s;
  first_child_.assign(nsuper, -1);
  next_sibling_.assign(nsuper, -1);
  for (int s = nsuper - 1; s >= 0; --s) {  // children lists, ascending (their order on the stack)
    const int up = parent[super_[s + 1] - 1];
    if (up < 0) continue;
    next_sibling_[s] = first_child_[super_of[up]];
    first_child_[super_of[up]] = s;
  }
  pi_.assign(1, 0);
  rows_.clear();
  std::fill(mark.begin(), mark.end(), -1);
  for (int s = 0; s < nsuper; ++s) {
    const int f = super_[s], l = super_[s + 1];
    const size_t begin = rows_.size();
    for (int j = f; j < l; ++j) rows_.push_back(j), mark[j] = s;
    auto add = [&](int i) {
      if (i >= l && mark[i] != s) mark[i] = s, rows_.push_back(i);
    };
    for (int j = f; j < l; ++j)
      for (int p = outer[perm_[j]]; p < outer[perm_[j] + 1]; ++p) add(inverse_perm_[inner[p]]);
    for (int c = first_child_[s]; c >= 0; c = next_sibling_[c])
      for (int p = pi_[c] + (super_[c + 1] - super_[c]); p < pi_[c + 1]; ++p) add(rows_[p]);
    std::sort(rows_.begin() + static_cast<std::ptrdiff_t>(begin) + (l - f), rows_.end());
    pi_.push_back(static_cast<int>(rows_.size()));
    if (static_cast<int>(rows_.size() - begin) != height_of[s])
      throw SolverFailure("supernodal Cholesky: inconsistent symbolic factor (a bug)");
  }

  // 5. Value offsets and the update-matrix stack: the children's updates are on top when
  // their parent is assembled, its own goes right above them and moves down once they are
  // added in.
  px_.assign(1, 0);
  children_start_.assign(nsuper, 0);
  update_start_.assign(nsuper, 0);
  size_t height_now = 0, stack_size = 0;
  for (int s = 0; s < nsuper; ++s) {
    const size_t k = super_[s + 1] - super_[s], m = pi_[s + 1] - pi_[s], below = m - k;
    if (static_cast<size_t>(px_.back()) + m * k > static_cast<size_t>(std::numeric_limits<int>::max()))
      throw InvalidInput("supernodal Cholesky: the factor has more than 2^31 entries");
    px_.push_back(static_cast<int>(px_.back() + m * k));
    size_t children_size = 0;
    for (int c = first_child_[s]; c >= 0; c = next_sibling_[c]) {
      const size_t b = static_cast<size_t>(pi_[c + 1] - pi_[c]) - (super_[c + 1] - super_[c]);
      children_size += b * b;
    }
    children_start_[s] = height_now - children_size;
    update_start_[s] = height_now;
    stack_size = std::max(stack_size, height_now + below * below);
    height_now = children_start_[s] + below * below;
  }
  values_.assign(px_.back(), 0.0);
  stack_.assign(stack_size, 0.0);
  relative_.assign(n, 0);
  map_.assign(n, 0);

  view_.n = n;
  view_.nsuper = nsuper;
  view_.perm = perm_.data();
  view_.super = super_.data();
  view_.pi = pi_.data();
  view_.px = px_.data();
  view_.rows = rows_.data();
  analysed_nonzeros_ = A.nonZeros();
}

}  // namespace corotate
