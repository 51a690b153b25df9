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

namespace {

/// One row of the right-hand sides' block: C values in one SIMD register (GCC/Clang vector
/// extensions; lowered to SSE2 pairs by default, to one AVX register in the avx2 clones below;
/// aligned(8): the storage is plain doubles, so accesses are unaligned).
template <int C>
struct RowOf;
template <>
struct RowOf<1> {
  using type = double;
};
template <>
struct RowOf<2> {
  typedef double type __attribute__((vector_size(16), aligned(8)));
};
template <>
struct RowOf<4> {
  typedef double type __attribute__((vector_size(32), aligned(8)));
};

template <int C>
using Row = typename RowOf<C>::type;

template <int C>
inline bool all_zero(const Row<C>* rows, std::ptrdiff_t count) {
  const double* values = reinterpret_cast<const double*>(rows);
  for (std::ptrdiff_t k = 0; k < count * C; ++k)
    if (values[k] != 0.0) return false;
  return true;
}

/// The forward substitution over `supernodes` (increasing). Rows of the top go to `accumulator`
/// (indexed by top_row) when it is given. Supernodes whose own rows are still zero are skipped.
template <int C>
__attribute__((always_inline)) inline void forward_pass(const FactorArrays& f, const std::vector<int>& supernodes,
                                                        const int* top_row, Row<C>* Y, Row<C>* accumulator) {
  const int *super = f.super, *pi = f.pi, *px = f.px, *s = f.s;
  std::vector<double> buffer_storage;
  std::vector<double*> at;
  for (int q : supernodes) {
    // A supernode whose own rows are still all zero (no right-hand side there and no update
    // from below) contributes nothing: skipped without reading its part of the factor.
    if (all_zero<C>(Y + super[q], super[q + 1] - super[q])) continue;
    const int columns = super[q + 1] - super[q], rows = pi[q + 1] - pi[q];
    const int* row = s + pi[q];
    const double* L = f.x + px[q];  // rows × columns, column-major
    buffer_storage.resize(static_cast<std::size_t>(rows) * C);
    at.resize(static_cast<std::size_t>(rows));
    Row<C>* __restrict b = reinterpret_cast<Row<C>*>(buffer_storage.data());
    for (int r = 0; r < rows; ++r) {
      const int top = accumulator ? top_row[row[r]] : -1;
      at[r] = reinterpret_cast<double*>(top >= 0 ? accumulator + top : Y + row[r]);
      b[r] = *reinterpret_cast<const Row<C>*>(at[r]);
    }
    int j = 0;
    for (; j + 1 < columns; j += 2) {  // two columns per sweep: b read and written once for both
      const double* __restrict c0 = L + static_cast<std::ptrdiff_t>(j) * rows;
      const double* __restrict c1 = c0 + rows;
      const Row<C> a0 = b[j] / c0[j];
      b[j] = a0;
      const Row<C> a1 = (b[j + 1] - c0[j + 1] * a0) / c1[j + 1];
      b[j + 1] = a1;
      for (int r = j + 2; r < rows; ++r) b[r] = (b[r] - c0[r] * a0) - c1[r] * a1;
    }
    if (j < columns) {
      const double* __restrict c0 = L + static_cast<std::ptrdiff_t>(j) * rows;
      const Row<C> a0 = b[j] / c0[j];
      b[j] = a0;
      for (int r = j + 1; r < rows; ++r) b[r] = b[r] - c0[r] * a0;
    }
    for (int r = 0; r < rows; ++r) *reinterpret_cast<Row<C>*>(at[r]) = b[r];
  }
}

/// The back substitution over `supernodes`, in decreasing order.
template <int C>
__attribute__((always_inline)) inline void backward_pass(const FactorArrays& f, const std::vector<int>& supernodes,
                                                         Row<C>* Y) {
  const int *super = f.super, *pi = f.pi, *px = f.px, *s = f.s;
  std::vector<double> buffer_storage;
  for (auto it = supernodes.rbegin(); it != supernodes.rend(); ++it) {
    const int q = *it;
    const int columns = super[q + 1] - super[q], rows = pi[q + 1] - pi[q];
    const int* row = s + pi[q];
    const double* L = f.x + px[q];
    buffer_storage.resize(static_cast<std::size_t>(rows) * C);
    Row<C>* __restrict b = reinterpret_cast<Row<C>*>(buffer_storage.data());
    for (int r = columns; r < rows; ++r) b[r] = Y[row[r]];
    for (int r = 0; r < columns; ++r) b[r] = Y[super[q] + r];
    int j = columns - 1;
    // Two columns per sweep (j and j − 1 share the loads of b), two partial sums per column:
    // four independent chains of additions, so the loop is not bound by their latency.
    for (; j >= 1; j -= 2) {
      const double* __restrict c1 = L + static_cast<std::ptrdiff_t>(j) * rows;
      const double* __restrict c0 = c1 - rows;
      Row<C> even1 = Row<C>{} * 0.0, odd1 = even1, even0 = even1, odd0 = even1;
      int r = j + 1;
      for (; r + 1 < rows; r += 2) {
        even1 += c1[r] * b[r];
        even0 += c0[r] * b[r];
        odd1 += c1[r + 1] * b[r + 1];
        odd0 += c0[r + 1] * b[r + 1];
      }
      if (r < rows) {
        even1 += c1[r] * b[r];
        even0 += c0[r] * b[r];
      }
      b[j] = (b[j] - (even1 + odd1)) / c1[j];
      b[j - 1] = (b[j - 1] - ((even0 + odd0) + c0[j] * b[j])) / c0[j - 1];
    }
    if (j == 0) {
      const double* __restrict column = L;
      Row<C> even = Row<C>{} * 0.0, odd = even;
      int r = 1;
      for (; r + 1 < rows; r += 2) {
        even += column[r] * b[r];
        odd += column[r + 1] * b[r + 1];
      }
      if (r < rows) even += column[r] * b[r];
      b[0] = (b[0] - (even + odd)) / column[0];
    }
    for (int j = 0; j < columns; ++j) Y[super[q] + j] = b[j];
  }
}

/// The passes compiled twice: for the baseline ISA (SSE2 on x86-64) and, chosen at run time
/// when the processor has it, AVX2 (one 4-wide register per row). No FMA contraction in either
/// (the avx2 target has no fma), so both give the same bits.
template <int C>
void forward_default(const FactorArrays& f, const std::vector<int>& supernodes, const int* top_row, Row<C>* Y,
                     Row<C>* accumulator) {
  forward_pass<C>(f, supernodes, top_row, Y, accumulator);
}
template <int C>
void backward_default(const FactorArrays& f, const std::vector<int>& supernodes, Row<C>* Y) {
  backward_pass<C>(f, supernodes, Y);
}
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MESHSMITH_AVX2_CLONES 1
template <int C>
__attribute__((target("avx2"))) void forward_avx2(const FactorArrays& f, const std::vector<int>& supernodes,
                                                  const int* top_row, Row<C>* Y, Row<C>* accumulator) {
  forward_pass<C>(f, supernodes, top_row, Y, accumulator);
}
template <int C>
__attribute__((target("avx2"))) void backward_avx2(const FactorArrays& f, const std::vector<int>& supernodes,
                                                   Row<C>* Y) {
  backward_pass<C>(f, supernodes, Y);
}
#endif

bool use_avx2() {
#ifdef MESHSMITH_AVX2_CLONES
  static const bool supported = __builtin_cpu_supports("avx2") != 0;
  return supported;
#else
  return false;
#endif
}

template <int C>
void forward_dispatch(const FactorArrays& f, const std::vector<int>& supernodes, const int* top_row, Row<C>* Y,
                      Row<C>* accumulator) {
#ifdef MESHSMITH_AVX2_CLONES
  if (use_avx2()) return forward_avx2<C>(f, supernodes, top_row, Y, accumulator);
#endif
  forward_default<C>(f, supernodes, top_row, Y, accumulator);
}

template <int C>
void backward_dispatch(const FactorArrays& f, const std::vector<int>& supernodes, Row<C>* Y) {
#ifdef MESHSMITH_AVX2_CLONES
  if (use_avx2()) return backward_avx2<C>(f, supernodes, Y);
#endif
  backward_default<C>(f, supernodes, Y);
}

}  // namespace

template <int C>
void SupernodalSolve::substitute(const Eigen::Ref<const Eigen::MatrixXd>& b, Eigen::Index first,
                                 Eigen::MatrixXd& x) const {
  using R = Row<C>;
  const int width = static_cast<int>(std::min<Eigen::Index>(C, b.cols() - first));
  const int* permutation = static_cast<const int*>(factor_->Perm);
  const FactorArrays f(*factor_);
  // Plain double storage (std::vector would not keep a vector type's reduced alignment).
  std::vector<double> Y_storage(static_cast<std::size_t>(n_) * C);
  for (Eigen::Index k = 0; k < n_; ++k) {
    const Eigen::Index source = permutation ? permutation[k] : k;
    for (int c = 0; c < width; ++c) Y_storage[k * C + c] = b(source, first + c);
  }
  std::vector<double> accumulator_storage[2];
  for (auto& accumulator : accumulator_storage) accumulator.assign(static_cast<std::size_t>(top_rows_) * C, 0.0);
  R* Y = reinterpret_cast<R*>(Y_storage.data());
  R* accumulators[2] = {reinterpret_cast<R*>(accumulator_storage[0].data()),
                        reinterpret_cast<R*>(accumulator_storage[1].data())};
  tbb::parallel_invoke([&] { forward_dispatch<C>(f, group_[0], top_row_.data(), Y, accumulators[0]); },
                       [&] { forward_dispatch<C>(f, group_[1], top_row_.data(), Y, accumulators[1]); });
  for (std::size_t k = 0; k < top_row_.size(); ++k) {
    const int top = top_row_[k];
    if (top >= 0) Y[k] += accumulators[0][top] + accumulators[1][top];
  }
  forward_dispatch<C>(f, top_, top_row_.data(), Y, nullptr);
  backward_dispatch<C>(f, top_, Y);
  tbb::parallel_invoke([&] { backward_dispatch<C>(f, group_[0], Y); },
                       [&] { backward_dispatch<C>(f, group_[1], Y); });
  for (Eigen::Index k = 0; k < n_; ++k) {
    const Eigen::Index target = permutation ? permutation[k] : k;
    for (int c = 0; c < width; ++c) x(target, first + c) = Y_storage[k * C + c];
  }
}

Eigen::MatrixXd SupernodalSolve::solve(const Eigen::Ref<const Eigen::MatrixXd>& b) const {
  if (b.rows() != n_) throw std::logic_error("SupernodalSolve: the right-hand side has the wrong number of rows");
  Eigen::MatrixXd x(n_, b.cols());
  // Columns four at a time (three padded with a zero column: one 4-wide register per row).
  for (Eigen::Index first = 0; first < b.cols(); first += 4) {
    switch (std::min<Eigen::Index>(4, b.cols() - first)) {
      case 1: substitute<1>(b, first, x); break;
      case 2: substitute<2>(b, first, x); break;
      default: substitute<4>(b, first, x); break;
    }
  }
  return x;
}

}  // namespace meshsmith::detail
