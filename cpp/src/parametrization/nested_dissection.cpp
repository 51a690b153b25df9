#include "nested_dissection.h"

#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace meshsmith::parametrization::detail {

namespace {

class Dissection {
 public:
  Dissection(const VertexRef& points, const AdjacencyView& graph, int leaf_size)
      : graph_(graph), leaf_size_(std::max(leaf_size, 1)) {
    const auto n = static_cast<std::size_t>(points.rows());
    items_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Item& item = items_[i];
      item.variable = static_cast<int>(i);
      for (int d = 0; d < 3; ++d) {
        // Non-finite coordinates read as 0: they make the order worse, never invalid.
        const double x = points(static_cast<Eigen::Index>(i), d);
        item.position[d] = std::isfinite(x) ? x : 0.0;
      }
    }
    // reach: the longest edge at the variable, so that only variables within reach of a
    // splitting plane need their neighbours looked at.
    for (std::size_t i = 0; i < n; ++i) {
      Item& item = items_[i];
      double longest = 0.0;
      for (int e = graph.starts[i]; e < graph.starts[i + 1]; ++e) {
        const Item& other = items_[graph.neighbours[e]];
        double squared = 0.0;
        for (int d = 0; d < 3; ++d) squared += (other.position[d] - item.position[d]) * (other.position[d] - item.position[d]);
        longest = std::max(longest, squared);
      }
      item.reach = std::sqrt(longest);
    }
    side_.assign(n, unassigned);
  }

  DissectionOrder run() && {
    DissectionOrder result;
    split(0, static_cast<int>(items_.size()), &result);
    result.order.resize(items_.size());
    for (std::size_t k = 0; k < items_.size(); ++k) result.order[k] = items_[k].variable;
    return result;
  }

 private:
  /// A variable and its position, kept together so that the passes over a range read memory in
  /// order.
  struct Item {
    double position[3];
    double reach;
    int variable;
  };
  /// side_ values; a variable with a neighbour on the other side also gets the `cut` bit.
  enum : unsigned char { unassigned = 0, low = 1, high = 2, separator = 3, cut = 4 };

  static constexpr int parallel_size = 4096;

  /// Orders the variables of items_[begin, end) in place: low side, high side, separator.
  /// `first_split`, if given, receives the sizes of the two sides.
  void split(int begin, int end, DissectionOrder* first_split = nullptr) {
    if (end - begin <= leaf_size_) return;
    int axis = 0;
    double plane = 0.0;  // low side: position[axis] ≤ plane, high side: ≥ plane
    const int middle = split_at_median(begin, end, axis, plane);
    for (int k = begin; k < middle; ++k) side_[items_[k].variable] = low;
    for (int k = middle; k < end; ++k) side_[items_[k].variable] = high;
    // The separator: the variables of one side with a neighbour on the other, from the side
    // where they are fewer. Only variables within reach of the plane can have one.
    int cut_count[3] = {0, 0, 0};
    for (int k = begin; k < end; ++k) {
      const Item& item = items_[k];
      if (std::abs(item.position[axis] - plane) > item.reach) continue;
      const int v = item.variable;
      const unsigned char own = side_[v];
      for (int e = graph_.starts[v]; e < graph_.starts[v + 1]; ++e) {
        if ((side_[graph_.neighbours[e]] & separator) == (separator ^ own)) {
          side_[v] = own | cut;
          ++cut_count[own];
          break;
        }
      }
    }
    const unsigned char cut_side = cut_count[low] <= cut_count[high] ? low : high;
    // Three-way partition in place into low, high, separator (each item read once; its mark
    // is cleared as it is read).
    int low_end = begin, next = begin, separator_begin = end;
    while (next < separator_begin) {
      unsigned char& mark = side_[items_[next].variable];
      const unsigned char where = mark == (cut_side | cut) ? separator : (mark & separator);
      mark = unassigned;
      if (where == low) {
        std::swap(items_[low_end++], items_[next++]);
      } else if (where == high) {
        ++next;
      } else {
        std::swap(items_[next], items_[--separator_begin]);
      }
    }
    // The two sides share no edge (a low–high edge would have put one end into the separator),
    // so they are ordered concurrently: each touches only its own slots and variables.
    const int high_end = separator_begin;
    if (first_split) {
      first_split->first_part = low_end - begin;
      first_split->second_part = high_end - low_end;
    }
    if (end - begin >= parallel_size) {
      tbb::parallel_invoke([&] { split(begin, low_end); }, [&] { split(low_end, high_end); });
    } else {
      split(begin, low_end);
      split(low_end, high_end);
    }
  }

  /// Splits items_[begin, end) about the median position along the widest axis of its bounding
  /// box and returns the split point: items before it are below the median, items from it on
  /// above. The median is estimated from a sample (one partition pass instead of a selection);
  /// when that leaves either side with under 1/8 of the items (many equal positions), the exact
  /// median is selected instead, ties broken by variable, so both sides are never empty.
  /// `axis` and `plane` receive the axis and a position along it between the two sides.
  int split_at_median(int begin, int end, int& axis, double& plane) {
    double lower[3], upper[3];
    for (int d = 0; d < 3; ++d) lower[d] = upper[d] = items_[begin].position[d];
    for (int k = begin + 1; k < end; ++k) {
      for (int d = 0; d < 3; ++d) {
        lower[d] = std::min(lower[d], items_[k].position[d]);
        upper[d] = std::max(upper[d], items_[k].position[d]);
      }
    }
    axis = 0;
    for (int d = 1; d < 3; ++d) {
      if (upper[d] - lower[d] > upper[axis] - lower[axis]) axis = d;
    }
    const int size = end - begin;
    const int sample_size = std::min(127, size / 8);
    if (sample_size >= 7) {
      double sample[127];
      for (int k = 0; k < sample_size; ++k) {
        sample[k] = items_[begin + static_cast<int>(static_cast<long long>(k) * size / sample_size)].position[axis];
      }
      std::nth_element(sample, sample + sample_size / 2, sample + sample_size);
      const double pivot = sample[sample_size / 2];
      const auto split = std::partition(items_.begin() + begin, items_.begin() + end,
                                        [axis, pivot](const Item& item) { return item.position[axis] < pivot; });
      const int middle = static_cast<int>(split - items_.begin());
      if (middle - begin >= size / 8 && end - middle >= size / 8) {
        plane = pivot;
        return middle;
      }
    }
    const int middle = begin + size / 2;
    std::nth_element(items_.begin() + begin, items_.begin() + middle, items_.begin() + end,
                     [axis](const Item& a, const Item& b) {
                       return a.position[axis] < b.position[axis] ||
                              (a.position[axis] == b.position[axis] && a.variable < b.variable);
                     });
    plane = items_[middle].position[axis];
    return middle;
  }

  AdjacencyView graph_;
  int leaf_size_;
  std::vector<Item> items_;
  std::vector<unsigned char> side_;
};

}  // namespace

DissectionOrder nested_dissection_order(const VertexRef& points, const AdjacencyView& graph, int leaf_size) {
  return Dissection(points, graph, leaf_size).run();
}

}  // namespace meshsmith::parametrization::detail
