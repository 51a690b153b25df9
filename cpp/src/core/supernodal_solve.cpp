#include "supernodal_solve.h"

#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

namespace meshsmith::detail {

namespace {

/// The balance the cut aims for: the heavier group holds at most this share of the two.
constexpr double kBalance = 0.55;
/// The cut stops descending once the top holds this share of the factor.
constexpr double kTopShare = 0.2;

/// Greedy split of weighted items into two bins (heaviest first into the lighter bin); returns
/// each item's bin and the heavier bin's weight.
std::vector<int> two_bins(const std::vector<int>& items, const std::vector<double>& weight, double* heavier) {
  std::vector<int> by_weight(items.size());
  std::iota(by_weight.begin(), by_weight.end(), 0);
  std::sort(by_weight.begin(), by_weight.end(), [&](int a, int b) {
    return weight[items[a]] != weight[items[b]] ? weight[items[a]] > weight[items[b]] : items[a] < items[b];
  });
  std::vector<int> bin(items.size(), 0);
  double load[2] = {0.0, 0.0};
  for (int k : by_weight) {
    const int lighter = load[1] < load[0] ? 1 : 0;
    bin[k] = lighter;
    load[lighter] += weight[items[k]];
  }
  *heavier = std::max(load[0], load[1]);
  return bin;
}

/// The supernodal factor's arrays: columns super[q] .. super[q+1] of supernode q, its row
/// indices s[pi[q] .. pi[q+1]) and its values x[px[q] ..] (rows × columns, column-major).
struct FactorArrays {
  explicit FactorArrays(const cholmod_factor& factor)
      : super(static_cast<const int*>(factor.super)),
        pi(static_cast<const int*>(factor.pi)),
        px(static_cast<const int*>(factor.px)),
        s(static_cast<const int*>(factor.s)),
        x(static_cast<const double*>(factor.x)) {}
  const int *super, *pi, *px, *s;
  const double* x;
};

}  // namespace

SupernodalSolve::SupernodalSolve(const cholmod_factor& factor) : factor_(&factor), n_(static_cast<Eigen::Index>(factor.n)) {
  if (!factor.is_super || !factor.is_ll || factor.xtype != CHOLMOD_REAL || factor.itype != CHOLMOD_INT) {
    throw std::logic_error("SupernodalSolve: needs a real supernodal LL' factor with int indices");
  }
  const int ns = static_cast<int>(factor.nsuper);
  const FactorArrays arrays(factor);
  const int *super = arrays.super, *pi = arrays.pi, *px = arrays.px, *s = arrays.s;
  // The supernodal elimination tree: the parent of q holds q's first off-diagonal row (a column
  // after q's, so parents are numbered after their children).
  std::vector<int> supernode_of(static_cast<std::size_t>(n_));
  for (int q = 0; q < ns; ++q)
    for (int k = super[q]; k < super[q + 1]; ++k) supernode_of[k] = q;
  std::vector<int> parent(ns, -1), child_starts(ns + 1, 0), children(ns);
  std::vector<double> subtree(ns);
  for (int q = 0; q < ns; ++q) {
    const int columns = super[q + 1] - super[q], rows = pi[q + 1] - pi[q];
    if (rows > columns) parent[q] = supernode_of[s[pi[q] + columns]];
    subtree[q] += static_cast<double>(px[q + 1] - px[q]);
    if (parent[q] >= 0) {
      subtree[parent[q]] += subtree[q];
      ++child_starts[parent[q] + 1];
    }
  }
  std::partial_sum(child_starts.begin(), child_starts.end(), child_starts.begin());
  {
    std::vector<int> fill(child_starts.begin(), child_starts.end() - 1);
    for (int q = 0; q < ns; ++q)
      if (parent[q] >= 0) children[fill[parent[q]]++] = q;
  }
  double total = 0.0;
  std::vector<int> items;
  for (int q = 0; q < ns; ++q) {
    if (parent[q] < 0) {
      items.push_back(q);
      total += subtree[q];
    }
  }
  // Descend from the roots: replace the heaviest subtree by its children (its root joins the
  // top) until the subtrees split into two balanced groups.
  std::vector<char> in_top(ns, 0);
  double top_weight = 0.0, heavier = 0.0;
  std::vector<int> bin = two_bins(items, subtree, &heavier);
  while (!items.empty()) {
    double weight = 0.0;
    for (int q : items) weight += subtree[q];
    if (heavier <= kBalance * weight || top_weight > kTopShare * total) break;
    const auto heaviest = std::max_element(items.begin(), items.end(), [&](int a, int b) {
      return subtree[a] != subtree[b] ? subtree[a] < subtree[b] : a > b;
    });
    const int q = *heaviest;
    if (child_starts[q] == child_starts[q + 1]) break;  // a leaf: nothing to split
    items.erase(heaviest);
    in_top[q] = 1;
    top_weight += static_cast<double>(px[q + 1] - px[q]);
    for (int k = child_starts[q]; k < child_starts[q + 1]; ++k) items.push_back(children[k]);
    bin = two_bins(items, subtree, &heavier);
  }
  std::vector<int> group(ns, -1);  // 0, 1, or 2 for the top
  for (std::size_t k = 0; k < items.size(); ++k) group[items[k]] = bin[k];
  for (int q = ns - 1; q >= 0; --q) {
    if (in_top[q]) {
      group[q] = 2;
    } else if (group[q] < 0) {
      group[q] = parent[q] >= 0 ? group[parent[q]] : 0;
    }
  }
  top_row_.assign(static_cast<std::size_t>(n_), -1);
  for (int q = 0; q < ns; ++q) {
    if (group[q] == 2) {
      top_.push_back(q);
      for (int k = super[q]; k < super[q + 1]; ++k) top_row_[k] = static_cast<int>(top_rows_++);
    } else {
      group_[group[q]].push_back(q);
    }
  }
}

template <int C>
void SupernodalSolve::forward(const std::vector<int>& supernodes, double* Y, double* accumulator) const {
  const FactorArrays f(*factor_);
  const int *super = f.super, *pi = f.pi, *px = f.px, *s = f.s;
  const double* x = f.x;
  std::vector<double> buffer;
  std::vector<double*> at;
  for (int q : supernodes) {
    const int columns = super[q + 1] - super[q], rows = pi[q + 1] - pi[q];
    const int* row = s + pi[q];
    const double* L = x + px[q];  // rows × columns, column-major
    buffer.resize(static_cast<std::size_t>(rows) * C);
    at.resize(static_cast<std::size_t>(rows));
    // Rows of the top go to this thread's accumulator (they only receive updates here).
    for (int r = 0; r < rows; ++r) {
      const int top = accumulator ? top_row_[row[r]] : -1;
      at[r] = top >= 0 ? accumulator + static_cast<std::ptrdiff_t>(top) * C : Y + static_cast<std::ptrdiff_t>(row[r]) * C;
      for (int c = 0; c < C; ++c) buffer[r * C + c] = at[r][c];
    }
    double* __restrict b = buffer.data();
    for (int j = 0; j < columns; ++j) {
      const double* __restrict column = L + static_cast<std::ptrdiff_t>(j) * rows;
      double a[C];
      for (int c = 0; c < C; ++c) a[c] = b[j * C + c] /= column[j];
      for (int r = j + 1; r < rows; ++r) {
        const double l = column[r];
        for (int c = 0; c < C; ++c) b[r * C + c] -= l * a[c];
      }
    }
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < C; ++c) at[r][c] = buffer[r * C + c];
  }
}

template <int C>
void SupernodalSolve::backward(const std::vector<int>& supernodes, double* Y) const {
  const FactorArrays f(*factor_);
  const int *super = f.super, *pi = f.pi, *px = f.px, *s = f.s;
  const double* x = f.x;
  std::vector<double> buffer;
  for (auto it = supernodes.rbegin(); it != supernodes.rend(); ++it) {
    const int q = *it;
    const int columns = super[q + 1] - super[q], rows = pi[q + 1] - pi[q];
    const int* row = s + pi[q];
    const double* L = x + px[q];
    buffer.resize(static_cast<std::size_t>(rows) * C);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < C; ++c) buffer[r * C + c] = Y[static_cast<std::ptrdiff_t>(row[r]) * C + c];
    double* __restrict b = buffer.data();
    for (int j = columns - 1; j >= 0; --j) {
      const double* __restrict column = L + static_cast<std::ptrdiff_t>(j) * rows;
      // Two partial sums per column of b (independent chains; the order is fixed).
      double even[C], odd[C];
      for (int c = 0; c < C; ++c) even[c] = odd[c] = 0.0;
      int r = j + 1;
      for (; r + 1 < rows; r += 2) {
        const double l0 = column[r], l1 = column[r + 1];
        for (int c = 0; c < C; ++c) {
          even[c] += l0 * b[r * C + c];
          odd[c] += l1 * b[(r + 1) * C + c];
        }
      }
      if (r < rows) {
        for (int c = 0; c < C; ++c) even[c] += column[r] * b[r * C + c];
      }
      for (int c = 0; c < C; ++c) b[j * C + c] = (b[j * C + c] - (even[c] + odd[c])) / column[j];
    }
    for (int j = 0; j < columns; ++j)
      for (int c = 0; c < C; ++c) Y[static_cast<std::ptrdiff_t>(super[q] + j) * C + c] = buffer[j * C + c];
  }
}

template <int C>
void SupernodalSolve::substitute(double* Y) const {
  std::vector<double> accumulators[2];
  for (auto& accumulator : accumulators) accumulator.assign(static_cast<std::size_t>(top_rows_) * C, 0.0);
  tbb::parallel_invoke([&] { forward<C>(group_[0], Y, accumulators[0].data()); },
                       [&] { forward<C>(group_[1], Y, accumulators[1].data()); });
  for (std::size_t k = 0; k < top_row_.size(); ++k) {
    const int top = top_row_[k];
    if (top < 0) continue;
    for (int c = 0; c < C; ++c) {
      Y[k * C + c] += accumulators[0][static_cast<std::size_t>(top) * C + c] + accumulators[1][static_cast<std::size_t>(top) * C + c];
    }
  }
  forward<C>(top_, Y, nullptr);
  backward<C>(top_, Y);
  tbb::parallel_invoke([&] { backward<C>(group_[0], Y); }, [&] { backward<C>(group_[1], Y); });
}

Eigen::MatrixXd SupernodalSolve::solve(const Eigen::Ref<const Eigen::MatrixXd>& b) const {
  if (b.rows() != n_) throw std::logic_error("SupernodalSolve: the right-hand side has the wrong number of rows");
  const int* permutation = static_cast<const int*>(factor_->Perm);
  Eigen::MatrixXd x(n_, b.cols());
  std::vector<double> Y;
  for (Eigen::Index first = 0; first < b.cols(); first += 4) {
    const int width = static_cast<int>(std::min<Eigen::Index>(4, b.cols() - first));
    Y.resize(static_cast<std::size_t>(n_) * width);
    for (Eigen::Index k = 0; k < n_; ++k) {
      const Eigen::Index source = permutation ? permutation[k] : k;
      for (int c = 0; c < width; ++c) Y[k * width + c] = b(source, first + c);
    }
    switch (width) {
      case 1: substitute<1>(Y.data()); break;
      case 2: substitute<2>(Y.data()); break;
      case 3: substitute<3>(Y.data()); break;
      default: substitute<4>(Y.data()); break;
    }
    for (Eigen::Index k = 0; k < n_; ++k) {
      const Eigen::Index target = permutation ? permutation[k] : k;
      for (int c = 0; c < width; ++c) x(target, first + c) = Y[k * width + c];
    }
  }
  return x;
}

}  // namespace meshsmith::detail
